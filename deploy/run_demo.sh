#!/usr/bin/env bash
# Sets up (Debian packages), builds, and runs the main job: the MACS final demonstrator. macsim
# runs the demonstrator world and kurt_demo plays it from the robot's own sensing over DDS:
# finds the cans, lifts one with the crane's magnet, drops it on the door's switch, drives
# through the opened door. One overview picture per scene is written.
#   deploy/run_demo.sh [--fast] [--seed N] [WORLD_FILE]
#     --fast     lock-step, as fast as the machine allows (default: real time)
#     --seed N   the world's layout varied by seed N (cans, colours, the robot's start)
#     WORLD_FILE default: worlds/DemoWorld_v1.xml
set -euo pipefail
source "$(dirname "$0")/common.sh"
fast=0
seed=""
world="$MACSIM_ROOT/worlds/DemoWorld_v1.xml"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --fast) fast=1 ;;
    --seed) [[ $# -ge 2 && "$2" =~ ^[0-9]+$ ]] || { echo "run_demo.sh: --seed takes a number" >&2; exit 2; }
            seed="$2"; shift ;;
    -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "run_demo.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) world="$1" ;;
  esac
  shift
done
domain="${MACSIM_DOMAIN:-42}"
# Only what the demo runs; the test command builds the rest in the same tree.
macsim_setup_and_build demo macsim kurt_demo
macsim_phase run
bin="$MACSIM_BUILD/bin"
pictures="$MACSIM_BUILD/demo_pictures"
rm -rf "$pictures"
mkdir -p "$pictures"

sim_args=(--world "$world" --domain "$domain" --pictures "$pictures")
demo_args=(--domain "$domain" --pictures)
[[ -n "$seed" ]] && sim_args+=(--seed "$seed")
if [[ $fast == 1 ]]; then
  sim_args+=(--lockstep)
  demo_args+=(--lockstep)
else
  sim_args+=(--status 10)
fi
echo "== starting the simulator: macsim ${sim_args[*]}"
"$bin/macsim" "${sim_args[@]}" > >(grep --line-buffered -v '^  rt/') 2>&1 &
sim=$!
trap 'kill -INT $sim 2>/dev/null || true; wait $sim 2>/dev/null || true' EXIT
sleep 1
echo "== starting the controller: kurt_demo ${demo_args[*]}"
start=$(date +%s%N)
status=0
"$bin/kurt_demo" "${demo_args[@]}" || status=$?
wall_ms=$((($(date +%s%N) - start) / 1000000))
kill -INT $sim 2>/dev/null || true
wait $sim 2>/dev/null || true
trap - EXIT
count=$(find "$pictures" -name '*.png' | wc -l)
echo "== pictures ($count) in $pictures:"
find "$pictures" -name '*.png' | sort | sed 's/^/   /'
printf '== demo %s: kurt_demo exited with %d after %d.%d s of wall time (its last line gives the robot time)\n' \
  "$([[ $status == 0 ]] && echo SUCCEEDED || echo FAILED)" "$status" $((wall_ms / 1000)) $((wall_ms % 1000 / 100))
macsim_phases
exit $status
