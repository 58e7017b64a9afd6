#!/usr/bin/env bash
# Fuzzes every reader of outside data (tests/fuzz) for SECONDS each and prints
# per target the executions and crashes; exits non-zero on any crash, hang,
# out-of-memory or sanitizer report. Builds the targets first in build-fuzz
# (clang-14, libFuzzer + AddressSanitizer + UndefinedBehaviorSanitizer).
#
# Usage: scripts/fuzz.sh SECONDS [TARGET...]
#   TARGET: ply pcd kitti_bin calibration poses kitti_calib model_bin
#           model_txt dense_map fused_vis database options (default: all)
# Environment: FUZZ_BUILD_DIR (default build-fuzz), FUZZ_JOBS (default 2),
# FUZZ_RUNS (stop each target after that many executions, SECONDS being the
# cap: `FUZZ_RUNS=1000000 scripts/fuzz.sh 3600` is the benchmark of
# docs/benchmarks/fuzz.md).
# Seeds: tests/fuzz/corpus/<target> (small real files, committed; remake them
# with scripts/fuzz_corpus.sh); what a run learns goes to
# $FUZZ_BUILD_DIR/fuzz_corpus/<target>, crash inputs to
# $FUZZ_BUILD_DIR/fuzz_corpus/artifacts. Reproduce a crash with
#   $FUZZ_BUILD_DIR/tests/fuzz/fuzz_<target> <crash file>
# Builds take /tmp/colmap-lidar-build.lock, like every build of this checkout.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ] || ! [[ $1 =~ ^[0-9]+$ ]]; then
  sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
seconds=$1
shift
all_targets=(ply pcd kitti_bin calibration poses kitti_calib model_bin
             model_txt dense_map fused_vis database options)
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then targets=("${all_targets[@]}"); fi

build_dir=${FUZZ_BUILD_DIR:-build-fuzz}
jobs=${FUZZ_JOBS:-2}
lock=/tmp/colmap-lidar-build.lock
for tool in clang-14 clang++-14; do
  command -v $tool >/dev/null || { echo "fuzz: $tool not found (apt-get install clang-14 libclang-rt-14-dev)" >&2; exit 2; }
done

start=$(date +%s)
mkdir -p "$build_dir"
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  # Ninja where installed: CMake's Makefiles build the named targets one
  # after another, Ninja on both cores.
  generator=()
  if command -v ninja >/dev/null; then generator=(-G Ninja); fi
  CC=clang-14 CXX=clang++-14 flock "$lock" cmake "${generator[@]}" -S . -B "$build_dir" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCOLMAP_LIDAR_BUILD_FUZZERS=ON \
    -DCOLMAP_LIDAR_BUILD_TESTS=OFF -DCOLMAP_LIDAR_BUILD_BENCHMARKS=OFF \
    > "$build_dir/configure.log" 2>&1 || { cat "$build_dir/configure.log"; exit 1; }
fi
build_targets=()
for t in "${targets[@]}"; do build_targets+=("fuzz_$t"); done
flock "$lock" cmake --build "$build_dir" -j"$jobs" --target "${build_targets[@]}" \
  > "$build_dir/fuzz_build.log" 2>&1 || { tail -n 60 "$build_dir/fuzz_build.log"; exit 1; }
echo "fuzz: built ${#targets[@]} targets in $(( $(date +%s) - start )) s"

failed=()
for t in "${targets[@]}"; do
  if ! tests/fuzz/run_fuzz_target.sh "$build_dir/tests/fuzz/fuzz_$t" "$seconds" \
         "$build_dir/fuzz_corpus/$t" "tests/fuzz/corpus/$t"; then
    failed+=("$t")
  fi
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: FINDINGS in ${failed[*]} (inputs in $build_dir/fuzz_corpus/artifacts)"
  exit 1
fi
echo "fuzz: ${#targets[@]} targets clean"
