#!/usr/bin/env bash
# Fuzzes the PCD, PLY and scene readers, the core planner and firmware C API call
# sequences with libFuzzer
# (fuzz/README.md): installs what is missing (the project's packages, plus clang 14 and
# its fuzzer runtime, needed by this script only), builds the `fuzz` preset (clang,
# ASan + UBSan), runs every target for SECONDS_PER_TARGET seconds (default 60; up to
# nproc targets at a time, FUZZ_JOBS overrides) on the committed seeds of
# fuzz/corpus/<target>/ and fuzz/regressions/<target>/ plus copies of the real clouds
# and scenes of ../shared/data, and prints each target's executions.
#
#   bash scripts/fuzz.sh [SECONDS_PER_TARGET]
#
# Exits non-zero when a target found something (crash, sanitizer report, leak, timeout,
# out-of-memory, heap use in the core): the input libFuzzer saved is moved to
# fuzz/regressions/<target>/, where the normal build's replay test
# (ctest -R fuzz.replay.<target>) runs it from then on. FUZZ_KEEP=1 keeps the work
# folder (logs and the corpus grown by the run).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
secs=${1:-60}
if ! [[ "$secs" =~ ^[0-9]+$ ]] || [ "$secs" -lt 1 ]; then
  echo "usage: $0 [SECONDS_PER_TARGET]   (a positive integer, default 60)" >&2
  exit 2
fi
t_start=$(date +%s)

# ---- packages --------------------------------------------------------------------------
bash scripts/install_deps.sh clang libclang-rt-14-dev  # clang and its fuzzer runtime: this script only

# ---- build -----------------------------------------------------------------------------
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)"
bin=$root/build/fuzz/fuzz

