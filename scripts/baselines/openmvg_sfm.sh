#!/usr/bin/env bash
# OpenMVG 2.1 structure from motion on a colmap-lidar recording (the
# paper's Table I baseline, issue 21), its model exported as a COLMAP text
# model that pose_evaluator and mesh_evaluator read:
#   SfMInit_ImageListing (one shared camera) -> openmvg_sfm_data.py (the
#   calibration's camera; with --priors the noisy prior centres as OpenMVG
#   pose-centre priors) -> ComputeFeatures (SIFT) -> PairGenerator
#   (exhaustive) -> ComputeMatches -> GeometricFilter (essential matrices
#   for GLOBAL, fundamental for INCREMENTAL) -> SfM (intrinsics fixed: the
#   calibration is known, as for colmap-lidar) -> openMVG2Colmap.
#
# Usage: bash scripts/baselines/openmvg_sfm.sh --dataset DIR --output DIR
#          [--engine INCREMENTAL|GLOBAL] [--priors] [--prior_sigma_m S]
#          [--describer_preset NORMAL|HIGH|ULTRA] [--prefix DIR] [--threads N]
#          [--features_from DIR]
#   dataset  a recording (docs/dataset-format.md: images/, calibration.yaml,
#            poses_prior.txt)
#   output   written afresh: sfm_data.json, matches/, reconstruction/
#            (sfm_data.bin), colmap/ (cameras.txt, images.txt, points3D.txt),
#            log.txt, time.txt (wall seconds)
#   engine   default GLOBAL (the issue's reference run); priors off by default
#   describer_preset  OpenMVG's SIFT preset, default ULTRA: NORMAL finds
#            100-150 features in a 640x480 frame of the matrix's street and
#            no pair survives the geometric filter; ULTRA (image upsampled)
#            about 2000, as many as stock COLMAP's SIFT
#   prefix   where scripts/baselines/build.sh installed OpenMVG (default
#            bench_work/baselines)
#   features_from  the output of an earlier run on the same recording and
#            preset: its SIFT features (per image, deterministic) are copied
#            and ComputeFeatures keeps them, so the runs and variants of a
#            benchmark differ only where OpenMVG is random (matching,
#            geometric filter, SfM)
set -euo pipefail
cd "$(dirname "$0")/../.."
ROOT=$(pwd)
DATASET=""
OUTPUT=""
ENGINE=GLOBAL
PRIORS=0
PRIOR_SIGMA=0.5
PREFIX="${ROOT}/bench_work/baselines"
THREADS=$(nproc)
PRESET=ULTRA
FEATURES_FROM=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --dataset) DATASET=$2; shift 2 ;;
    --output) OUTPUT=$2; shift 2 ;;
    --engine) ENGINE=$2; shift 2 ;;
    --priors) PRIORS=1; shift ;;
    --prior_sigma_m) PRIOR_SIGMA=$2; shift 2 ;;
    --prefix) PREFIX=$2; shift 2 ;;
    --threads) THREADS=$2; shift 2 ;;
    --describer_preset) PRESET=$2; shift 2 ;;
    --features_from) FEATURES_FROM=$2; shift 2 ;;
    -h|--help) sed -n 2,34p "$0"; exit 0 ;;
    *) echo "openmvg_sfm.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
fail() { echo "openmvg_sfm: $*" >&2; exit 1; }
log() { echo "[openmvg_sfm $(date +%H:%M:%S)] $*"; }
[[ -n "${DATASET}" && -n "${OUTPUT}" ]] || fail "--dataset and --output are required"
[[ -d "${DATASET}/images" ]] || fail "no images/ folder in ${DATASET}"
[[ -f "${DATASET}/calibration.yaml" ]] || fail "no calibration.yaml in ${DATASET}"
[[ "${PRESET}" == NORMAL || "${PRESET}" == HIGH || "${PRESET}" == ULTRA ]] ||
  fail "--describer_preset must be NORMAL, HIGH or ULTRA, not '${PRESET}'"
[[ "${ENGINE}" == GLOBAL || "${ENGINE}" == INCREMENTAL ]] ||
  fail "--engine must be GLOBAL or INCREMENTAL, not '${ENGINE}'"
if [[ -n "${FEATURES_FROM}" ]]; then
  [[ -f "${FEATURES_FROM}/matches/image_describer.json" ]] ||
    fail "--features_from ${FEATURES_FROM} has no matches/image_describer.json"
  FEATURES_FROM=$(cd "${FEATURES_FROM}" && pwd)
fi
BIN="${PREFIX}/openmvg/bin"
[[ -x "${BIN}/openMVG_main_SfM" ]] ||
  fail "no OpenMVG in ${BIN} (bash scripts/baselines/build.sh --prefix ${PREFIX} ...)"
