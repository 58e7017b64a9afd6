#!/usr/bin/env bash
# Remakes the seed corpora of the fuzz targets, tests/fuzz/corpus/<target>,
# from real files: the KITTI raw sample in ../shared and a tiny scene made by
# `colmap-lidar synthesize` (4 frames, 160x120, 16 rings, depth maps). Large
# files are shrunk by tests/fuzz/make_seeds.cc (a few records re-encoded by
# our writers), so every seed stays a few KB. Minimised inputs that once
# crashed a reader, tests/fuzz/corpus/<target>/regression_*, are kept.
#
# Usage: scripts/fuzz_corpus.sh
# Needs build/colmap-lidar (scripts/build.sh) and the fuzz build
# (scripts/fuzz.sh builds it; FUZZ_BUILD_DIR, default build-fuzz).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${FUZZ_BUILD_DIR:-build-fuzz}
kitti=${COLMAP_LIDAR_SHARED_DIR:-../shared}/data/kitti_raw_2011_09_26_sample/2011_09_26
[ -x build/colmap-lidar ] || { echo "fuzz_corpus: build/colmap-lidar missing (scripts/build.sh)" >&2; exit 1; }
[ -d "$kitti" ] || { echo "fuzz_corpus: no KITTI sample at $kitti" >&2; exit 1; }
flock /tmp/colmap-lidar-build.lock cmake --build "$build_dir" -j2 --target fuzz_make_seeds \
  > "$build_dir/make_seeds_build.log" 2>&1 || { tail -n 40 "$build_dir/make_seeds_build.log"; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
build/colmap-lidar synthesize --output_path "$work/scene" \
  --Synthesis.num_frames 4 --Synthesis.image_width 160 --Synthesis.image_height 120 \
  --Synthesis.lidar_model VLP-16 --Synthesis.survey_max_points 2000 \
  --Synthesis.write_depth_maps 1 > "$work/synthesize.log" 2>&1 ||
  { tail -n 20 "$work/synthesize.log"; exit 1; }

rm -rf tests/fuzz/corpus.new
"$build_dir/tests/fuzz/fuzz_make_seeds" tests/fuzz/corpus.new "$kitti" "$work/scene"
# Inputs that once crashed a reader (regression_*, minimised) are kept.
if [ -d tests/fuzz/corpus ]; then
  (cd tests/fuzz/corpus &&
   find . -type f -name 'regression_*' -exec cp --parents {} ../corpus.new/ \;)
fi
rm -rf tests/fuzz/corpus
mv tests/fuzz/corpus.new tests/fuzz/corpus
find tests/fuzz/corpus -type f -size +100k -print -exec false {} + ||
  { echo "fuzz_corpus: seeds above 100 KB" >&2; exit 1; }
echo "fuzz_corpus: $(find tests/fuzz/corpus -type f | wc -l) seeds," \
     "$(du -sk tests/fuzz/corpus | cut -f1) KB in tests/fuzz/corpus"
