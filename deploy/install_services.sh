#!/usr/bin/env bash
# Renders the systemd units of deploy/systemd/ for this checkout (after a build) and checks
# them with systemd-analyze verify.
#   deploy/install_services.sh [DEST]   (default /etc/systemd/system; needs root there)
# then: systemctl daemon-reload && systemctl enable --now macsim   (or kurt_adapter)
set -euo pipefail
if [[ "${1:-}" == "--help" ]]; then
  echo "usage: $0 [DEST]   renders macsim, kurt_adapter and macsim-discovery units into DEST"
  exit 0
fi
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
dest=${1:-/etc/systemd/system}
mkdir -p "$dest"
for template in "$root"/deploy/systemd/*.service.in; do
  unit="$dest/$(basename "${template%.in}")"
  sed "s|@ROOT@|$root|g" "$template" > "$unit"
  systemd-analyze verify "$unit"
  echo "install_services: $unit"
done
echo "install_services: now run: systemctl daemon-reload && systemctl enable --now macsim"
