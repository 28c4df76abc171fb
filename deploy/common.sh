# Shared by the deploy scripts: set-up and build, from any working directory, with the time each
# phase took.
# shellcheck shell=bash
MACSIM_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MACSIM_BUILD="${MACSIM_BUILD:-$MACSIM_ROOT/build}"
# Keep every DDS participant of the demo and the tests on this machine (127.0.0.1 + shared memory).
export FASTRTPS_DEFAULT_PROFILES_FILE="${FASTRTPS_DEFAULT_PROFILES_FILE:-$MACSIM_ROOT/deploy/dds/localhost.xml}"

# Phases: `macsim_phase NAME` ends the running phase and starts NAME; `macsim_phases` ends the
# last one and prints each with its wall time.
MACSIM_PHASES=()
macsim_now() { date +%s%N; }
macsim_phase() {
  local now
  now=$(macsim_now)
  if [[ -n "${MACSIM_PHASE_NAME:-}" ]]; then
    MACSIM_PHASES+=("$MACSIM_PHASE_NAME $(( (now - MACSIM_PHASE_START) / 1000000 ))")
  fi
  MACSIM_PHASE_NAME="$1"
  MACSIM_PHASE_START=$now
}
macsim_phases() {
  macsim_phase ""
  local line name ms total=0
  echo "== phases (wall time):"
  for line in "${MACSIM_PHASES[@]}"; do
    read -r name ms <<< "$line"
    total=$((total + ms))
    printf '   %-10s %6d.%d s\n' "$name" $((ms / 1000)) $((ms % 1000 / 100))
  done
  printf '   %-10s %6d.%d s\n' "total" $((total / 1000)) $((total % 1000 / 100))
}

# `macsim_setup_and_build PARTS [TARGETS...]` installs what is missing, configures, and builds
# TARGETS (all when none are named). PARTS `demo`: the demo's packages only (install_deps.sh
# --demo) and, in a tree configured for the first time, MACSIM_DEMO_ONLY (no tests, benchmarks,
# Python module, web view or topic tools; a tree configured before keeps its parts). PARTS `all`:
# every package, every part. Compile flags do not depend on the parts, so the test command after
# the demo recompiles nothing the demo built. The same in two steps: `macsim_install PARTS`, then
# `macsim_build PARTS [TARGETS...]`.
macsim_setup_and_build() {
  macsim_install "$1"
  macsim_build "$@"
}
macsim_install() {
  macsim_phase install
  if [[ $1 == demo ]]; then
    "$MACSIM_ROOT/deploy/install_deps.sh" --demo
  else
    "$MACSIM_ROOT/deploy/install_deps.sh"
  fi
}
macsim_build() {
  local parts="$1"
  shift
  local configure=()
  if [[ $parts == demo ]]; then
    [[ -f "$MACSIM_BUILD/CMakeCache.txt" ]] || configure+=(-DMACSIM_DEMO_ONLY=ON)
  else
    configure+=(-DMACSIM_DEMO_ONLY=OFF)
  fi
  macsim_phase configure
  # Ninja (it keeps both cores busy across targets: a target's objects need not wait for the
  # libraries it links); a tree configured earlier keeps its generator.
  if [[ ! -f "$MACSIM_BUILD/CMakeCache.txt" ]] && command -v ninja > /dev/null; then
    configure+=(-G Ninja)
  fi
  cmake -S "$MACSIM_ROOT" -B "$MACSIM_BUILD" "${configure[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo
  macsim_phase build
  local targets=()
  for t in "$@"; do targets+=(--target "$t"); done
  cmake --build "$MACSIM_BUILD" -j "$(nproc)" "${targets[@]}"
}

# ctest starts the longest tests first when it knows their times: a fresh tree starts from the
# times committed in tests/ctest_costs.txt (ctest keeps its own from then on).
macsim_seed_test_costs() {
  local costs="$MACSIM_BUILD/Testing/Temporary/CTestCostData.txt"
  if [[ ! -f "$costs" && -f "$MACSIM_ROOT/tests/ctest_costs.txt" ]]; then
    mkdir -p "$(dirname "$costs")"
    cp "$MACSIM_ROOT/tests/ctest_costs.txt" "$costs"
  fi
}

# The end of each failed test's output (ctest's LastTest.log), printed again after the summary so
# that the tail of a run's log says why it failed.
macsim_failed_test_outputs() {
  local temporary="$MACSIM_BUILD/Testing/Temporary" name
  [[ -s "$temporary/LastTestsFailed.log" ]] || return 0
  while IFS=: read -r _ name; do
    echo "== the last lines of failed test $name:"
    awk -v test="$name" '
      /^[0-9]+\/[0-9]+ Test: / { sub(/^[0-9]+\/[0-9]+ Test: /, ""); inside = ($0 == test); n = 0; next }
      inside && /^<end of output>$/ { for (i = (n > 20 ? n - 20 : 0); i < n; ++i) print "   " line[i]; inside = 0; next }
      inside { line[n++] = $0 }' "$temporary/LastTest.log"
  done < "$temporary/LastTestsFailed.log"
}
