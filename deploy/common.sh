# Shared by the deploy scripts: set-up and build, from any working directory.
# shellcheck shell=bash
MACSIM_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MACSIM_BUILD="${MACSIM_BUILD:-$MACSIM_ROOT/build}"
# Keep every DDS participant of the demo and the tests on this machine (127.0.0.1 + shared memory).
export FASTRTPS_DEFAULT_PROFILES_FILE="${FASTRTPS_DEFAULT_PROFILES_FILE:-$MACSIM_ROOT/deploy/dds/localhost.xml}"

macsim_setup_and_build() {
  "$MACSIM_ROOT/deploy/install_deps.sh"
  cmake -S "$MACSIM_ROOT" -B "$MACSIM_BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo
  cmake --build "$MACSIM_BUILD" -j "$(nproc)"
}
