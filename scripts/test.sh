#!/usr/bin/env bash
# Installs what is missing, builds (host-release) and runs the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake --preset host-release >/dev/null
cmake --build --preset host-release -j "$(nproc)"
ctest --preset host-release -j "$(nproc)"
