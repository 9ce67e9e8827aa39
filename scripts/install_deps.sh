#!/usr/bin/env bash
# Installs the Debian packages forcegrasp builds and tests with (Debian 12), plus any
# named as arguments (the extra tools of scripts/fuzz.sh, cross.sh, wcet.sh), only
# those missing. Run as root (or with sudo available).
#   bash scripts/install_deps.sh [PACKAGE...]
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libccd-dev liburdfdom-dev
  nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  liblzf-dev  # tests only: the LZF decoder's oracle
  python3-dev pybind11-dev python3-pybind11 python3-numpy  # the Python module (platform/host/python)
  python3-pytest python3-open3d  # its tests; Open3D reads the example's clouds as a user's script would
  "$@"
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "forcegrasp: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
