#!/usr/bin/env bash
# Cross-target builds (issue 4): installs what is missing, then
#  - aarch64: cross-builds everything (preset `aarch64`), runs the test suite but
#    its long scenario sets (tests/long_scenarios.txt) under qemu-aarch64, then checks
#    that the aarch64 program plans the example and 38 simulated scenes exactly as the
#    host program does (scripts/plans_alike.py);
#  - mips: 32-bit big-endian Linux (MIPS32r2): cross-builds everything (preset `mips`),
#    runs the same tests under qemu-mips, and checks that it plans those scenes
#    exactly as the host program, as for aarch64;
#  - cortex-m7: builds the bare-metal image fg_m7_image (the build fails on any heap,
#    exception or RTTI symbol and prints .text/.data/.bss and sizeof(fg::Planner)),
#    and runs it under qemu-system-arm (mps2-an500).
# Run as root (or with sudo available) on Debian 12.
set -euo pipefail
cd "$(dirname "$0")/.."
# Minutes since this script started, on each stage line.
stage() { echo "== [cross.sh $(( SECONDS / 60 )) min $(( SECONDS % 60 )) s] $*"; }
bash scripts/install_deps.sh \
  g++-aarch64-linux-gnu g++-mips-linux-gnu qemu-user googletest \
  gcc-arm-none-eabi binutils-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib \
  qemu-system-arm

stage "aarch64 preset (cross-built, tests under qemu-aarch64)"
cmake --preset aarch64 >/dev/null
cmake --build --preset aarch64 -j "$(nproc)"
# Every test but the long scenario sets (tests/long_scenarios.txt: under qemu they
# took most of CI's 90 min); the host runs them, and the plans below must match the
# host's bit for bit.
long=$(bash scripts/long_scenarios.sh)
ctest --preset aarch64 -j "$(nproc)" -E "$long"

stage "aarch64 and host plan alike"
# The host program from build/host-release (in CI already built by scripts/test.sh), or
# from the build folder FG_HOST_BUILD names.
host_build=${FG_HOST_BUILD:-build/host-release}
cmake -S . -B "$host_build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$host_build" -j "$(nproc)" --target forcegrasp
host_fg="$host_build"/platform/host/cli/forcegrasp
# The scenes each target must plan exactly as the host (scripts/plans_alike.py: every
# key, string and number bit for bit, timings aside): the example and 38 simulated
# two-sensor scenes, two of each kind, rendered and exported by the host's simulator
# (the wrist camera's pose as UR5 joints, so the plans carry joint solutions too).
# Exported rather than rendered on each target: the simulator's libm (sin, cos, exp of
# its noise and poses) may round differently there, which is a different scene, not a
# different plan.
scenes_dir=build/cross-scenes
rm -rf "$scenes_dir"
"$host_fg" sim --distribution classic --objects all --trials 38 --seed 5000 --export "$scenes_dir" --quiet >/dev/null
scenes=(examples/two-sensor-box/scene.json "$scenes_dir"/*/scene.json)
python3 scripts/plans_alike.py aarch64 "$host_fg" \
  "qemu-aarch64 -L /usr/aarch64-linux-gnu build/aarch64/platform/host/cli/forcegrasp" "${scenes[@]}"

stage "mips preset (32-bit big-endian, cross-built, tests under qemu-mips)"
cmake --preset mips >/dev/null
cmake --build --preset mips -j "$(nproc)"
# Byte order reaches the readers, the voxel grid, the flags read eight at a time and
# the hull's rasters, all tested by the short tests; the long scenario sets are left
# out as for aarch64 (the plans below must match the host's).
ctest --preset mips -j "$(nproc)" -E "$long"
stage "mips and host plan alike"
python3 scripts/plans_alike.py mips "$host_fg" \
  "qemu-mips -L /usr/mips-linux-gnu build/mips/platform/host/cli/forcegrasp" "${scenes[@]}"

stage "cortex-m7 preset (bare-metal image, run under qemu-system-arm -M mps2-an500)"
cmake --preset cortex-m7 >/dev/null
cmake --build --preset cortex-m7 -j "$(nproc)"
ctest --preset cortex-m7
