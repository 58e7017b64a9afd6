#!/usr/bin/env bash
# Accuracy and speed benchmark of the 3D/3D line association (paper section
# III-C, issue 5) on the default synthetic scene:
#   synthesize -> lidar_importer -> line_extractor -> line_matcher
# with ground-truth poses and with the noisy priors (0.5 m, 5 deg; the
# matcher registers the view pairs on their segments), printing track
# precision against the ground-truth crease edges
# (scripts/eval_line_tracks.py; with SEGMENTS=gt against the edge each
# segment was made from) and the association time.
#
# Usage: scripts/bench_line_matching.sh [WORK_DIR] [extra line_matcher args]
# WORK_DIR defaults to bench_work/line_matching in the checkout.
# Env: COLMAP_LIDAR (default build/colmap-lidar), NUM_FRAMES (default 60),
#      NUM_THREADS (default 2), DATASET (an existing synthetic dataset to use),
#      SEGMENTS=extractor (default: line_extractor) | gt (the crease edges as
#      each view sees them, benchmarks/bench_line_matching_segments: measures
#      the association alone).
set -euo pipefail

SOURCE_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="${COLMAP_LIDAR:-${SOURCE_DIR}/build/colmap-lidar}"
WORK="${1:-${SOURCE_DIR}/bench_work/line_matching}"
shift || true
NUM_FRAMES="${NUM_FRAMES:-60}"
NUM_THREADS="${NUM_THREADS:-2}"
mkdir -p "${WORK}"
WORK="$(cd "${WORK}" && pwd)"

DATASET="${DATASET:-${WORK}/dataset}"
if [[ ! -f "${DATASET}/poses_gt.txt" ]]; then
  echo "== synthesize (${NUM_FRAMES} frames) -> ${DATASET}"
  "${BIN}" synthesize --output_path "${DATASET}" \
    --Synthesis.num_frames "${NUM_FRAMES}" > "${WORK}/synthesize.log" 2>&1
fi

# The same recording twice: as is (noisy priors) and with poses_prior.txt =
# poses_gt.txt, so that the importer builds a model with the exact poses.
DATASET_GT="${WORK}/dataset_gt"
rm -rf "${DATASET_GT}"
mkdir -p "${DATASET_GT}"
for entry in "${DATASET}"/*; do
  name="$(basename "${entry}")"
  [[ "${name}" == "poses_prior.txt" ]] && continue
  ln -s "${entry}" "${DATASET_GT}/${name}"
done
cp "${DATASET}/poses_gt.txt" "${DATASET_GT}/poses_prior.txt"

SEGMENTS="${SEGMENTS:-extractor}"
WS="${WORK}/workspace_${SEGMENTS}"
WS_GT="${WORK}/model_gt_poses"
if [[ ! -f "${WS}/database.db" ]]; then
  echo "== lidar_importer + line_extractor"
  rm -rf "${WS}"
  "${BIN}" lidar_importer --dataset_path "${DATASET}" --workspace_path "${WS}" \
    > "${WORK}/import.log" 2>&1
  if [[ "${SEGMENTS}" == "gt" ]]; then
    "$(dirname "${BIN}")/benchmarks/bench_line_matching_segments" \
      "${DATASET}" "${WS}/database.db" "${WS}/segment_labels.txt"
  else
    "${BIN}" line_extractor --database_path "${WS}/database.db" \
      --image_path "${WS}/images" > "${WORK}/line_extractor.log" 2>&1
    tail -n 3 "${WORK}/line_extractor.log"
  fi
fi
rm -rf "${WS_GT}"
# Only the model matters here (same frames, same image ids as ${WS}).
"${BIN}" lidar_importer --dataset_path "${DATASET_GT}" \
  --workspace_path "${WS_GT}" --LidarImport.copy_images 0 \
  --LidarImport.copy_scans 0 > "${WORK}/import_gt.log" 2>&1

EVAL_ARGS=()
if [[ "${SEGMENTS}" == "gt" ]]; then
  EVAL_ARGS=(--segment_labels "${WS}/segment_labels.txt")
fi

run() {  # label model_dir extra args...
  local label="$1" model="$2"
  shift 2
  echo "== line_matcher, ${SEGMENTS} segments, ${label} poses"
  local start end
  start=$(date +%s.%N)
  "${BIN}" line_matcher --database_path "${WS}/database.db" \
    --input_path "${model}" --export_tracks_path "${WORK}/tracks_${SEGMENTS}_${label}.json" \
    --LineMatching.num_threads "${NUM_THREADS}" "$@" \
    > "${WORK}/line_matcher_${SEGMENTS}_${label}.log" 2>&1
  end=$(date +%s.%N)
  grep -E "^(Line association|  )" "${WORK}/line_matcher_${SEGMENTS}_${label}.log" || true
  echo "  Wall time of the command: $(echo "${end} - ${start}" | bc) s"
  python3 "${SOURCE_DIR}/scripts/eval_line_tracks.py" \
    "${WORK}/tracks_${SEGMENTS}_${label}.json" "${DATASET}/poses_gt.txt" \
    "${DATASET}/ground_truth/crease_edges.txt" "${EVAL_ARGS[@]}" | sed 's/^/  /'
}

run gt "${WS_GT}/sparse/prior" "$@"
run prior "${WS}/sparse/prior" --LineMatching.pose_sigma_t_m 0.5 \
  --LineMatching.pose_sigma_r_deg 5 "$@"
