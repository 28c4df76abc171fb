#!/usr/bin/env bash
# Sets up (Debian packages), builds, and runs the whole test suite with ctest.
set -euo pipefail
source "$(dirname "$0")/common.sh"
start=$(date +%s)
macsim_setup_and_build
status=0
(cd "$MACSIM_BUILD" && ctest --output-on-failure -j "$(nproc)" --timeout 300) || status=$?
# Participants killed by tests can leave Fast DDS shared-memory segments behind.
fastdds shm clean >/dev/null 2>&1 || true
echo "run_tests: finished in $(( $(date +%s) - start )) s with status $status"
exit $status
