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
TOOL=bench_redepth
HELP_LINES=2,20
ALLOW_KITTI=0
source scripts/matrix_variant_lib.sh
variant_parse_args "$@"
if [[ -z "${CELLS}" ]]; then
  CELLS=$(cd "${WORK}" && for d in */run1/ws/eval/depth_maps.json; do echo "${d%%/*}"; done | paste -sd, -)
fi

IFS=, read -r -a SELECTED <<< "${CELLS}"
for cell in "${SELECTED[@]}"; do
  run="${WORK}/${cell}/run1"
  dataset="${WORK}/${cell}/dataset"
  if [[ ! -f "${run}/ws/pipeline/patch_match.done" || ! -d "${dataset}/ground_truth/depth_maps" ]]; then
    log "${cell}: no finished run 1 with ground-truth depth maps; skipped"
    continue
  fi
  out="${WORK}/${cell}/redepth/${NAME}"
  variant_copy_run1 "${run}" "${out}"
  rm -rf "${out}/ws/dense/stereo/fusion_masks"
  rm -f "${out}"/ws/dense/stereo/{depth,normal}_maps/*.geometric.bin
  rm -f "${out}"/ws/pipeline/{patch_match,fusion,mesh,evaluate,report}.done
  log "${cell}: geometric pass + depth evaluation"
  start=$(date +%s)
  { "${BIN}" automatic_reconstructor --workspace_path "${out}/ws" \
      --dataset_path "${dataset}" --AutomaticReconstruction.stages patch_match "${EXTRA_ARGS[@]}" &&
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
