#!/usr/bin/env bash
# A Fast DDS discovery server for MACSim-DDS participants on several hosts (server id 0, UDP
# port 11811 by default). Start it on one host, then start every program with
#   ROS_DISCOVERY_SERVER=ADDRESS:PORT
# and a network profile (deploy/dds/network.xml): participants then find each other through the
# server instead of multicast (networks without multicast, or many hosts).
#   deploy/run_discovery_server.sh ADDRESS [PORT]
set -euo pipefail
if [[ $# -lt 1 || "$1" == "--help" ]]; then
  echo "usage: $0 ADDRESS [PORT]   (the address of this host the others reach; port 11811)"
  [[ $# -ge 1 ]] && exit 0 || exit 2
fi
# The server binary itself (not the `fastdds discovery` wrapper), so that stopping this script's
# process stops the server.
exec fast-discovery-server -i 0 -l "$1" -p "${2:-11811}"
