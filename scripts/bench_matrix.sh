#!/usr/bin/env bash
# The benchmark matrix (issue 14): `colmap-lidar automatic_reconstructor`
# with default options on every cell of scripts/matrix_cells.txt (scene x
# LIDAR x camera x prior noise, synthesized with ground truth) and on the
# KITTI raw sample, then per cell
#   - 3D segments per frame and their precision / recall against the crease
#     edges (the run's own segments placed with the ground-truth poses);
#   - line tracks (line_matcher) with the noisy priors and with the refined
#     poses, their purity, mean length and share of non-vertical tracks
#     (scripts/eval_line_tracks.py);
#   - poses: mean position error without alignment and the floor the priors
#     leave for that draw (scripts/pose_gauge_bound.py), after sim3, rotation;
#   - depth maps within 5 cm and their coverage (eval/depth_maps.json);
#   - mesh P/R/F at 0.02/0.05/0.1/0.5 m for ours, LIDAR-only Poisson and ours
#     without line samples (the mesh and evaluate stages re-run on a copy of
#     the workspace with --AutomaticReconstruction.mesh_with_lines 0);
#   - wall / CPU time and peak memory per stage (pipeline/stages.json);
# and writes the table with the worst cell of every column
# (scripts/matrix_table.py -> <work>/matrix.md; docs/benchmarks/matrix.md is
# the curated page its tables are copied into, never overwritten).
#
# Cells are reusable: a cell's dataset and each finished run are kept under
# the work folder, and a re-run only does what is missing. Every figure of a
# cell with several runs is given as worst and best.
#
# Usage: bash scripts/bench_matrix.sh [--work DIR] [--cells a,b,...]
#          [--cells_file FILE] [--runs N] [--num_frames N] [--kitti DIR]
#          [--run_options "OPTIONS"] [--no-write]
#   work        default bench_work/matrix
#   cells       default: every cell of the cells file
#   runs        runs of the same commit per cell (default 1; 3 for headline
#               figures: the worst of 3)
#   num_frames  frames per synthetic cell (default 20, as every documented
#               round since 2026-11-26; a cell's dataset, once synthesized,
#               is reused whatever this says)
#   kitti       a KITTI raw recording (default: none, the kitti cell is
#               skipped; the tests use the sample in ../shared/data)
#   run_options options given to every automatic_reconstructor run (an A/B
#               of one option against the defaults, in its own --work)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BIN="${COLMAP_LIDAR_BIN:-${ROOT}/build/colmap-lidar}"
WORK=bench_work/matrix
CELLS=""
CELLS_FILE="${ROOT}/scripts/matrix_cells.txt"
RUNS=1
NUM_FRAMES=20
KITTI=""
EXTRA_RUN_OPTIONS=""
WRITE=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --work) WORK=$2; shift 2 ;;
    --cells) CELLS=$2; shift 2 ;;
    --cells_file) CELLS_FILE=$2; shift 2 ;;
    --runs) RUNS=$2; shift 2 ;;
    --num_frames) NUM_FRAMES=$2; shift 2 ;;
    --kitti) KITTI=$2; shift 2 ;;
    --run_options) EXTRA_RUN_OPTIONS=$2; shift 2 ;;
    --no-write) WRITE=0; shift ;;
    -h|--help) sed -n '2,39p' "$0"; exit 0 ;;
    *) echo "bench_matrix: unknown argument $1" >&2; exit 2 ;;
  esac
done
[[ -x "${BIN}" ]] || { echo "bench_matrix: ${BIN} not found; build first (bash scripts/build.sh)" >&2; exit 1; }
[[ -f "${CELLS_FILE}" ]] || { echo "bench_matrix: cells file ${CELLS_FILE} not found" >&2; exit 2; }
[[ "${RUNS}" =~ ^[1-9][0-9]*$ ]] || { echo "bench_matrix: --runs must be a positive integer" >&2; exit 2; }
[[ "${NUM_FRAMES}" =~ ^[1-9][0-9]*$ ]] || { echo "bench_matrix: --num_frames must be a positive integer" >&2; exit 2; }
mkdir -p "${WORK}"
WORK=$(cd "${WORK}" && pwd)
PY=/usr/bin/python3
THREADS=$(nproc)

