#!/usr/bin/env bash
# A/B of PatchMatch's geometric pass on a finished benchmark matrix
# (scripts/bench_matrix.sh): re-runs the geometric pass of run 1 of each
# synthetic cell with the given binary and options (the photometric maps of
# the run are kept; the pass reads them), on a copy of the workspace (hard
# links; every map is written to a new file and renamed, so the links are
# never written through), evaluates the geometric depth maps against the
# cell's ground truth (colmap-lidar depth_evaluator) and prints per cell
# coverage and the shares within 5 and 2 cm beside run 1's own.
#
# Usage: bash scripts/bench_redepth.sh --work DIR --name NAME [--cells a,b]
#          [-- automatic_reconstructor options...]
#   work   the matrix's work folder (--work of bench_matrix.sh)
#   name   the variant's folder under each cell (DIR/CELL/redepth/NAME)
#   cells  default: every synthetic cell of the work folder with a finished
#          run 1
# COLMAP_LIDAR_BIN selects the binary (default build/colmap-lidar). The
# variant's workspace can then be fused, meshed and evaluated with
#   colmap-lidar automatic_reconstructor --workspace_path DIR/CELL/redepth/NAME/ws
#     --dataset_path DIR/CELL/dataset --AutomaticReconstruction.stages fusion:evaluate
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BIN="${COLMAP_LIDAR_BIN:-${ROOT}/build/colmap-lidar}"
WORK=""
NAME=""
CELLS=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --work) WORK=$2; shift 2 ;;
    --name) NAME=$2; shift 2 ;;
    --cells) CELLS=$2; shift 2 ;;
    --) shift; break ;;
    -h|--help) sed -n '2,21p' "$0"; exit 0 ;;
    *) echo "bench_redepth: unknown argument $1" >&2; exit 2 ;;
  esac
done
[[ -n "${WORK}" && -d "${WORK}" ]] || { echo "bench_redepth: --work DIR (a matrix work folder) is required" >&2; exit 2; }
[[ "${NAME}" =~ ^[A-Za-z0-9_.-]+$ ]] || { echo "bench_redepth: --name must be a plain folder name" >&2; exit 2; }
[[ -x "${BIN}" ]] || { echo "bench_redepth: ${BIN} not found; build first (bash scripts/build.sh)" >&2; exit 1; }
WORK=$(cd "${WORK}" && pwd)
if [[ -z "${CELLS}" ]]; then
  CELLS=$(cd "${WORK}" && for d in */run1/ws/eval/depth_maps.json; do echo "${d%%/*}"; done | paste -sd, -)
fi
log() { echo "[bench_redepth $(date +%H:%M:%S)] $*"; }

IFS=, read -r -a SELECTED <<< "${CELLS}"
for cell in "${SELECTED[@]}"; do
  run="${WORK}/${cell}/run1"
  dataset="${WORK}/${cell}/dataset"
  if [[ ! -f "${run}/ws/pipeline/patch_match.done" || ! -d "${dataset}/ground_truth/depth_maps" ]]; then
    log "${cell}: no finished run 1 with ground-truth depth maps; skipped"
    continue
  fi
  out="${WORK}/${cell}/redepth/${NAME}"
  rm -rf "${out}"
  mkdir -p "${out}/ws"
  cp -al "${run}/ws/." "${out}/ws/"
  rm -f "${out}/ws/database.db" && cp "${run}/ws/database.db" "${out}/ws/database.db"
  rm -rf "${out}/ws/eval" "${out}/ws/report" "${out}/ws/dense/stereo/fusion_masks"
  rm -f "${out}"/ws/dense/stereo/{depth,normal}_maps/*.geometric.bin
  rm -f "${out}"/ws/pipeline/{patch_match,fusion,mesh,evaluate,report}.done
  log "${cell}: geometric pass + depth evaluation"
  start=$(date +%s)
  { "${BIN}" automatic_reconstructor --workspace_path "${out}/ws" \
      --dataset_path "${dataset}" --AutomaticReconstruction.stages patch_match "$@" &&
    "${BIN}" depth_evaluator --workspace_path "${out}/ws/dense" \
      --dataset_path "${dataset}" --output_path "${out}/depth_maps.json" \
      --DepthEvaluation.map_types geometric; } > "${out}/log" 2>&1 \
    || { log "${cell}: failed (see ${out}/log)"; continue; }
  log "${cell}: done in $(( $(date +%s) - start )) s"
done
/usr/bin/python3 - "${WORK}" "${NAME}" "${SELECTED[@]}" <<'PY'
import json, os, sys
work, name, cells = sys.argv[1], sys.argv[2], sys.argv[3:]
def geometric(path):
    if not os.path.exists(path):
        return None
    return json.load(open(path))["overall"].get("geometric")
def cell_text(g):
    if g is None:
        return "-"
    return f"{100 * g['coverage']:.1f} % / {100 * g['within_5cm']:.1f} % / {100 * g['within_2cm']:.1f} %"
print(f"| cell | coverage / within 5 cm / within 2 cm, {name} | run 1 |")
print("|---|---|---|")
for cell in cells:
    new = geometric(os.path.join(work, cell, "redepth", name, "depth_maps.json"))
    old = geometric(os.path.join(work, cell, "run1", "ws/eval/depth_maps.json"))
    if new is None:
        continue
    print(f"| {cell} | {cell_text(new)} | {cell_text(old)} |")
PY
