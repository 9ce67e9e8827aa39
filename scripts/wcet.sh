#!/usr/bin/env bash
# Worst-case timing (docs/worst-case-timing.md, issue 4 item 4). For the host and the
# cortex-m7 capacities (both compiled for this x86-64 host), in build/h-wcet and
# build/h-wcet-m7 (Release, plus -fstack-usage -fcallgraph-info=su for the stack graph
# and -g so callgrind can name source files; -g does not change the generated code):
#   1. time:         fg_wcet --runs N       -> median / max microseconds per stage, and
#                    tests/wcet/interleaved_ratio.py: the whole plan's worst case against
#                    the typical one with the cases run in interleaved rounds (fair on a
#                    shared machine) -> interleaved.md
#   2. instructions: per case, valgrind --tool=callgrind on fg_wcet --case NAME --once --ir
#                    (the planner's own stage timers count instructions, see
#                    tests/wcet/wcet_clock.hpp), and a profile run for callgrind_annotate
#   3. stack:        tests/wcet/stack_depth.py over fg_core's .ci files (static bound) and
#                    fg_wcet's painted-stack high-water per case (measured)
#   4. report:       tests/wcet/wcet_report.py -> build/h-wcet*/wcet/report.md
#
# usage: bash scripts/wcet.sh [--runs N] [--config host|cortex-m7|all] [--cases a,b]
#                             [--no-callgrind] [--no-profile] [--hash-cells N] [--rounds R]
# Installs what is missing (scripts/install_deps.sh, and valgrind). Takes about
# 15 minutes on a shared 2-core machine, most of it callgrind.
set -euo pipefail
cd "$(dirname "$0")/.."

runs=20
configs=all
cases=""
callgrind=1
profile=1
hash_cells_host=16384   # hash_collide is O(n^2): 98,304 colliding cells take minutes natively
rounds=4                # interleaved rounds (0: skip)
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs="$2"; shift 2 ;;
    --config) configs="$2"; shift 2 ;;
    --cases) cases="$2"; shift 2 ;;
    --no-callgrind) callgrind=0; shift ;;
    --no-profile) profile=0; shift ;;
    --hash-cells) hash_cells_host="$2"; shift 2 ;;
    --rounds) rounds="$2"; shift 2 ;;
    *) echo "usage: bash scripts/wcet.sh [--runs N] [--config host|cortex-m7|all] [--cases a,b] [--no-callgrind] [--no-profile] [--hash-cells N] [--rounds R]" >&2; exit 2 ;;
  esac
done

bash scripts/install_deps.sh
if ! dpkg-query -W -f='${Status}' valgrind 2>/dev/null | grep -q "install ok installed"; then
  echo "wcet: installing valgrind"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends valgrind >/dev/null
fi
command -v python3 >/dev/null || { echo "wcet: python3 is needed" >&2; exit 2; }

todo=()
case "$configs" in
  host) todo=(host) ;;
  cortex-m7) todo=(cortex-m7) ;;
  all) todo=(host cortex-m7) ;;
  *) echo "wcet: unknown --config $configs" >&2; exit 2 ;;
esac

reports=()
for limits in "${todo[@]}"; do
  if [ ! -f "config/$limits/fg_limits.h" ]; then
    echo "wcet: config/$limits/fg_limits.h is missing; skipping $limits" >&2
    continue
  fi
  dir=build/h-wcet
  [ "$limits" = host ] || dir=build/h-wcet-m7
  echo "== $limits ($dir)"
  # Only this build folder gets the stack-usage flags; Release as host-release.
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DFG_LIMITS="$limits" \
    -DFG_BUILD_BENCH=ON -DFG_BUILD_HOST_TOOLS=ON \
    -DCMAKE_CXX_FLAGS="-g -fstack-usage -fcallgraph-info=su" >/dev/null
  cmake --build "$dir" --target fg_wcet -j "$(nproc)"
  exe="$dir/tests/fg_wcet"
  out="$dir/wcet"
  rm -rf "$out"
  mkdir -p "$out/ir" "$out/cg"

  hash_args=()
  [ "$limits" = host ] && hash_args=(--hash-cells "$hash_cells_host")
  case_args=()
  [ -n "$cases" ] && case_args=(--case "$cases")
  all_cases=$("$exe" --list | awk '{print $1}')
  [ -n "$cases" ] && all_cases=$(echo "$cases" | tr ',' ' ')

  # 1. time
  echo "-- time ($runs runs per case; load average: $(cut -d' ' -f1-3 /proc/loadavg))"
  cut -d' ' -f1-3 /proc/loadavg >"$out/loadavg_before.txt"
  "$exe" --runs "$runs" "${case_args[@]}" "${hash_args[@]}" --json "$out/time.json" --markdown "$out/time.md"
  cut -d' ' -f1-3 /proc/loadavg >"$out/loadavg_after.txt"
  if [ "$rounds" -gt 0 ] && [ -z "$cases" ]; then
    echo "-- time, interleaved ($rounds rounds of every case)"
    python3 tests/wcet/interleaved_ratio.py "$exe" --rounds "$rounds" --json "$out/interleaved.json" >"$out/interleaved.md"
    tail -1 "$out/interleaved.md"
  fi

  # 2. instructions
  if [ "$callgrind" = 1 ]; then
    for c in $all_cases; do
      echo "-- callgrind: $c"
      prefix="$out/cg/$c.ir"
      valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file="$prefix" \
        "$exe" --case "$c" --ir "$prefix" "${hash_args[@]}" --json "$out/ir/$c.json" --quiet 2>"$out/cg/$c.ir.log" ||
        { echo "wcet: callgrind run of $c failed (see $out/cg/$c.ir.log)" >&2; exit 1; }
      rm -f "$prefix" "$prefix".*
      if [ "$profile" = 1 ]; then
        valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file="$out/cg/$c.profile" \
          "$exe" --case "$c" --profile "${hash_args[@]}" --quiet 2>"$out/cg/$c.profile.log" ||
          { echo "wcet: callgrind profile of $c failed" >&2; exit 1; }
        callgrind_annotate --inclusive=yes "$out/cg/$c.profile" >"$out/cg/$c.inclusive.txt" 2>/dev/null || true
        callgrind_annotate "$out/cg/$c.profile" >"$out/cg/$c.self.txt" 2>/dev/null || true
      fi
    done
  fi

  # 3. stack (static bound over the call graph; std::sort's introsort recursion is
  # bounded by 2 log2(kMaxCandidates) levels, GJK's support calls go through pointers)
  max_cand=$(python3 -c "import json;print(json.load(open('$out/time.json'))['capacities']['kMaxCandidates'])")
  depth=$(python3 -c "import math;print(2*int(math.log2($max_cand))+1)")
  python3 tests/wcet/stack_depth.py \
    --indirect gjk_intersect=aabb_support,point_set_support \
    --recursion-bound "__introsort_loop=$depth" \
    --json "$out/stack.json" \
    "$dir/core/CMakeFiles/fg_core.dir" "$dir/platform/CMakeFiles/fg_platform.dir" >"$out/stack.txt"
  head -12 "$out/stack.txt"

  # 4. report
  python3 tests/wcet/wcet_report.py "$out" >"$out/report.md"
  reports+=("$out/report.md")
  echo "-- report: $out/report.md"
done
echo "wcet: done: ${reports[*]}"
