#!/usr/bin/env bash
# Installs the Debian 12 packages MACSim-DDS builds and runs with.
#   deploy/install_deps.sh          everything: the build, the tests, the benchmarks, the tools
#   deploy/install_deps.sh --demo   only what the simulator and the controllers build and run
#                                   with (the demo command; its tree is configured with
#                                   MACSIM_DEMO_ONLY, and the test command installs the rest)
# Idempotent: when every package is present it does nothing and needs no network;
# it runs `apt-get update` only when something must be installed.
set -euo pipefail
demo=0
case "${1:-}" in
  "") ;;
  --demo) demo=1 ;;
  -h|--help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "install_deps.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
esac

# What the libraries, macsim and the example controllers need (MACSIM_DEMO_ONLY=ON).
DEMO_PACKAGES=(
  # toolchain; Ninja, ccache and the mold linker make the build faster (tests/README.md); any
  # Python 3 runs the generator of the supervisor's operations
  cmake g++ make pkg-config ninja-build ccache mold python3
  # DDS: Fast DDS 2.9 runtime, CDR, IDL generator (pulls a headless JRE)
  libfastrtps-dev libfastcdr-dev fastddsgen
  # physics, XML, math; OpenCV's four modules, not libopencv-dev (which brings every module, with
  # VTK, Qt, GDAL and FFmpeg: 146 more packages; deploy/cmake/macsimOpenCV.cmake)
  libode-dev libtinyxml2-dev libeigen3-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-ml-dev
  # the state hash (XXH3)
  libxxhash-dev
  # offscreen rendering on the CPU: EGL + OpenGL through Mesa's llvmpipe
  libegl-dev libopengl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  # the interactive window (freeglut on X)
  libglut-dev
  # every program's options (CLI11) and leveled logging (spdlog)
  libcli11-dev libspdlog-dev
)

# The rest: the tests, the benchmarks, the Python module, the topic tools and the web view.
PACKAGES=(
  # Fast DDS's command-line tools (the discovery server)
  fastdds-tools
  # topic tools: YAML for echo/pub and bag metadata, sqlite3 for rosbag2 bags (+ its CLI)
  libyaml-cpp-dev libsqlite3-dev sqlite3
  # Python (its sqlite3 module) reads the bags in a test; the `macsim` Python module (pybind11,
  # numpy arrays) and its pytest suite, for Debian's /usr/bin/python3
  python3-dev pybind11-dev python3-numpy python3-pytest
  # a virtual X server for the interactive window's tests
  xvfb xauth
  # the fuzzers' stage of the tests: clang with libFuzzer and the sanitizers' runtimes
  clang-14 libclang-rt-14-dev
  # tests and benchmarks; Cyclone DDS (C, with idlc) for the interoperability test; stress-ng
  # loads the cores while the suite runs, to find tests that depend on the machine's load
  stress-ng libgtest-dev libgmock-dev libbenchmark-dev cyclonedds-dev cyclonedds-tools
  # bench_peers only: MuJoCo 2.2.2 on the same scenes (its CMake config lists qhull's headers)
  libmujoco-dev libqhull-dev
  # profiles for bench/README.md
  linux-perf
  # bench_planning only: clingo (ASP) beside the project's own planner on the same problems
  gringo
  # several hosts in tests: network namespaces joined by a veth pair; DDS Security certificates
  iproute2 openssl
  # packet loss on those links (nftables' random drop; kernels without netem have it too)
  nftables
  # checking the service units (systemd-analyze verify)
  systemd
  # Debian packages (cpack -G DEB: dependencies by dpkg-shlibdeps, which needs file)
  dpkg-dev file
  # affordance trials as Slurm job arrays (deploy/slurm/): the slurm test's one-node cluster,
  # which the test starts itself with a key, socket, ports and config of its own (beside any
  # munged or slurmd the packages' units may start; it uses neither /etc/munge nor /etc/slurm)
  slurm-wlm munge
  # macsim_web: HTTP + WebSocket (websocketpp on standalone asio), JSON; its browser test drives
  # Debian's Chromium through chromedriver
  libwebsocketpp-dev libasio-dev nlohmann-json3-dev chromium chromium-driver
  # the browser test's WebDriver client (selenium) and its screenshot decoding (PIL)
  python3-selenium python3-pil
)
if [[ $demo == 1 ]]; then PACKAGES=("${DEMO_PACKAGES[@]}")
else PACKAGES=("${DEMO_PACKAGES[@]}" "${PACKAGES[@]}"); fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# The page's three.js comes from the npm registry into the build tree (npm ci); Node.js and npm
# are Debian's when the machine has none.
if [[ $demo == 0 ]] && ! command -v npm > /dev/null; then missing+=(npm); fi

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "install_deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
