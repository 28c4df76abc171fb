#!/usr/bin/env bash
# Sets up (Debian packages), builds, and runs the whole test suite: ctest, then the fuzzers.
#   deploy/run_tests.sh            everything (the gate: CI runs exactly this)
#   deploy/run_tests.sh --quick    builds the unit tests only and runs those that start no
#                                  process (ctest label `quick`): the inner loop
#   deploy/run_tests.sh [--quick] -- CTEST_ARGS   e.g. -- -R Runner, -- --schedule-random
set -euo pipefail
quick=0
ctest_args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --quick) quick=1 ;;
    --) shift; ctest_args=("$@"); break ;;
    -h|--help) sed -n '2,6p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "run_tests.sh: unknown argument '$1' (ctest's go after --; see --help)" >&2; exit 2 ;;
  esac
  shift
done
source "$(dirname "$0")/common.sh"
start=$(date +%s)
status=0
ctest_status=0
# More tests at once than there are cores, since most of them wait; those that keep a core busy
# each hold one of the machine's cores (ctest's resource `cores`; tests/CMakeLists.txt).
cores=$(nproc)
jobs=$(( 2 * cores + 1 ))
resources="$MACSIM_BUILD/ctest_resources.json"
if [[ $quick == 1 ]]; then
  macsim_setup_and_build all quick_tests
  macsim_phase test
  (cd "$MACSIM_BUILD" && ctest --output-on-failure -j "$jobs" -L quick "${ctest_args[@]}") ||
    ctest_status=$?
  status=$ctest_status
else
  macsim_install all
  # The fuzzers' clang tree builds at the lowest priority from here on, on the time the build
  # and then the tests leave the cores idle (a code generator or a link holding one core; tests
  # waiting for discovery, for children, for real time).
  mkdir -p "$MACSIM_BUILD"
  fuzz_log="$MACSIM_BUILD/fuzz_build.log"
  # In a session of its own, so that a failed main build ends it with all its compilers. Where
  # the kernel groups each session's processes (autogroup), nice counts only inside a group:
  # the group itself is made nice, else the two builds would share the cores half and half.
  setsid nice -n 19 "$MACSIM_ROOT/tests/fuzz/run_fuzzers.sh" --build-only > "$fuzz_log" 2>&1 &
  fuzz_build=$!
  if [[ -w /proc/$fuzz_build/autogroup ]]; then echo 19 > "/proc/$fuzz_build/autogroup" || true; fi
  trap 'kill -- -"$fuzz_build" 2> /dev/null || true' EXIT
  macsim_build all
  macsim_seed_test_costs
  printf '{"version": {"major": 1, "minor": 0}, "local": [{"cores": [{"id": "0", "slots": %d}]}]}\n' \
    "$cores" > "$resources"
  macsim_phase test
  (cd "$MACSIM_BUILD" && ctest --output-on-failure -j "$jobs" --resource-spec-file "$resources" \
     --timeout 300 "${ctest_args[@]}") || ctest_status=$?
  status=$ctest_status
  # The fuzzers, a short run each from the seeds and the committed corpus (tests/fuzz/README.md):
  # the five side by side for 30 s, about 12 s of a core each.
  macsim_phase fuzz
  if wait "$fuzz_build"; then
    "$MACSIM_ROOT/tests/fuzz/run_fuzzers.sh" --no-build "${MACSIM_FUZZ_SECONDS:-30}" ||
      status=$?
  else
    echo "run_tests: the fuzzers' tree did not build:"
    tail -30 "$fuzz_log"
    status=1
  fi
fi
# Participants killed by tests leave Fast DDS shared-memory files behind.
[[ -x "$MACSIM_BUILD/bin/macsim_shm_clean" ]] && "$MACSIM_BUILD/bin/macsim_shm_clean" --min-age 0 || true
# Why a test failed, near the end of the log (its whole output is above, in ctest's order).
if [[ $ctest_status != 0 ]]; then macsim_failed_test_outputs; fi
macsim_phases
echo "run_tests: finished in $(( $(date +%s) - start )) s with status $status"
exit $status
