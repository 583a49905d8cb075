#!/usr/bin/env bash
# Installs the Debian packages axonguide builds against. Idempotent: it only calls
# apt-get when something is missing, and runs `apt-get update` at most once.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libtbb-dev libgsl-dev libboost-graph-dev
  libgtest-dev librapidcheck-dev librandom123-dev
  nlohmann-json3-dev libcli11-dev libfmt-dev libssl-dev
  python3 python3-matplotlib
)
# Extra groups, opt-in: `install-deps.sh viewer` adds what the viewer tests need.
for group in "$@"; do
  case "$group" in
    viewer) packages+=(chromium python3-vtk9 nodejs npm) ;;
    *) echo "install-deps.sh: unknown group '$group' (known: viewer)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