declare -A CELL_OPTIONS
ORDER=()
while read -r name rest; do
  [[ -z "${name}" || "${name}" == \#* ]] && continue
  CELL_OPTIONS[${name}]="${rest}"
  ORDER+=("${name}")
done < "${CELLS_FILE}"
SELECTED=()
if [[ -n "${CELLS}" ]]; then
  IFS=, read -r -a SELECTED <<< "${CELLS}"
  for c in "${SELECTED[@]}"; do
    [[ -v CELL_OPTIONS[$c] ]] || { echo "bench_matrix: no cell '$c' in ${CELLS_FILE}" >&2; exit 2; }
  done
else
  SELECTED=("${ORDER[@]}")
fi

now() { date +%s; }
log() { echo "[$(date -u +%H:%M:%S)] $*"; }

# A dataset whose priors are the ground truth, linking the source's files:
# its sparse/prior is the ground-truth model that places the segments.
make_gt_workspace() {  # dataset gt_dir
  local dataset=$1 gt=$2
  [[ -f "${gt}/workspace/database.db" ]] && return 0
  rm -rf "${gt}"
  mkdir -p "${gt}/dataset"
  for f in calibration.yaml images lidar ground_truth; do
    ln -s "${dataset}/${f}" "${gt}/dataset/${f}"
  done
  cp "${dataset}/poses_gt.txt" "${gt}/dataset/poses_gt.txt"
  cp "${dataset}/poses_gt.txt" "${gt}/dataset/poses_prior.txt"
  "${BIN}" lidar_importer --dataset_path "${gt}/dataset" \
    --workspace_path "${gt}/workspace.tmp" --LidarImport.copy_images false \
    --LidarImport.copy_scans false > "${gt}/import.log" 2>&1
  mv "${gt}/workspace.tmp" "${gt}/workspace"
}

# Extras of one finished run: lines, tracks, the no-lines mesh, pose floor.
run_extras() {  # cell dataset run_dir
  local cell=$1 dataset=$2 run=$3
  local extra="${run}/matrix"
  mkdir -p "${extra}"
  local has_gt=0
  [[ -f "${dataset}/poses_gt.txt" ]] && has_gt=1

  # Segments per frame (all datasets) and against the crease edges.
  if [[ ! -f "${extra}/lines.done" ]]; then
    "${BIN}" line_exporter --database_path "${run}/ws/database.db" \
      --input_path "${run}/ws/sparse/refined" \
      --output_path "${extra}/lines_refined.ply" > "${extra}/lines.log" 2>&1 || true
    if [[ ${has_gt} -eq 1 && -f "${dataset}/ground_truth/crease_edges.txt" ]]; then
      make_gt_workspace "${dataset}" "$(dirname "${run}")/gt"
      "${BIN}" line_exporter --database_path "${run}/ws/database.db" \
        --input_path "$(dirname "${run}")/gt/workspace/sparse/prior" \
        --output_path "${extra}/lines_gt_poses.ply" >> "${extra}/lines.log" 2>&1
      "${BIN}" line_evaluator --input_path "${extra}/lines_gt_poses.ply" \
        --ground_truth_path "${dataset}/ground_truth/crease_edges.txt" \
        --output_path "${extra}/lines_eval.json" >> "${extra}/lines.log" 2>&1
    fi
    touch "${extra}/lines.done"
  fi

  # Line tracks (line_matcher on a copy of the database; the scan paths it
  # stores are relative to its folder: link the workspace's scans) with the
  # noisy priors and with the refined poses, then their purity and length.
  local poses
  for poses in prior refined; do
    [[ -f "${extra}/tracks_${poses}.done" ]] && continue
    cp "${run}/ws/database.db" "${extra}/tracks.db"
    ln -sfn "${run}/ws/lidar" "${extra}/lidar"
    "${BIN}" line_matcher --database_path "${extra}/tracks.db" \
      --input_path "${run}/ws/sparse/${poses}" \
      --export_tracks_path "${extra}/tracks_${poses}.json" \
      > "${extra}/tracks_${poses}.log" 2>&1 || true
    rm -f "${extra}/tracks.db" "${extra}/lidar"
    if [[ ! -f "${extra}/tracks_${poses}.json" ]]; then
      continue
    elif [[ ${has_gt} -eq 1 && -f "${dataset}/ground_truth/crease_edges.txt" ]]; then
      "${PY}" scripts/eval_line_tracks.py "${extra}/tracks_${poses}.json" \
        "${dataset}/poses_gt.txt" "${dataset}/ground_truth/crease_edges.txt" \
        > "${extra}/tracks_${poses}_eval.txt" 2>&1
    else
      "${PY}" - "${extra}/tracks_${poses}.json" \
        > "${extra}/tracks_${poses}_eval.txt" <<'EOF'
import json, sys
tracks = json.load(open(sys.argv[1]))["tracks"]
n = len(tracks)
obs = sum(len(t["observations"]) for t in tracks)
print(f"tracks {n}, observations {obs}, mean track length {obs / max(1, n):.2f}")
EOF
    fi
    touch "${extra}/tracks_${poses}.done"
  done

  # Ours without line samples: mesh + evaluate on a copy that links the
  # dense inputs (every stage writes new files and renames, so the links
  # are never written through).
  if [[ ${has_gt} -eq 1 && ! -f "${extra}/nolines.done" ]]; then
    local copy="${extra}/nolines_ws"
    rm -rf "${copy}"
    mkdir -p "${copy}"
    cp -al "${run}/ws/." "${copy}/"
    rm -f "${copy}/database.db" && cp "${run}/ws/database.db" "${copy}/database.db"
    rm -rf "${copy}/eval" "${copy}/report" "${copy}/dense/meshed-delaunay.ply"
    rm -f "${copy}"/pipeline/{mesh,evaluate,report}.done
    "${BIN}" automatic_reconstructor --workspace_path "${copy}" \
      --dataset_path "${dataset}" --AutomaticReconstruction.stages mesh:evaluate \
      --AutomaticReconstruction.mesh_with_lines 0 \
      --AutomaticReconstruction.evaluate_lidar_baseline 0 \
      --AutomaticReconstruction.num_threads "${THREADS}" ${EXTRA_RUN_OPTIONS} \
      > "${extra}/nolines.log" 2>&1
    mkdir -p "${extra}/nolines_eval"
    cp "${copy}"/eval/mesh_ours*.json "${extra}/nolines_eval/" 2>/dev/null || true
    cp "${copy}/pipeline/mesh.done" "${extra}/nolines_eval/mesh.done" 2>/dev/null || true
    rm -rf "${copy}"
    touch "${extra}/nolines.done"
  fi

  # The floor that the priors leave (perfect relative poses, 6-DoF fit).
  if [[ ${has_gt} -eq 1 && ! -f "${extra}/gauge.txt" ]]; then
    local sigma_t sigma_r
    sigma_t=$(sed -n 's/.*--Synthesis.prior_translation_sigma_m \([0-9.]*\).*/\1/p' <<< "${CELL_OPTIONS[$cell]}")
    sigma_r=$(sed -n 's/.*--Synthesis.prior_rotation_sigma_deg \([0-9.]*\).*/\1/p' <<< "${CELL_OPTIONS[$cell]}")
    "${PY}" scripts/pose_gauge_bound.py --gt "${dataset}/poses_gt.txt" \
      --prior "${dataset}/poses_prior.txt" --sigma_t "${sigma_t:-0.5}" \
      --sigma_r_deg "${sigma_r:-5}" --trials 200 > "${extra}/gauge.txt.tmp" 2>&1
    mv "${extra}/gauge.txt.tmp" "${extra}/gauge.txt"
  fi
}

TOTAL_START=$(now)
for cell in "${SELECTED[@]}"; do
  CELL_DIR="${WORK}/${cell}"
  mkdir -p "${CELL_DIR}"
  CELL_START=$(now)
  if [[ "${cell}" == kitti ]]; then
    if [[ -z "${KITTI}" ]]; then
      log "${cell}: skipped (no --kitti DIR)"
      continue
    fi
    DATASET=$(cd "${KITTI}" && pwd)
  else
    DATASET="${CELL_DIR}/dataset"
    if [[ ! -f "${DATASET}/poses_gt.txt" ]]; then
      log "${cell}: synthesizing ${NUM_FRAMES} frames"
      rm -rf "${DATASET}"
      # shellcheck disable=SC2086
      "${BIN}" synthesize --output_path "${DATASET}" \
        --Synthesis.num_frames "${NUM_FRAMES}" ${CELL_OPTIONS[$cell]} \
        > "${CELL_DIR}/synthesize.log" 2>&1 ||
        { log "${cell}: synthesize failed, see ${CELL_DIR}/synthesize.log"; continue; }
    fi
  fi
  for ((r = 1; r <= RUNS; ++r)); do
    RUN_DIR="${CELL_DIR}/run${r}"
    mkdir -p "${RUN_DIR}"
    if [[ ! -f "${RUN_DIR}/ws/pipeline/evaluate.done" && ! -f "${RUN_DIR}/ws/pipeline/report.done" ]]; then
      log "${cell}: run ${r}/${RUNS}: automatic_reconstructor"
      # The real recording's line in the cells file holds options of the
      # pipeline itself (synthetic cells: of synthesize).
      RUN_OPTIONS="${EXTRA_RUN_OPTIONS}"
      [[ "${cell}" == kitti ]] && RUN_OPTIONS+=" ${CELL_OPTIONS[$cell]}"
      # shellcheck disable=SC2086
      if ! "${BIN}" automatic_reconstructor --workspace_path "${RUN_DIR}/ws" \
          --dataset_path "${DATASET}" \
          --AutomaticReconstruction.num_threads "${THREADS}" ${RUN_OPTIONS} \
          > "${RUN_DIR}/pipeline.log" 2>&1; then
        log "${cell}: run ${r} FAILED, see ${RUN_DIR}/pipeline.log"
        echo failed > "${RUN_DIR}/failed"
        continue
      fi
      rm -f "${RUN_DIR}/failed"
    fi
    log "${cell}: run ${r}/${RUNS}: lines, tracks, no-lines mesh"
    run_extras "${cell}" "${DATASET}" "${RUN_DIR}" ||
      log "${cell}: run ${r}: extras failed (see ${RUN_DIR}/matrix/*.log)"
  done
  log "${cell}: done in $(( $(now) - CELL_START )) s"
done
log "matrix: $(( $(now) - TOTAL_START )) s in all"

TABLE_ARGS=(--work "${WORK}" --cells_file "${CELLS_FILE}")
if [[ ${WRITE} -eq 1 ]]; then
  TABLE_ARGS+=(--output "${WORK}/matrix.md")
fi
"${PY}" scripts/matrix_table.py "${TABLE_ARGS[@]}"
