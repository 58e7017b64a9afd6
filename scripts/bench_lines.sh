#!/usr/bin/env bash
# Accuracy benchmark of the line detection module (paper section III-B) on
# the default synthetic scene with ground-truth poses:
#   1. `colmap-lidar synthesize` (default preset, N frames);
#   2. import it with the ground-truth poses as the priors (so that
#      sparse/prior is the ground-truth model);
#   3. `line_extractor` on all frames, `line_exporter` into the world frame;
#   4. `line_evaluator` against ground_truth/crease_edges.txt.
# Prints the share of 3D segment length within 1/2/5/10 cm of a crease edge
# (target: >= 90% within 5 cm) and the length recall of the crease edges,
# plus the extraction summary. The recall counts all crease edges of the
# scene, also those no frame observes with both sensors, so it is a lower
# bound of the recall over edges seen by both.
#
# Usage: scripts/bench_lines.sh [build_dir] [num_frames] [work_dir]
#   build_dir defaults to build, num_frames to 20, work_dir to a temp folder.
set -euo pipefail

BUILD_DIR=${1:-build}
NUM_FRAMES=${2:-20}
WORK_DIR=${3:-$(mktemp -d /tmp/bench_lines.XXXXXX)}
BIN="${BUILD_DIR}/colmap-lidar"
[[ -x "${BIN}" ]] || { echo "ERROR: ${BIN} not found; build first" >&2; exit 1; }

DATASET="${WORK_DIR}/dataset"
WORKSPACE="${WORK_DIR}/workspace"
mkdir -p "${WORK_DIR}"
LOG="${WORK_DIR}/log.txt"
: > "${LOG}"

echo "== Synthesising ${NUM_FRAMES} frames into ${DATASET}"
if [[ ! -f "${DATASET}/poses_gt.txt" ]]; then
  "${BIN}" synthesize --output_path "${DATASET}" \
    --Synthesis.num_frames "${NUM_FRAMES}" >> "${LOG}" 2>&1
fi
# The priors are replaced by the ground truth: sparse/prior is then the
# ground-truth model the segments are placed with.
cp "${DATASET}/poses_gt.txt" "${DATASET}/poses_prior.txt"

echo "== Importing"
rm -rf "${WORKSPACE}"
"${BIN}" lidar_importer --dataset_path "${DATASET}" \
  --workspace_path "${WORKSPACE}" >> "${LOG}" 2>&1

echo "== Extracting lines"
START=$(date +%s.%N)
"${BIN}" line_extractor --database_path "${WORKSPACE}/database.db" \
  --image_path "${WORKSPACE}/images" \
  --debug_path "${WORKSPACE}/lines_debug" 2>> "${LOG}" | tee -a "${LOG}"
END=$(date +%s.%N)
echo "   wall time: $(echo "${END} - ${START}" | bc) s for ${NUM_FRAMES} frames"

"${BIN}" line_exporter --database_path "${WORKSPACE}/database.db" \
  --input_path "${WORKSPACE}/sparse/prior" \
  --output_path "${WORKSPACE}/lines_world.ply" 2>> "${LOG}" | tee -a "${LOG}"

echo "== Evaluating against ${DATASET}/ground_truth/crease_edges.txt"
"${BIN}" line_evaluator --input_path "${WORKSPACE}/lines_world.ply" \
  --ground_truth_path "${DATASET}/ground_truth/crease_edges.txt" \
  --output_path "${WORK_DIR}/line_evaluation.json" 2>> "${LOG}" \
  | tee -a "${LOG}"
echo "Report: ${WORK_DIR}/line_evaluation.json, log: ${LOG}"
