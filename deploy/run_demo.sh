#!/usr/bin/env bash
# Sets up (Debian packages), builds, and runs the main job: the simulator on a world and the
# helloKurt controller as two DDS participants on this machine.
#   deploy/run_demo.sh [WORLD_FILE]   (default: worlds/DemoWorld_v1.xml)
set -euo pipefail
source "$(dirname "$0")/common.sh"
world="${1:-$MACSIM_ROOT/worlds/DemoWorld_v1.xml}"
domain="${MACSIM_DOMAIN:-42}"
macsim_setup_and_build
bin="$MACSIM_BUILD/bin"

echo "== starting the simulator: macsim --world $world --domain $domain"
"$bin/macsim" --world "$world" --domain "$domain" --status 1 &
sim=$!
trap 'kill -INT $sim 2>/dev/null || true; wait $sim 2>/dev/null || true' EXIT
sleep 1
echo "== starting the controller: helloKurt --domain $domain"
status=0
"$bin/helloKurt" --domain "$domain" || status=$?
sleep 1.5   # let the simulator print the robot standing at its goal
kill -INT $sim
wait $sim || true
trap - EXIT
echo "== demo finished: helloKurt exited with $status"
exit $status
