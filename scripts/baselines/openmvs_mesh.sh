#!/usr/bin/env bash
# OpenMVS 2.3 photogrammetry on the poses of an OpenMVG run (the paper's
# Table II "OpenMVG + OpenMVS" row, issue 21): openMVG2openMVS (undistorted
# images) -> DensifyPointCloud -> ReconstructMesh -> RefineMesh, all on the
# CPU with their default options. The meshes stay in OpenMVG's frame: the
# evaluation carries them by the fit of the same model's cameras to the
# ground truth (mesh_evaluator --alignment_model_path OPENMVG/colmap).
#
# Usage: bash scripts/baselines/openmvs_mesh.sh --openmvg DIR --output DIR
#          [--prefix DIR] [--threads N]
#   openmvg  the output folder of scripts/baselines/openmvg_sfm.sh
#   output   written afresh: scene.mvs, undistorted/, scene_dense.mvs and
#            .ply (dense cloud), scene_mesh.ply, scene_refined.ply,
#            log.txt, time.txt (wall seconds per step)
#   prefix   where scripts/baselines/build.sh installed OpenMVG and OpenMVS
#            (default bench_work/baselines)
# Each step logs its progress at least once a minute (the elapsed time).
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$(pwd)
OPENMVG_OUT=""
OUTPUT=""
PREFIX="${ROOT}/bench_work/baselines"
THREADS=$(nproc)
while [[ $# -gt 0 ]]; do
  case "$1" in
    --openmvg) OPENMVG_OUT=$2; shift 2 ;;
    --output) OUTPUT=$2; shift 2 ;;
    --prefix) PREFIX=$2; shift 2 ;;
    --threads) THREADS=$2; shift 2 ;;
    -h|--help) sed -n 2,18p "$0"; exit 0 ;;
    *) echo "openmvs_mesh.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
fail() { echo "openmvs_mesh: $*" >&2; exit 1; }
log() { echo "[openmvs_mesh $(date +%H:%M:%S)] $*"; }
[[ -n "${OPENMVG_OUT}" && -n "${OUTPUT}" ]] || fail "--openmvg and --output are required"
SFM_DATA="${OPENMVG_OUT}/reconstruction/sfm_data.bin"
[[ -f "${SFM_DATA}" ]] || fail "no ${SFM_DATA} (run scripts/baselines/openmvg_sfm.sh first)"
MVG_BIN="${PREFIX}/openmvg/bin"
MVS_BIN="${PREFIX}/openmvs/bin/OpenMVS"
[[ -x "${MVG_BIN}/openMVG_main_openMVG2openMVS" ]] || fail "no OpenMVG in ${MVG_BIN}"
[[ -x "${MVS_BIN}/DensifyPointCloud" ]] ||
  fail "no OpenMVS in ${MVS_BIN} (bash scripts/baselines/build.sh --prefix ${PREFIX} ...)"

rm -rf "${OUTPUT}"
mkdir -p "${OUTPUT}"
OUTPUT=$(cd "${OUTPUT}" && pwd)
LOG="${OUTPUT}/log.txt"
: > "${OUTPUT}/time.txt"
source "${ROOT}/scripts/progress_lib.sh"
step() {  # step NAME CMD...: runs CMD into the log with a progress line a minute
  local name=$1; shift
  log "${name}"
  echo "== ${name}: $*" >> "${LOG}"
  local start=${SECONDS}
  run_with_progress "${name}" "${LOG}" "$@" ||
    { tail -n 20 "${LOG}" >&2; fail "${name} failed (log ${LOG})"; }
  echo "${name} $(( SECONDS - start ))" >> "${OUTPUT}/time.txt"
}

step import "${MVG_BIN}/openMVG_main_openMVG2openMVS" -i "${SFM_DATA}" \
  -o "${OUTPUT}/scene.mvs" -d "${OUTPUT}/undistorted" -n "${THREADS}"
# OpenMVS writes its own logs into the working folder.
cd "${OUTPUT}"
step densify "${MVS_BIN}/DensifyPointCloud" -i scene.mvs -o scene_dense.mvs \
  -w "${OUTPUT}" --max-threads "${THREADS}"
step mesh "${MVS_BIN}/ReconstructMesh" -i scene_dense.mvs -o scene_mesh.mvs \
  -w "${OUTPUT}" --max-threads "${THREADS}"
step refine "${MVS_BIN}/RefineMesh" -i scene_dense.mvs -m scene_mesh.ply \
  -o scene_refined.mvs -w "${OUTPUT}" --max-threads "${THREADS}"
for f in scene_dense.ply scene_mesh.ply scene_refined.ply; do
  [[ -s "${f}" ]] || fail "OpenMVS wrote no ${OUTPUT}/${f} (log ${LOG})"
done
log "done: $(awk '{s += $2} END {print s}' "${OUTPUT}/time.txt") s; meshes ${OUTPUT}/scene_mesh.ply, ${OUTPUT}/scene_refined.ply"
