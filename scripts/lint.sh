#!/usr/bin/env bash
# The style and static checks CI runs (.ci/run): clang-format over every source, and
# clang-tidy (.clang-tidy files) over the non-test sources the host build compiles,
# through its compile_commands.json. Exits non-zero on any finding.
# usage: scripts/lint.sh [BUILD_DIR]   (default build/host-release, configured)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/host-release}
bash scripts/install_deps.sh clang-format clang-tidy
[[ -f "$build/compile_commands.json" ]] || { echo "lint: no $build/compile_commands.json (configure first)" >&2; exit 2; }

echo "lint: clang-format"
git ls-files '*.cpp' '*.hpp' '*.h' '*.c' | xargs clang-format --dry-run -Werror

echo "lint: clang-tidy"
mapfile -t files < <(python3 - "$build/compile_commands.json" "$PWD" <<'PY'
import json, os, sys
root = sys.argv[2] + "/"
seen = set()
for e in json.load(open(sys.argv[1])):
    f = os.path.normpath(os.path.join(e["directory"], e["file"]))
    rel = f[len(root):] if f.startswith(root) else None
    if rel and not rel.startswith(("tests/", "fuzz/", "build/")) and rel not in seen:
        seen.add(rel)
        print(rel)
PY
)
printf '%s\n' "${files[@]}" | xargs -P "$(nproc)" -n 4 clang-tidy -p "$build" --quiet 2>/dev/null
echo "lint: ${#files[@]} sources clean"
