#!/usr/bin/env bash
# LIDAR-initialised vs random-initialised PatchMatch on the default synthetic
# scene: synthesises a short sequence (if not there yet) and prints, with the
# date and machine load, the share of pixels within 5 cm of the ground-truth
# depth per iteration, completeness / accuracy after the cost filter, the
# time per 848x480 image and the peak memory. The output is the table of
# docs/benchmarks/patch_match.md.
#
#   scripts/bench_patch_match.sh [BUILD_DIR] [DATASET_DIR] [NUM_FRAMES]
#
# DATASET_DIR defaults to bench_work/patch_match in the checkout (relative
# paths are taken from the current folder).
#
# Extra options for experiments: BENCH_SET="lidar_prior_weight=0,..." (see
# benchmarks/bench_patch_match.cc).
set -euo pipefail
build_dir=${1:-build}
source_dir=$(cd "$(dirname "$0")/.." && pwd)
dataset=${2:-$source_dir/bench_work/patch_match}
num_frames=${3:-12}
if [[ ! -f "$dataset/poses_gt.txt" ]]; then
  "$build_dir/colmap-lidar" synthesize --output_path "$dataset" \
    --Synthesis.num_frames "$num_frames" --Synthesis.survey_num_stations 1 \
    --Synthesis.survey_angular_step_deg 0.5 --Synthesis.overwrite 1
fi
echo "Date: $(date -u '+%Y-%m-%d %H:%M UTC'); $(nproc) cores; load average" \
  "at start: $(cut -d' ' -f1-3 /proc/loadavg)"
# The dataset as the docs table names it: relative to the checkout (no path
# of this machine), else as given.
label=$(realpath -m --relative-base="$source_dir" "$dataset")
[[ "$label" == /* ]] && label=$dataset
echo "Dataset: $label; options: ${BENCH_SET:-defaults}"
/usr/bin/time -v "$build_dir/benchmarks/bench_patch_match" "$dataset" 3 6 \
  2> >(grep -E "Maximum resident|Elapsed" >&2)
echo "Load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
