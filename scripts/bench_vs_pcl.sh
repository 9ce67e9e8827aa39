#!/usr/bin/env bash
# forcegrasp against the PCL reference build (../shared/anchors/pcl_reference), side by
# side on the same machine and the same scenes: the project's speed figure is this ratio,
# never an absolute time from another day.
#   bash scripts/bench_vs_pcl.sh [--runs R] [--scenes N] [--forcegrasp PATH] [--out DIR]
# Installs PCL if missing (as root), builds the PCL reference (Release) in
# build/pcl-reference and, unless --forcegrasp is given, forcegrasp in build/host-release;
# makes N simulated scenes (fixed seed, a balanced mix of kinds) in the three PCD encodings
# under DIR (default build/bench-vs-pcl), then times both programs on them with
# scripts/bench_vs_pcl.py and prints markdown tables (also written to DIR/report.md).
# Exits non-zero on failures only (a build, a scene, a program's exit code), never on slow figures.
set -euo pipefail

runs=10
scenes=10
fg_bin=""
out=""
seed=1000  # fixed: the same scenes on every machine and every day
encodings=(binary binary_compressed ascii)

# The comment at the top of this file is the help; exit code $1 (0 for --help, 2 for a bad argument).
usage() { sed -n '2,11s/^# \{0,1\}//p' "$0" >&2; exit "$1"; }
while [ $# -gt 0 ]; do
  case $1 in
    --runs) runs=${2:?--runs needs a value}; shift 2 ;;
    --scenes) scenes=${2:?--scenes needs a value}; shift 2 ;;
    --forcegrasp) fg_bin=${2:?--forcegrasp needs a path}; shift 2 ;;
    --out) out=${2:?--out needs a directory}; shift 2 ;;
    -h | --help) usage 0 ;;
    *) echo "bench_vs_pcl: unknown argument '$1'" >&2; usage 2 ;;
  esac
done
[[ $runs =~ ^[1-9][0-9]*$ && $scenes =~ ^[1-9][0-9]*$ ]] || { echo "bench_vs_pcl: --runs and --scenes take positive integers" >&2; exit 2; }
# Paths given are the caller's; everything else is relative to the repo root.
[ -z "$fg_bin" ] || fg_bin=$(realpath -m "$fg_bin")
[ -z "$out" ] || out=$(realpath -m "$out")
cd "$(dirname "$0")/.."
root=$PWD
out=${out:-build/bench-vs-pcl}

# Elapsed time since the script started, on each stage line: the PCL build is the long one.
stage() { echo "== [bench_vs_pcl $((SECONDS / 60)) min $((SECONDS % 60)) s] $*" >&2; }

# Runs a command with its output in $out/logs/NAME.log, shown only when it fails: the
# tables stay readable, and a failed build still says why.
logged() {
  local log=$out/logs/$1.log
  shift
  "$@" >"$log" 2>&1 || {
    tail -n 30 "$log" >&2
    echo "bench_vs_pcl: failed: $* (whole log: $log)" >&2
    exit 1
  }
}

# PCL for the reference build; GNU time for each program's own peak RSS.
install_pcl() {
  dpkg -s libpcl-dev time >/dev/null 2>&1 && return 0
  local cmd="apt-get update && apt-get install -y libpcl-dev time"
  if [ "$(id -u)" -ne 0 ]; then
    echo "bench_vs_pcl: PCL is missing; as root run: $cmd" >&2
    exit 2
  fi
  stage "installing libpcl-dev and time"
  export DEBIAN_FRONTEND=noninteractive
  logged apt-get-update apt-get update
  logged apt-get-install apt-get install -y libpcl-dev time
}

# Configures once; later runs only call cmake --build, which is a no-op when up to date.
build_pcl_reference() {
  local src=$root/../shared/anchors/pcl_reference dir=build/pcl-reference start=$SECONDS
  [ -f "$src/CMakeLists.txt" ] || { echo "bench_vs_pcl: no PCL reference at $src" >&2; exit 1; }
  if [ ! -f "$dir/CMakeCache.txt" ]; then
    logged pcl-configure cmake -S "$src" -B "$dir" -DCMAKE_BUILD_TYPE=Release
  fi
  logged pcl-build cmake --build "$dir" -j "$(nproc)" --target pcl_forcegrasp
  stage "PCL reference built in $((SECONDS - start)) s"
}

# fg_make_scenes is a host tool of hal/sim; its folder is found rather than assumed.
find_make_scenes() {
  find build/host-release -type f -name fg_make_scenes -perm -u+x -print -quit 2>/dev/null || true
}

# forcegrasp and the scene generator from build/host-release. With --forcegrasp PATH the
# program under test is that one, and only a missing scene generator is built.
build_forcegrasp() {
  local targets=(forcegrasp fg_make_scenes)
  if [ -n "$fg_bin" ]; then
    [ -x "$fg_bin" ] || { echo "bench_vs_pcl: --forcegrasp $fg_bin is not an executable" >&2; exit 2; }
    [ -n "$(find_make_scenes)" ] && return 0
    targets=(fg_make_scenes)
  fi
  logged forcegrasp-configure cmake --preset host-release
  logged forcegrasp-build cmake --build build/host-release -j "$(nproc)" --target "${targets[@]}"
  [ -n "$fg_bin" ] || fg_bin=build/host-release/platform/host/cli/forcegrasp
}

# The same seeds in every encoding, so the encodings differ only in how the clouds are read.
make_scenes() {
  local make_scenes enc
  make_scenes=$(find_make_scenes)
  [ -n "$make_scenes" ] || { echo "bench_vs_pcl: fg_make_scenes not found under build/host-release" >&2; exit 1; }
  for enc in "${encodings[@]}"; do
    rm -rf "${out:?}/$enc"
    logged "scenes-$enc" "$make_scenes" "$out/$enc" --count "$scenes" --seed "$seed" --encoding "$enc" \
      --distribution classic
  done
  check_cloud_size
}

# A 640x480 binary cloud of x y z floats is 640*480*12 bytes (~3.7 MB) plus its header:
# anything much smaller means the generator wrote something else than what is timed here.
check_cloud_size() {
  local pcd bytes
  pcd=$(find "$out/binary" -name head.pcd -print -quit)
  bytes=$(stat -c %s "$pcd")
  if [ "$bytes" -lt 3600000 ]; then
    echo "bench_vs_pcl: $pcd has $bytes bytes, expected ~3.7 MB (640x480 binary)" >&2
    exit 1
  fi
}

mkdir -p "$out/logs"
stage "PCL"
install_pcl
build_pcl_reference
stage "forcegrasp"
build_forcegrasp
stage "$scenes scenes x ${#encodings[@]} encodings (seed $seed) in $out"
make_scenes
stage "timing: $runs runs"
python3 scripts/bench_vs_pcl.py --runs "$runs" --forcegrasp "$fg_bin" \
  --pcl build/pcl-reference/pcl_forcegrasp --json "$out/results.json" \
  "${encodings[@]/#/$out/}" | tee "$out/report.md"
stage "done (report in $out/report.md)"
