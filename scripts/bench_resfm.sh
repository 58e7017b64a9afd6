#!/usr/bin/env bash
# A/B of the sfm stage (lidar_mapper) on a finished benchmark matrix
# (scripts/bench_matrix.sh): re-runs lidar_mapper with the given binary and
# options on a copy of each run's database (features and matches as the run
# had them: stock COLMAP's matcher is not deterministic, so this separates
# what the build changes from what the matcher draws), evaluates the refined
# poses against the cell's ground truth (colmap-lidar pose_evaluator, sim3
# of the centres and axes, and without alignment against the floor the
# priors leave, the run's matrix/gauge.txt) and prints per cell and run the
# variant beside the run's own figures.
#
# Usage: bash scripts/bench_resfm.sh --work DIR --name NAME [--cells a,b]
#          [--rematch] [--relines] [--line_options "OPTIONS"] [--lines_eval]
#          [-- lidar_mapper options...]
#   work   the matrix's work folder (--work of bench_matrix.sh)
#   name   the variant's folder under each run (DIR/CELL/runK/resfm/NAME)
#   cells  default: every synthetic cell of the work folder with a finished
#          run 1; every finished run of a cell is re-run
#   rematch  clear the copy's matches and two-view geometries first (the
#          features stay): lidar_mapper matches again (e.g. with
#          --LidarMapper.matcher exact)
#   relines  clear the copy's line segments, matches and tracks first:
#          lidar_mapper extracts the lines again (this binary's extraction,
#          e.g. an A/B of two builds' line extractors)
#   line_options  with --relines: the lines are extracted by
#          `colmap-lidar line_extractor OPTIONS` (any --LineExtraction.*
#          option, e.g. "--LineExtraction.plane_keep_occlusions 1") before
#          lidar_mapper, which then keeps them
#   lines_eval  also the variant's lines as the matrix measures them: its
#          segments placed with the true poses against the crease edges
#          (line_evaluator: lines_eval.json) and its line tracks on the
#          refined poses (line_matcher, scripts/eval_line_tracks.py:
#          tracks_refined_eval.txt), printed per cell beside the run's
# COLMAP_LIDAR_BIN selects the binary (default build/colmap-lidar).
set -euo pipefail
cd "$(dirname "$0")/.."
TOOL=bench_resfm
HELP_LINES=2,34
ALLOW_KITTI=0
source scripts/matrix_variant_lib.sh
# --rematch and --relines are ours (before --; what follows -- goes to
# lidar_mapper).
REMATCH=0
RELINES=0
LINE_OPTIONS=""
LINES_EVAL=0
ARGS=()
AFTER_DASHES=0
while [[ $# -gt 0 ]]; do
  arg=$1
  shift
  [[ "${arg}" == -- ]] && AFTER_DASHES=1
  if [[ ${AFTER_DASHES} -eq 0 && "${arg}" == --rematch ]]; then
    REMATCH=1
  elif [[ ${AFTER_DASHES} -eq 0 && "${arg}" == --relines ]]; then
    RELINES=1
  elif [[ ${AFTER_DASHES} -eq 0 && "${arg}" == --lines_eval ]]; then
    LINES_EVAL=1
  elif [[ ${AFTER_DASHES} -eq 0 && "${arg}" == --line_options ]]; then
    [[ $# -gt 0 ]] || { echo "${TOOL}: --line_options needs a value" >&2; exit 2; }
    LINE_OPTIONS=$1
    shift
  else
    ARGS+=("${arg}")
  fi
done
if [[ -n "${LINE_OPTIONS}" && ${RELINES} -eq 0 ]]; then
  echo "${TOOL}: --line_options needs --relines" >&2
  exit 2
fi
variant_parse_args "${ARGS[@]}"
if [[ -z "${CELLS}" ]]; then
  CELLS=$(cd "${WORK}" && for d in */run1/ws/pipeline/sfm.done; do
            [[ -f "${d%%/*}/dataset/poses_gt.txt" ]] && echo "${d%%/*}"; done | paste -sd, -)
fi

evaluate() {  # evaluate MODEL GT ALIGNMENT OUT
  "${BIN}" pose_evaluator --input_path "$1" --ground_truth_path "$2" \
    --PoseEvaluation.alignment "$3" --output_path "$4" > /dev/null 2>&1
}

# The variant's lines as bench_matrix.sh's run_extras measures a run's.
evaluate_lines() {  # evaluate_lines CELL_DIR RUN_DIR OUT
  local cell_dir=$1 run=$2 out=$3
  local edges="${cell_dir}/dataset/ground_truth/crease_edges.txt"
  local gt_model="${cell_dir}/gt/workspace/sparse/prior"
  [[ -f "${edges}" && -d "${gt_model}" ]] || return 1
  {
    "${BIN}" line_exporter --database_path "${out}/ws/database.db" \
      --input_path "${gt_model}" --output_path "${out}/lines_gt_poses.ply" &&
    "${BIN}" line_evaluator --input_path "${out}/lines_gt_poses.ply" \
      --ground_truth_path "${edges}" --output_path "${out}/lines_eval.json" &&
    cp "${out}/ws/database.db" "${out}/tracks.db" &&
    ln -sfn "${run}/ws/lidar" "${out}/lidar" &&
    "${BIN}" line_matcher --database_path "${out}/tracks.db" \
      --input_path "${out}/ws/sparse/refined" \
      --export_tracks_path "${out}/tracks_refined.json"
  } > "${out}/lines_eval.log" 2>&1
  local status=$?
  rm -f "${out}/tracks.db" "${out}/lidar"
  [[ ${status} -eq 0 ]] || return 1
  /usr/bin/python3 scripts/eval_line_tracks.py "${out}/tracks_refined.json" \
    "${cell_dir}/dataset/poses_gt.txt" "${edges}" \
    > "${out}/tracks_refined_eval.txt" 2>> "${out}/lines_eval.log"
}

IFS=, read -r -a SELECTED <<< "${CELLS}"
for cell in "${SELECTED[@]}"; do
  gt="${WORK}/${cell}/dataset/poses_gt.txt"
  [[ -f "${gt}" ]] || { log "${cell}: no ground truth; skipped"; continue; }
  for run in "${WORK}/${cell}"/run*; do
    [[ -f "${run}/ws/pipeline/sfm.done" ]] || continue
    out="${run}/resfm/${NAME}"
    rm -rf "${out}"
    mkdir -p "${out}/ws"
    cp "${run}/ws/database.db" "${out}/ws/database.db"
    if [[ ${REMATCH} -eq 1 ]]; then
      /usr/bin/python3 -c 'import sqlite3, sys
db = sqlite3.connect(sys.argv[1])
db.execute("DELETE FROM matches"); db.execute("DELETE FROM two_view_geometries")
db.commit()' "${out}/ws/database.db"
    fi
    if [[ ${RELINES} -eq 1 ]]; then
      /usr/bin/python3 -c 'import sqlite3, sys
db = sqlite3.connect(sys.argv[1])
for table in ("ext_line_track_elements", "ext_line_tracks", "ext_line_matches",
              "ext_line_segments"):
    db.execute(f"DELETE FROM {table}")
db.commit()' "${out}/ws/database.db"
    fi
    ln -s "${run}/ws/images" "${out}/ws/images"
    ln -s "${run}/ws/lidar" "${out}/ws/lidar"
    log "${cell}/$(basename "${run}"): lidar_mapper"
    start=$(date +%s)
    if [[ -n "${LINE_OPTIONS}" ]]; then
      # Word splitting of the options is intended (one string of options).
      # shellcheck disable=SC2086
      (cd "${out}/ws" && "${BIN}" line_extractor --database_path database.db \
        --image_path images ${LINE_OPTIONS}) > "${out}/line_extractor.log" 2>&1 ||
        { log "${cell}: line_extractor failed (see ${out}/line_extractor.log)"; continue; }
    fi
    { "${BIN}" lidar_mapper --workspace_path "${out}/ws" "${EXTRA_ARGS[@]}" &&
      evaluate "${out}/ws/sparse/refined" "${gt}" sim3_axes "${out}/poses_sim3_axes.json" &&
      evaluate "${out}/ws/sparse/refined" "${gt}" none "${out}/poses_none.json"; } \
      > "${out}/log" 2>&1 || { log "${cell}: failed (see ${out}/log)"; continue; }
    echo $(( $(date +%s) - start )) > "${out}/wall_seconds"
    if [[ ${LINES_EVAL} -eq 1 ]]; then
      evaluate_lines "${WORK}/${cell}" "${run}" "${out}" ||
        log "${cell}: lines evaluation failed (see ${out}/lines_eval.log)"
    fi
    log "${cell}/$(basename "${run}"): done in $(( $(date +%s) - start )) s"
  done
done
/usr/bin/python3 - "${WORK}" "${NAME}" "${SELECTED[@]}" <<'PY'
import glob, json, os, re, sys
work, name, cells = sys.argv[1], sys.argv[2], sys.argv[3:]
def load(path):
    return json.load(open(path)) if os.path.exists(path) else None
def floor(run):
    path = os.path.join(run, "matrix", "gauge.txt")
    if not os.path.exists(path):
        return None
    m = re.search(r"Oracle on .*\(6-DoF, rotation prior weight [0-9.]+ deg "
                  r"per-axis\): mean ([0-9.]+) m", open(path).read())
    return float(m.group(1)) if m else None
def text(axes, none, gauge):
    if axes is None:
        return "-"
    s = (f"{100 * axes['position_error_m']['mean']:.2f} cm / "
         f"{axes['rotation_error_deg']['mean']:.3f} deg")
    if none is not None and gauge:
        s += f" / {none['position_error_m']['mean'] / gauge:.2f}"
    return s
print(f"| cell | run | {name}: position / rotation after sim3 (centres + axes) / without alignment over the floor | the run's own |")
print("|---|---|---|---|")
for cell in cells:
    for run in sorted(glob.glob(os.path.join(work, cell, "run*"))):
        out = os.path.join(run, "resfm", name)
        if not os.path.exists(os.path.join(out, "poses_sim3_axes.json")):
            continue
        gauge = floor(run)
        new = text(load(os.path.join(out, "poses_sim3_axes.json")),
                   load(os.path.join(out, "poses_none.json")), gauge)
        old = text(load(os.path.join(run, "ws/eval/poses_refined_sim3_axes.json")),
                   load(os.path.join(run, "ws/eval/poses_refined_none.json")), gauge)
        print(f"| {cell} | {os.path.basename(run)} | {new} | {old} |")
def num_frames(cell):
    with open(os.path.join(work, cell, "dataset", "poses_gt.txt")) as stream:
        return sum(1 for line in stream if line.strip() and not line.startswith("#"))
def lines(cell, folder):
    """segments per frame, share within 5 cm, length recall at 5 cm; line
    tracks on the refined poses, pure share, not vertical share (None when
    not measured)."""
    evaluation = load(os.path.join(folder, "lines_eval.json"))
    path = os.path.join(folder, "tracks_refined_eval.txt")
    if evaluation is None or not os.path.exists(path):
        return None
    text = open(path).read()
    tracks = re.search(r"tracks (\d+)", text).group(1)
    pure = re.search(r"precision ([0-9.]+)%", text).group(1)
    not_vertical = re.search(r"not vertical ([0-9.]+)%", text).group(1)
    i = evaluation["thresholds_m"].index(0.05)
    return (f"{evaluation['num_estimated_segments'] / max(1, num_frames(cell)):.1f} / "
            f"{100 * evaluation['inlier_segment_share'][i]:.1f} % / "
            f"{100 * evaluation['length_recall'][i]:.1f} %; "
            f"{tracks} / {pure} % / {not_vertical} %")
rows = []
for cell in cells:
    for run in sorted(glob.glob(os.path.join(work, cell, "run*"))):
        new = lines(cell, os.path.join(run, "resfm", name))
        old = lines(cell, os.path.join(run, "matrix"))
        if new is not None:
            rows.append(f"| {cell} | {os.path.basename(run)} | {new} | {old or '-'} |")
if rows:
    print()
    print(f"| cell | run | {name}: segments per frame / within 5 cm of a crease / "
          "length recall at 5 cm; tracks on the refined poses / pure / not vertical "
          "| the run's own |")
    print("|---|---|---|---|")
    print("\n".join(rows))
PY
