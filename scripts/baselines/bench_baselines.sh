#!/usr/bin/env bash
# The paper's baselines beside colmap-lidar on the cells of a finished
# benchmark matrix (issue 21; scripts/bench_matrix.sh --work DIR):
#   - OpenMVG 2.1 SfM (scripts/baselines/openmvg_sfm.sh), GLOBAL and
#     INCREMENTAL, each without and with the noisy prior centres;
#   - OpenMVS 2.3 densify + mesh + refine on the poses of the OpenMVG variant
#     of the run that registered the most images
#     (scripts/baselines/openmvs_mesh.sh; --no_mvs skips it);
#   - colmap-lidar: the matrix's own runs of the cell (ws/sparse/refined,
#     ws/dense/meshed-delaunay.ply) and its LIDAR-only Poisson mesh
#     (ws/eval/mesh_lidar_poisson.ply), re-evaluated here with the same
#     protocol as the baselines.
# One evaluator for all: pose_evaluator (sim3 of centres and axes to the
# ground truth; the paper's protocol, sim3 of the centres to the priors
# for the baselines and no alignment for ours, is computed by
# baselines_table.py from the models); mesh_evaluator with the mesh carried
# by the fit of its own model's cameras to the ground truth (sim3 for the
# baselines, se3 for the metric ones), then ICP, recall on the reference
# within 0.2 m of the cell's scans fused with the true poses (the same region
# for every method; `lidar_fuser` on the cell's ground-truth workspace).
#
# Usage: bash scripts/baselines/bench_baselines.sh --work DIR [--cells a,b]
#          [--runs N] [--prefix DIR] [--threads N] [--no_mvs]
#   work    the matrix's work folder; results go to DIR/CELL/baselines/
#   cells   default: every synthetic cell with a finished run 1
#   runs    runs of each baseline per cell (default 3: the median and the
#           worst are reported, so that luck shows); a finished run is kept
#   prefix  where scripts/baselines/build.sh installed OpenMVG and OpenMVS
# Prints the table (scripts/baselines/baselines_table.py) at the end.
# COLMAP_LIDAR_BIN selects colmap-lidar (default build/colmap-lidar).
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$(pwd)
BIN="${COLMAP_LIDAR_BIN:-${ROOT}/build/colmap-lidar}"
PY=/usr/bin/python3
WORK=""
CELLS=""
RUNS=3
PREFIX="${ROOT}/bench_work/baselines"
THREADS=$(nproc)
MVS=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --work) WORK=$2; shift 2 ;;
    --cells) CELLS=$2; shift 2 ;;
    --runs) RUNS=$2; shift 2 ;;
    --prefix) PREFIX=$2; shift 2 ;;
    --threads) THREADS=$2; shift 2 ;;
    --no_mvs) MVS=0; shift ;;
    -h|--help) sed -n 2,30p "$0"; exit 0 ;;
    *) echo "bench_baselines.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
fail() { echo "bench_baselines: $*" >&2; exit 1; }
log() { echo "[bench_baselines $(date +%H:%M:%S)] $*"; }
[[ -n "${WORK}" && -d "${WORK}" ]] || fail "--work must name a finished matrix work folder"
[[ "${RUNS}" =~ ^[1-9][0-9]*$ ]] || fail "--runs must be a positive integer"
[[ -x "${BIN}" ]] || fail "no colmap-lidar binary ${BIN} (build first)"
WORK=$(cd "${WORK}" && pwd)
if [[ -z "${CELLS}" ]]; then
  CELLS=$(cd "${WORK}" && for d in */run1/ws/pipeline/sfm.done; do
            [[ -f "${d%%/*}/dataset/poses_gt.txt" ]] && echo "${d%%/*}"; done | paste -sd, -)
fi
[[ -n "${CELLS}" ]] || fail "no finished synthetic cell in ${WORK}"

evaluate_poses() {  # MODEL GT OUT
  "${BIN}" pose_evaluator --input_path "$1" --ground_truth_path "$2" \
    --PoseEvaluation.alignment sim3_axes --output_path "$3" > "$3.log" 2>&1 ||
    log "pose_evaluator failed on $1 (see $3.log)"
}
evaluate_mesh() {  # MESH MODEL ALIGNMENT CELL_DIR OUT
  local dataset="$4/dataset"
  "${BIN}" mesh_evaluator --input_path "$1" --reference_path "${dataset}/reference.ply" \
    --alignment "$3" --alignment_model_path "$2" \
    --ground_truth_poses_path "${dataset}/poses_gt.txt" --icp 1 \
    --output_path "$5" \
    --MeshEvaluation.observed_cloud_path "$4/baselines/lidar_gt/lidar_fused.ply" \
    --MeshEvaluation.observed_cloud_in_reference_frame 1 \
    --MeshEvaluation.reference_surface_path "${dataset}/ground_truth/scene.ply" \
    --MeshEvaluation.edge_region_path "${dataset}/ground_truth/crease_edges.txt" \
    > "$5.log" 2>&1 || log "mesh_evaluator failed on $1 (see $5.log)"
}

