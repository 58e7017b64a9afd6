#!/usr/bin/env bash
# The paper's baselines beside colmap-lidar on the cells of a finished
# benchmark matrix (issue 21; scripts/bench_matrix.sh --work DIR):
#   - OpenMVG 2.1 SfM (scripts/baselines/openmvg_sfm.sh), GLOBAL and
#     INCREMENTAL, each without and with the noisy prior centres; the SIFT
#     features (deterministic per image) are computed once per cell and
#     reused, matching, geometric filter and SfM run afresh every time;
#   - OpenMVS 2.3 densify + mesh + refine on the poses of the OpenMVG variant
#     of the run that registered the most images
#     (scripts/baselines/openmvs_mesh.sh; --no_mvs skips it);
#   - stock COLMAP's `mapper` on a copy of the database of the matrix's run 1
#     (the same features and matches as colmap-lidar's), its largest model;
#   - colmap-lidar: the matrix's own runs of the cell (ws/sparse/refined,
#     ws/dense/meshed-delaunay.ply) and its LIDAR-only Poisson mesh
#     (ws/eval/mesh_lidar_poisson.ply), re-evaluated here with the same
#     protocol as the baselines.
# One evaluator for all: pose_evaluator (sim3 of centres and axes to the
# ground truth; the paper's protocol, sim3 of the centres to the priors
# for the baselines and no alignment for ours, is computed by
# baselines_table.py from the models); mesh_evaluator with the mesh carried
# by the fit of its own model's cameras to the ground truth (sim3 for the
# baselines, se3 for the metric ones), then ICP, recall twice: on the
# reference within 0.2 m of the cell's scans fused with the true poses (the
# LIDAR-covered part, the same region for every method; `lidar_fuser` on the
# cell's ground-truth workspace; *_eval*.json) and on the whole reference
# that the true cameras see, occluded parts removed (the paper's protocol;
# --MeshEvaluation.visible_model_path; *_visible*.json).
#
# Usage: bash scripts/baselines/bench_baselines.sh --work DIR [--cells a,b]
#          [--runs N] [--prefix DIR] [--threads N] [--no_mvs]
#   work    the matrix's work folder; results go to DIR/CELL/baselines/
#   cells   default: every synthetic cell with a finished run 1
#   runs    runs of each baseline per cell (default 3: the median and the
#           worst are reported, so that luck shows); a finished run is kept
#   prefix  where scripts/baselines/build.sh installed OpenMVG and OpenMVS
# Prints the per-cell tables (scripts/baselines/baselines_table.py; with
# --summary it prints one row per cell) at the end.
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
evaluate_mesh_region() {  # MESH MODEL ALIGNMENT CELL_DIR OUT REGION_OPTIONS...
  local mesh=$1 model=$2 alignment=$3 dataset="$4/dataset" out=$5
  shift 5
  "${BIN}" mesh_evaluator --input_path "${mesh}" --reference_path "${dataset}/reference.ply" \
    --alignment "${alignment}" --alignment_model_path "${model}" \
    --ground_truth_poses_path "${dataset}/poses_gt.txt" --icp 1 \
    --output_path "${out}" "$@" \
    --MeshEvaluation.reference_surface_path "${dataset}/ground_truth/scene.ply" \
    --MeshEvaluation.edge_region_path "${dataset}/ground_truth/crease_edges.txt" \
    > "${out}.log" 2>&1 || log "mesh_evaluator failed on ${mesh} (see ${out}.log)"
}
# Both regions of recall for MESH, each evaluation kept once written:
# OUT_PREFIX_eval.json (LIDAR-covered) and OUT_PREFIX_visible.json.
evaluate_mesh() {  # MESH MODEL ALIGNMENT CELL_DIR OUT_PREFIX
  [[ -f "$5_eval.json" ]] ||
    evaluate_mesh_region "$1" "$2" "$3" "$4" "$5_eval.json" \
      --MeshEvaluation.observed_cloud_path "$4/baselines/lidar_gt/lidar_fused.ply" \
      --MeshEvaluation.observed_cloud_in_reference_frame 1
  [[ -f "$5_visible.json" ]] ||
    evaluate_mesh_region "$1" "$2" "$3" "$4" "$5_visible.json" \
      --MeshEvaluation.visible_model_path "$4/gt/workspace/sparse/prior"
}
# Stock COLMAP's mapper on a copy of DB; its model with the most registered
# images copied to OUT/colmap (as the OpenMVG runs' export). A run without a
# model (e.g. "No good initial image pair found") is kept as such: OUT/time.txt
# without OUT/colmap, counted as 0 images registered.
run_colmap_mapper() {  # DB IMAGES OUT
  local out=$3
  rm -rf "${out}"
  mkdir -p "${out}/models"
  cp "$1" "${out}/database.db"
  local start=${SECONDS} best="" most=0 model count
  colmap mapper --database_path "${out}/database.db" --image_path "$2" \
    --output_path "${out}/models" --Mapper.num_threads "${THREADS}" > "${out}/log.txt" 2>&1 || true
  for model in "${out}"/models/*/; do
    [[ -d "${model}" ]] || continue
    count=$(colmap model_analyzer --path "${model}" 2>&1 |
              sed -n 's/.*Registered images: *\([0-9]*\).*/\1/p')
    if (( ${count:-0} > most )); then most=${count}; best=${model}; fi
  done
  rm -f "${out}/database.db"
  if [[ -n "${best}" ]]; then
    cp -r "${best}" "${out}/colmap"
  else
    log "stock mapper: no model ($(grep -m1 -E 'ERROR|No good' "${out}/log.txt" |
      sed 's/^ *=> *//' || true); ${out}/log.txt)"
  fi
  echo "mapper $(( SECONDS - start ))" > "${out}/time.txt"
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
        # SIFT is deterministic per image: the features of the cell's first
        # run are reused; matching, filter and SfM run afresh.
        first="${out}/run1/openmvg_global"
        [[ "${dir}" != "${first}" && -f "${first}/time.txt" ]] &&
          args+=(--features_from "${first}")
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
      # The refined mesh: OpenMVS's final output, the paper's row.
      [[ -s "${mvs}/scene_refined.ply" ]] &&
        evaluate_mesh "${mvs}/scene_refined.ply" "${mvg}/colmap" sim3_axes "${cell_dir}" \
          "${mvs}/scene_refined"
    fi
    mapper="${out}/run${run}/colmap_mapper"
    if [[ ! -f "${mapper}/time.txt" && -f "${cell_dir}/run1/ws/database.db" ]]; then
      log "${cell} run ${run}: stock COLMAP mapper"
      run_colmap_mapper "${cell_dir}/run1/ws/database.db" "${cell_dir}/run1/ws/images" \
        "${mapper}" || true
    fi
    [[ -d "${mapper}/colmap" && ! -f "${mapper}/poses.json" ]] &&
      evaluate_poses "${mapper}/colmap" "${dataset}/poses_gt.txt" "${mapper}/poses.json"
  done
  # Ours and LIDAR-only, every run of the matrix, same protocol.
  for ws in "${cell_dir}"/run*/ws; do
    run=$(basename "$(dirname "${ws}")")
    ours="${out}/ours_${run}"
    mkdir -p "${ours}"
    [[ -f "${ours}/poses.json" ]] ||
      evaluate_poses "${ws}/sparse/refined" "${dataset}/poses_gt.txt" "${ours}/poses.json"
    [[ -f "${ws}/dense/meshed-delaunay.ply" ]] &&
      evaluate_mesh "${ws}/dense/meshed-delaunay.ply" "${ws}/sparse/refined" se3_axes \
        "${cell_dir}" "${ours}/mesh"
    [[ -f "${ws}/eval/mesh_lidar_poisson.ply" ]] &&
      evaluate_mesh "${ws}/eval/mesh_lidar_poisson.ply" "${ws}/sparse/refined" se3_axes \
        "${cell_dir}" "${ours}/lidar_poisson"
  done
  log "${cell}: done"
done
"${PY}" "${ROOT}/scripts/baselines/baselines_table.py" --work "${WORK}" --cells "${CELLS}"
