#!/usr/bin/env bash
# Sets up (Debian packages), builds, and runs the whole test suite with ctest.
set -euo pipefail
source "$(dirname "$0")/common.sh"
start=$(date +%s)
macsim_setup_and_build
macsim_phase test
status=0
(cd "$MACSIM_BUILD" && ctest --output-on-failure -j "$(nproc)" --timeout 300) || status=$?
# The fuzzers, a short run each from the seeds and the committed corpus (tests/fuzz/README.md).
macsim_phase fuzz
"$MACSIM_ROOT/tests/fuzz/run_fuzzers.sh" "${MACSIM_FUZZ_SECONDS:-20}" || status=$?
# Participants killed by tests leave Fast DDS shared-memory files behind.
"$MACSIM_BUILD/bin/macsim_shm_clean" --min-age 0 || true
macsim_phases
echo "run_tests: finished in $(( $(date +%s) - start )) s with status $status"
exit $status