VARIANTS=(global global_priors incremental incremental_priors)
IFS=, read -r -a SELECTED <<< "${CELLS}"
for cell in "${SELECTED[@]}"; do
  cell_dir="${WORK}/${cell}"
  dataset="${cell_dir}/dataset"
  [[ -f "${dataset}/poses_gt.txt" && -f "${dataset}/reference.ply" ]] ||
    { log "${cell}: no ground truth; skipped"; continue; }
  out="${cell_dir}/baselines"
  mkdir -p "${out}"
  if [[ ! -f "${out}/lidar_gt/lidar_fused.ply" ]]; then
    log "${cell}: the scans fused with the true poses (the region judged)"
    "${BIN}" lidar_fuser --database_path "${cell_dir}/gt/workspace/database.db" \
      --input_path "${cell_dir}/gt/workspace/sparse/prior" \
      --output_path "${out}/lidar_gt" > "${out}/lidar_gt.log" 2>&1 ||
      fail "${cell}: lidar_fuser on the ground-truth workspace failed (${out}/lidar_gt.log)"
  fi
  for run in $(seq 1 "${RUNS}"); do
    mkdir -p "${out}/run${run}"
    for variant in "${VARIANTS[@]}"; do
      dir="${out}/run${run}/openmvg_${variant}"
      if [[ ! -f "${dir}/time.txt" ]]; then
        args=(--engine GLOBAL)
        [[ ${variant} == incremental* ]] && args=(--engine INCREMENTAL)
        [[ ${variant} == *_priors ]] && args+=(--priors)
        log "${cell} run ${run}: OpenMVG ${variant}"
        bash "${ROOT}/scripts/baselines/openmvg_sfm.sh" --dataset "${dataset}" \
          --output "${dir}" --prefix "${PREFIX}" --threads "${THREADS}" "${args[@]}" \
          > "${dir}.log" 2>&1 || { log "${cell} run ${run}: OpenMVG ${variant} failed (${dir}.log)"; continue; }
      fi
      [[ -f "${dir}/poses.json" ]] ||
        evaluate_poses "${dir}/colmap" "${dataset}/poses_gt.txt" "${dir}/poses.json"
    done
    # OpenMVS on the OpenMVG variant of this run that registered the most
    # images (the first of VARIANTS on a tie): the baseline at its best.
    mvg=""
    best=0
    for variant in "${VARIANTS[@]}"; do
      images="${out}/run${run}/openmvg_${variant}/colmap/images.txt"
      [[ -f "${images}" ]] || continue
      count=$(grep -v '^#' "${images}" | awk 'NR % 2 == 1' | grep -c . || true)
      if (( count > best )); then best=${count}; mvg="${out}/run${run}/openmvg_${variant}"; fi
    done
    mvs="${out}/run${run}/openmvs"
    if [[ ${MVS} -eq 1 && -n "${mvg}" ]]; then
      [[ -f "${mvs}/openmvg_variant.txt" ]] && mvg=$(cat "${mvs}/openmvg_variant.txt")
      if [[ ! -f "${mvs}/time.txt" || ! -s "${mvs}/scene_refined.ply" ]]; then
        log "${cell} run ${run}: OpenMVS on $(basename "${mvg}")"
        bash "${ROOT}/scripts/baselines/openmvs_mesh.sh" --openmvg "${mvg}" \
          --output "${mvs}" --prefix "${PREFIX}" --threads "${THREADS}" \
          > "${mvs}.log" 2>&1 || log "${cell} run ${run}: OpenMVS failed (${mvs}.log)"
        [[ -d "${mvs}" ]] && echo "${mvg}" > "${mvs}/openmvg_variant.txt"
      fi
      for mesh in scene_mesh scene_refined; do
        [[ -s "${mvs}/${mesh}.ply" && ! -f "${mvs}/${mesh}_eval.json" ]] &&
          evaluate_mesh "${mvs}/${mesh}.ply" "${mvg}/colmap" sim3_axes "${cell_dir}" \
            "${mvs}/${mesh}_eval.json"
      done
    fi
  done
  # Ours and LIDAR-only, every run of the matrix, same protocol.
  for ws in "${cell_dir}"/run*/ws; do
    run=$(basename "$(dirname "${ws}")")
    ours="${out}/ours_${run}"
    mkdir -p "${ours}"
    [[ -f "${ours}/poses.json" ]] ||
      evaluate_poses "${ws}/sparse/refined" "${dataset}/poses_gt.txt" "${ours}/poses.json"
    [[ -f "${ws}/dense/meshed-delaunay.ply" && ! -f "${ours}/mesh_eval.json" ]] &&
      evaluate_mesh "${ws}/dense/meshed-delaunay.ply" "${ws}/sparse/refined" se3_axes \
        "${cell_dir}" "${ours}/mesh_eval.json"
    [[ -f "${ws}/eval/mesh_lidar_poisson.ply" && ! -f "${ours}/lidar_poisson_eval.json" ]] &&
      evaluate_mesh "${ws}/eval/mesh_lidar_poisson.ply" "${ws}/sparse/refined" se3_axes \
        "${cell_dir}" "${ours}/lidar_poisson_eval.json"
  done
  log "${cell}: done"
done
"${PY}" "${ROOT}/scripts/baselines/baselines_table.py" --work "${WORK}" --cells "${CELLS}"
