#!/usr/bin/env bash
# A/B of the dense stages on a finished benchmark matrix
# (scripts/bench_matrix.sh): re-runs the stages from --from (default mesh)
# to evaluate of run 1 of each cell with the given binary and options, on a
# copy of the workspace (hard links; every stage writes new files and
# renames, so the links are never written through), without the LIDAR-only
# baseline, and prints per cell the mesh figures (and, from dense or
# patch_match on, the depth maps') of the variant beside the run's own and
# its mesh without line samples (matrix/nolines_eval). The stages before
# --from are not re-run: the variant works on the same poses and lines.
#
# Usage: bash scripts/bench_remesh.sh --work DIR --name NAME [--cells a,b]
#          [--kitti DIR] [--from dense|patch_match|fusion|mesh]
#          [-- automatic_reconstructor options...]
#   work   the matrix's work folder (--work of bench_matrix.sh)
#   name   the variant's folder under each cell (DIR/CELL/remesh/NAME)
#   cells  default: every cell of the work folder with a finished run 1
#   kitti  the KITTI recording of the matrix's kitti cell (else it is skipped)
#   from   the first stage re-run (its outputs and the later ones are removed)
# COLMAP_LIDAR_BIN selects the binary (default build/colmap-lidar).
set -euo pipefail
cd "$(dirname "$0")/.."
TOOL=bench_remesh
HELP_LINES=2,20
ALLOW_KITTI=1
source scripts/matrix_variant_lib.sh
FROM=mesh
args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --from) FROM=$2; shift 2 ;;
    --) args+=("$@"); break ;;
    *) args+=("$1"); shift ;;
  esac
done
case "${FROM}" in
  dense|patch_match|fusion|mesh) ;;
  *) echo "${TOOL}: --from must be dense, patch_match, fusion or mesh" >&2; exit 2 ;;
esac
variant_parse_args "${args[@]}"
if [[ -z "${CELLS}" ]]; then
  CELLS=$(cd "${WORK}" && for d in */run1/ws/pipeline/mesh.done; do echo "${d%%/*}"; done | paste -sd, -)
fi

IFS=, read -r -a SELECTED <<< "${CELLS}"
for cell in "${SELECTED[@]}"; do
  run="${WORK}/${cell}/run1"
  if [[ "${cell}" == kitti ]]; then
    [[ -n "${KITTI}" ]] || { log "${cell}: skipped (no --kitti DIR)"; continue; }
    dataset=$(cd "${KITTI}" && pwd)
  else
    dataset="${WORK}/${cell}/dataset"
  fi
  [[ -f "${run}/ws/pipeline/mesh.done" ]] || { log "${cell}: no finished run 1; skipped"; continue; }
  out="${WORK}/${cell}/remesh/${NAME}"
  variant_copy_run1 "${run}" "${out}"
  rm -f "${out}/ws/dense/meshed-delaunay.ply"
  rm -f "${out}"/ws/pipeline/{mesh,evaluate,report}.done
  if [[ "${FROM}" != mesh ]]; then
    rm -rf "${out}/ws/dense/stereo/fusion_masks"
    rm -f "${out}"/ws/dense/fused.ply{,.vis} "${out}/ws/pipeline/fusion.done"
  fi
  if [[ "${FROM}" == dense ]]; then
    # The whole dense workspace (undistorted images, LIDAR fusion) again.
    rm -rf "${out}/ws/dense"
    rm -f "${out}"/ws/pipeline/{dense,patch_match}.done
  fi
  if [[ "${FROM}" == patch_match ]]; then
    rm -f "${out}"/ws/dense/stereo/{depth,normal}_maps/*.bin
    rm -f "${out}"/ws/dense/stereo/consistency_graphs/*
    rm -f "${out}/ws/pipeline/patch_match.done"
  fi
  log "${cell}: ${FROM} to evaluate"
  start=$(date +%s)
  "${BIN}" automatic_reconstructor --workspace_path "${out}/ws" \
    --dataset_path "${dataset}" --AutomaticReconstruction.stages "${FROM}:evaluate" \
    --AutomaticReconstruction.evaluate_lidar_baseline 0 "${EXTRA_ARGS[@]}" > "${out}/log" 2>&1 \
    || { log "${cell}: failed (see ${out}/log)"; continue; }
  log "${cell}: done in $(( $(date +%s) - start )) s"
done
/usr/bin/python3 - "${WORK}" "${NAME}" "${SELECTED[@]}" <<'PY'
import json, os, sys
work, name, cells = sys.argv[1], sys.argv[2], sys.argv[3:]
def load(path):
    return json.load(open(path)) if os.path.exists(path) else None
def edge(j):
    return j["edge_region"]["precision"][1] if j and "edge_region" in j else float("nan")
def depth(cell_ws):
    j = load(os.path.join(cell_ws, "eval/depth_maps.json"))
    g = j["overall"].get("geometric") if j else None
    return f"{100 * g['coverage']:.1f} / {100 * g['within_5cm']:.1f}" if g else "-"
print(f"| cell | F@0.02 / 0.05 / 0.1, {name} | run 1 | no lines | edge-region precision @0.05, {name} | run 1 | no lines | depth coverage / within 5 cm %, {name} | run 1 |")
print("|---|---|---|---|---|---|---|---|---|")
for cell in cells:
    base = os.path.join(work, cell, "run1")
    new = load(os.path.join(work, cell, "remesh", name, "ws/eval/mesh_ours.json"))
    old = load(os.path.join(base, "ws/eval/mesh_ours.json"))
    nol = load(os.path.join(base, "matrix/nolines_eval/mesh_ours.json"))
    if new is None:
        continue
    f = lambda j: " / ".join(f"{x:.3f}" for x in j["fscore"][:3]) if j else "-"
    print(f"| {cell} | {f(new)} | {f(old)} | {f(nol)} | {edge(new):.4f} | {edge(old):.4f} | {edge(nol):.4f} "
          f"| {depth(os.path.join(work, cell, 'remesh', name, 'ws'))} | {depth(os.path.join(base, 'ws'))} |")
PY