DATASET=$(cd "${DATASET}" && pwd)
# The camera first: bad input fails before the output is touched.
CAMERA=$(python3 - "${DATASET}/calibration.yaml" 2> /dev/null <<'EOF'
import re, sys
block = open(sys.argv[1]).read().split("camera:", 1)[1]
get = lambda key: re.search(r"\n\s+" + key + r":\s*([^\n#]+)", block).group(1).strip()
print(get("model"), get("width"), get("height"))
EOF
) || fail "${DATASET}/calibration.yaml has no camera block with model, width and height"
read -r MODEL W H <<< "${CAMERA}"

# A fresh output: nothing of an earlier run is mixed in.
rm -rf "${OUTPUT}"
mkdir -p "${OUTPUT}/matches"
OUTPUT=$(cd "${OUTPUT}" && pwd)
LOG="${OUTPUT}/log.txt"
START=${SECONDS}
source "${ROOT}/scripts/progress_lib.sh"
step() {  # step NAME CMD...: runs CMD into the log, fails naming the step
  local name=$1; shift
  log "${name}"
  echo "== ${name}: $*" >> "${LOG}"
  run_with_progress "${name}" "${LOG}" "$@" ||
    { tail -n 20 "${LOG}" >&2; fail "${name} failed (log ${LOG})"; }
}

case "${MODEL}" in
  SIMPLE_PINHOLE|PINHOLE) CAMERA_MODEL=1 ;;
  SIMPLE_RADIAL) CAMERA_MODEL=2 ;;
  RADIAL) CAMERA_MODEL=3 ;;
  OPENCV) CAMERA_MODEL=4 ;;
  *) fail "camera model ${MODEL} of ${DATASET}/calibration.yaml has no OpenMVG equivalent" ;;
esac
# The listing needs a K; openmvg_sfm_data.py then writes the true camera.
step listing "${BIN}/openMVG_main_SfMInit_ImageListing" -i "${DATASET}/images" \
  -o "${OUTPUT}" -k "1000;0;$((W / 2));0;1000;$((H / 2));0;0;1" \
  -c "${CAMERA_MODEL}" -g 1
PRIOR_ARGS=()
[[ ${PRIORS} -eq 1 ]] && PRIOR_ARGS=(--priors --prior_sigma_m "${PRIOR_SIGMA}")
step camera python3 "${ROOT}/scripts/baselines/openmvg_sfm_data.py" \
  "${OUTPUT}/sfm_data.json" "${DATASET}" "${PRIOR_ARGS[@]}"
if [[ -n "${FEATURES_FROM}" ]]; then
  # ComputeFeatures keeps an image's .feat / .desc when both exist (no -f).
  log "features of ${FEATURES_FROM}"
  cp "${FEATURES_FROM}"/matches/image_describer.json "${FEATURES_FROM}"/matches/*.feat \
    "${FEATURES_FROM}"/matches/*.desc "${OUTPUT}/matches/"
fi
step features "${BIN}/openMVG_main_ComputeFeatures" -i "${OUTPUT}/sfm_data.json" \
  -o "${OUTPUT}/matches" -m SIFT -p "${PRESET}" -n "${THREADS}"
step pairs "${BIN}/openMVG_main_PairGenerator" -i "${OUTPUT}/sfm_data.json" \
  -o "${OUTPUT}/matches/pairs.bin" -m EXHAUSTIVE
step matches "${BIN}/openMVG_main_ComputeMatches" -i "${OUTPUT}/sfm_data.json" \
  -p "${OUTPUT}/matches/pairs.bin" -o "${OUTPUT}/matches/matches.putative.bin"
if [[ "${ENGINE}" == GLOBAL ]]; then GEOMETRY=e; else GEOMETRY=f; fi
step geometric_filter "${BIN}/openMVG_main_GeometricFilter" \
  -i "${OUTPUT}/sfm_data.json" -m "${OUTPUT}/matches/matches.putative.bin" \
  -g "${GEOMETRY}" -o "${OUTPUT}/matches/matches.${GEOMETRY}.bin"
SFM_ARGS=(-s "${ENGINE}" -i "${OUTPUT}/sfm_data.json" -m "${OUTPUT}/matches"
  -M "${OUTPUT}/matches/matches.${GEOMETRY}.bin" -o "${OUTPUT}/reconstruction" -f NONE)
[[ ${PRIORS} -eq 1 ]] && SFM_ARGS+=(-P)
step sfm "${BIN}/openMVG_main_SfM" "${SFM_ARGS[@]}"
mkdir -p "${OUTPUT}/colmap"
step export "${BIN}/openMVG_main_openMVG2Colmap" \
  -i "${OUTPUT}/reconstruction/sfm_data.bin" -o "${OUTPUT}/colmap"
echo $(( SECONDS - START )) > "${OUTPUT}/time.txt"
log "done in $(( SECONDS - START )) s: $(grep -c '\.png\|\.jpg' "${OUTPUT}/colmap/images.txt" || true) image lines in ${OUTPUT}/colmap/images.txt"
