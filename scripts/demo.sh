#!/usr/bin/env bash
# Installs what is missing, builds (host-release) and plans a grasp on the two-sensor
# example scene that ships with the project; prints the grasp and writes its pictures.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake --preset host-release >/dev/null
cmake --build --preset host-release --target forcegrasp
scene=${1:-examples/two-sensor-box/scene.json}
out=${2:-out/pictures}
./build/host-release/platform/host/cli/forcegrasp plan "$scene" --pictures "$out"
echo "pictures: $out/index.html"
