#!/usr/bin/env bash
# Builds the fuzzers (clang, libFuzzer, ASan + UBSan) in their own tree and runs them side by
# side for a while each, from the seeds and the committed corpus. Exit 1 if any target finds a
# crash, a leak or undefined behaviour (the input is kept in the tree's findings/ folder).
#   tests/fuzz/run_fuzzers.sh [--build-only | --no-build] [SECONDS_PER_TARGET]   (default 20)
set -euo pipefail
build=1
run=1
seconds=20
for arg in "$@"; do
  case "$arg" in
    -h|--help) sed -n '2,5p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --build-only) run=0 ;;
    --no-build) build=0 ;;
    *) seconds="$arg" ;;
  esac
done
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "run_fuzzers: SECONDS_PER_TARGET must be a positive whole number, got '$seconds'" >&2
  exit 2
fi
source "$(dirname "$0")/../../deploy/common.sh"
tree="$MACSIM_BUILD/fuzz"
targets=(world_loader requests kurt_can snapshot session)
if [[ $build == 1 ]]; then
  generator=()
  if [[ ! -f "$tree/CMakeCache.txt" ]] && command -v ninja > /dev/null; then generator=(-G Ninja); fi
  CC=clang-14 CXX=clang++-14 cmake -S "$MACSIM_ROOT" -B "$tree" "${generator[@]}" -DMACSIM_FUZZ=ON \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  cmake --build "$tree" -j "$(nproc)" --target "${targets[@]/#/fuzz_}" make_fuzz_seeds
fi
[[ $run == 1 ]] || exit 0
"$tree/bin/make_fuzz_seeds" "$tree/seeds" >/dev/null
mkdir -p "$tree/findings"
export ASAN_OPTIONS="detect_leaks=1:new_delete_type_mismatch=0"
# The targets run at once, each for SECONDS of wall time on its share of the cores.
declare -A pids
for target in "${targets[@]}"; do
  mkdir -p "$tree/corpus/$target"
  committed=()  # the inputs that once found something, if the target has any
  [[ -d "$MACSIM_ROOT/tests/fuzz/corpus/$target" ]] && committed=("$MACSIM_ROOT/tests/fuzz/corpus/$target")
  # An input that runs for more than 10 s is a finding (a hang), not a wait to the end.
  "$tree/bin/fuzz_$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="$tree/findings/$target-" "$tree/corpus/$target" "$tree/seeds/$target" \
    "${committed[@]}" >"$tree/findings/$target.log" 2>&1 &
  pids[$target]=$!
done
status=0
for target in "${targets[@]}"; do
  log="$tree/findings/$target.log"
  if wait "${pids[$target]}"; then
    runs=$(grep -a 'stat::number_of_executed_units' "$log" | awk '{print $2}')
    rate=$(grep -a 'stat::average_exec_per_sec' "$log" | awk '{print $2}')
    cov=$(grep -a -o 'cov: [0-9]*' "$log" | tail -1 | awk '{print $2}')
    echo "fuzz_$target runs $runs execs"
    echo "fuzz_$target rate $rate execs/s"
    echo "fuzz_$target coverage ${cov:-0} edges"
  else
    status=1
    echo "fuzz_$target: FINDING (see $log):"
    grep -a -m5 'ERROR\|runtime error\|finding:\|what()' "$log" || tail -20 "$log"
  fi
done
exit $status
