#!/usr/bin/env bash
# Builds the fuzzers (clang, libFuzzer, ASan + UBSan) in their own tree and runs each one for a
# while from the seeds and the committed corpus. Exit 1 if any target finds a crash, a leak or
# undefined behaviour (the input is kept in the tree's findings/ folder).
#   tests/fuzz/run_fuzzers.sh [SECONDS_PER_TARGET]     (default 20)
set -euo pipefail
case "${1:-}" in
  -h|--help) sed -n '2,5p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
esac
seconds="${1:-20}"
if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "run_fuzzers: SECONDS_PER_TARGET must be a positive whole number, got '$seconds'" >&2
  exit 2
fi
source "$(dirname "$0")/../../deploy/common.sh"
tree="$MACSIM_BUILD/fuzz"
CC=clang-14 CXX=clang++-14 cmake -S "$MACSIM_ROOT" -B "$tree" -DMACSIM_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$tree" -j "$(nproc)" --target fuzz_world_loader fuzz_requests fuzz_kurt_can \
  make_fuzz_seeds
"$tree/bin/make_fuzz_seeds" "$tree/seeds" >/dev/null
mkdir -p "$tree/findings"
export ASAN_OPTIONS="detect_leaks=1:new_delete_type_mismatch=0"
status=0
for target in world_loader requests kurt_can; do
  mkdir -p "$tree/corpus/$target"
  log="$tree/findings/$target.log"
  if "$tree/bin/fuzz_$target" -max_total_time="$seconds" -rss_limit_mb=4096 -print_final_stats=1 \
      -artifact_prefix="$tree/findings/$target-" "$tree/corpus/$target" "$tree/seeds/$target" \
      "$MACSIM_ROOT/tests/fuzz/corpus/$target" >"$log" 2>&1; then
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
