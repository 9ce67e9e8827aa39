#!/usr/bin/env bash
# The embedded/host boundary in the sources (docs/architecture.md):
#  - embedded-side code includes no allocating or throwing standard header and no
#    host-side header (the CMake link check, fg_check_boundary, covers the targets);
#  - the HAL interfaces depend on the core's small types only, never on the planner.
# Prints every offending line and exits 1 when there is one.
set -u
cd "$(dirname "$0")/.."
embedded=(core robot hal/include firmware_api platform/include platform/targets)
host_std='<(vector|string|map|unordered_map|set|list|deque|memory|iostream|fstream|sstream|functional|thread|mutex|exception|stdexcept|regex|filesystem)>'
host_paths='"(io|cli|urdf|sim)/|nlohmann|CLI/|urdf_|tinyxml|console_bridge'
status=0
if git grep -nE "^\s*#\s*include\s*($host_std|.*($host_paths))" -- "${embedded[@]}"; then
  echo "check_layout: embedded-side code above includes host-only headers" >&2
  status=1
fi
hal_allowed='"fg/core/(status|pinhole|types)\.hpp"'
if git grep -nE '^\s*#\s*include\s*"' -- hal/include | grep -vE "$hal_allowed"; then
  echo "check_layout: a HAL interface above includes more than the core's small types" >&2
  status=1
fi
exit $status