# ---- corpora ---------------------------------------------------------------------------
targets=(pcd ply scene plan api)
declare -A dict=([pcd]=pcd.dict [ply]=ply.dict [scene]=json.dict)
work=$(mktemp -d "${TMPDIR:-/tmp}/fg-fuzz.XXXXXX")
cleanup() { if [ "${FUZZ_KEEP:-0}" = 1 ]; then echo "fuzz: work folder kept: $work"; else rm -rf "$work"; fi; }
trap cleanup EXIT
for t in "${targets[@]}"; do mkdir -p "$work/$t/new" "$work/$t/seeds" "$work/$t/artifacts"; done
shared=$root/../shared/data
if [ -d "$shared/clouds" ]; then
  # The real clouds (a few MB each: copied here, never committed under fuzz/).
  while IFS= read -r -d '' f; do
    rel=${f#"$shared/clouds/"}
    cp "$f" "$work/pcd/seeds/${rel//\//_}"
  done < <(find "$shared/clouds" -type f -name '*.pcd' -print0)
  while IFS= read -r -d '' f; do
    rel=${f#"$shared/clouds/"}
    cp "$f" "$work/ply/seeds/${rel//\//_}"
  done < <(find "$shared/clouds" -type f -name '*.ply' -print0)
else
  echo "fuzz: $shared/clouds not found: fuzzing on the committed seeds only" >&2
fi
# The real scene manifests (shared data and the example), small but kept in one place.
while IFS= read -r -d '' f; do
  rel=${f#"$shared/"}
  rel=${rel#"$root/"}
  cp "$f" "$work/scene/seeds/${rel//\//_}"
done < <(find "$shared/scenes" "$root/examples" -type f -name '*.json' ! -name 'truth.json' -print0 2>/dev/null)

# Input size cap of the fuzzing loops. The real clouds (up to 2.5 MB) run whole once in
# the pass below; in the loops libFuzzer truncates them to the cap, keeping their headers
# and the start of their data: full-size inputs would cut the executions a hundredfold.
declare -A max_len=([pcd]=65536 [ply]=65536 [scene]=16384 [plan]=16384 [api]=16384)

# ---- run -------------------------------------------------------------------------------
jobs=${FUZZ_JOBS:-$(nproc)}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# The real files, each run whole once (libFuzzer's file mode).
real_failed=0
for t in "${targets[@]}"; do
  files=("$work/$t/seeds"/*)
  [ -e "${files[0]}" ] || continue
  if "$bin/${t}_fuzz" -timeout=120 -rss_limit_mb=3072 -artifact_prefix="$work/$t/real-" "${files[@]}" \
       >"$work/$t/real.log" 2>&1; then
    echo "fuzz: $t: ${#files[@]} real files run whole: ok"
  else
    echo "fuzz: $t: a real file of ../shared/data fails (it stays there, not copied to fuzz/regressions):"
    grep -E '^Running: |==[0-9]+==ERROR|runtime error|==fg-|deadly signal' "$work/$t/real.log" | tail -n 5 || true
    tail -n 30 "$work/$t/real.log"
    real_failed=1
  fi
done
echo "fuzz: ${#targets[@]} targets x ${secs} s, $jobs at a time (work folder $work)"
run_target() {
  local t=$1 rc=0
  local dirs=("$work/$t/new" "$work/$t/seeds" "$root/fuzz/corpus/$t")
  [ -d "$root/fuzz/regressions/$t" ] && dirs+=("$root/fuzz/regressions/$t")
  local opts=(-max_total_time="$secs" -print_final_stats=1 -timeout=30 -rss_limit_mb=3072
              -max_len="${max_len[$t]}" -artifact_prefix="$work/$t/artifacts/")
  [ -n "${dict[$t]:-}" ] && opts+=(-dict="$root/fuzz/${dict[$t]}")
  "$bin/${t}_fuzz" "${opts[@]}" "${dirs[@]}" >"$work/$t/log" 2>&1 || rc=$?
  echo "$rc" >"$work/$t/rc"
}
running=0
for t in "${targets[@]}"; do
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
  echo "fuzz: $t ..."
  run_target "$t" &
  running=$((running + 1))
done
wait || true

# ---- report ----------------------------------------------------------------------------
final_stat() { grep -m1 "^stat::$2:" "$work/$1/log" | awk '{print $2}' || true; }
failed=0
printf '\n%-6s %12s %10s %10s %8s  %s\n' target executions exec/s new_units rss_mb result
for t in "${targets[@]}"; do
  rc=$(cat "$work/$t/rc" 2>/dev/null || echo 1)
  result=ok
  if [ "$rc" != 0 ]; then
    result="FINDING (libFuzzer exit $rc)"
    failed=1
  fi
  printf '%-6s %12s %10s %10s %8s  %s\n' "$t" "$(final_stat "$t" number_of_executed_units)" \
    "$(final_stat "$t" average_exec_per_sec)" "$(final_stat "$t" new_units_added)" "$(final_stat "$t" peak_rss_mb)" "$result"
done
for t in "${targets[@]}"; do
  rc=$(cat "$work/$t/rc" 2>/dev/null || echo 1)
  kept=()
  for a in "$work/$t/artifacts"/crash-* "$work/$t/artifacts"/leak-* "$work/$t/artifacts"/timeout-* \
           "$work/$t/artifacts"/oom-*; do
    [ -e "$a" ] || continue
    mkdir -p "$root/fuzz/regressions/$t"
    mv "$a" "$root/fuzz/regressions/$t/"
    kept+=("fuzz/regressions/$t/$(basename "$a")")
  done
  [ "$rc" = 0 ] && [ ${#kept[@]} -eq 0 ] && continue
  echo
  echo "==== $t: finding (libFuzzer exit $rc)"
  # The first lines of the report: sanitizer, libFuzzer or fuzz-check banner onwards.
  first=$(grep -n -m1 -E '==[0-9]+==ERROR|runtime error|==fg-|ERROR: libFuzzer|Direct leak|deadly signal' \
            "$work/$t/log" | cut -d: -f1 || true)
  tail -n +"${first:-1}" "$work/$t/log" | awk '{ print } /^SUMMARY: / || NR >= 40 { exit }' || true
  if [ ${#kept[@]} -gt 0 ]; then
    for k in "${kept[@]}"; do echo "input kept: $k  (replay: $bin/${t}_fuzz $k)"; done
  else
    echo "no input saved; the log ends:"
    tail -n 20 "$work/$t/log"
  fi
done
echo
echo "fuzz: done in $(( $(date +%s) - t_start )) s"
[ "$real_failed" = 0 ] || failed=1
if [ "$failed" != 0 ]; then
  echo "fuzz: FINDINGS above; their inputs are in fuzz/regressions/ (ctest -R fuzz.replay replays them)"
  exit 1
fi
