#!/usr/bin/env bash
# Accuracy benchmark of the line detection module (paper section III-B) on
# the default synthetic scene with ground-truth poses:
#   1. `colmap-lidar synthesize` (default preset, N frames), unless an
#      existing dataset is given with --dataset;
#   2. import it with the ground-truth poses as the priors (so that
#      sparse/prior is the ground-truth model); the dataset itself is not
#      modified: a work copy links its files and replaces poses_prior.txt;
#   3. `line_extractor` on all frames, `line_exporter` into the world frame;
#   4. `line_evaluator` against ground_truth/crease_edges.txt;
#   5. scripts/observed_crease_edges.py: the crease edges observed by both
#      sensors (midpoint seen in a ground-truth depth map and inside the
#      LIDAR's vertical field of view), and line_evaluator against them.
# Prints the share of 3D segment length within 1/2/5/10 cm of a crease edge,
# the share of segments entirely within 5 cm (target: >= 90%), the length
# recall of all crease edges and of those observed by both sensors, the
# segments and milliseconds per frame, and writes a Markdown table
# (<work_dir>/lines_table.md) for docs/benchmarks/lines.md.
#
# Usage: scripts/bench_lines.sh [--build_dir DIR] [--dataset PATH]
#          [--num_frames N] [--work_dir DIR] [-- extra line_extractor options]
# Also times a one-thread extraction run (CPU and wall seconds per frame,
# everything included).
#   build_dir defaults to build, num_frames (synthesis only) to 20, work_dir
#   to bench_work/lines in the checkout (a re-run reuses its synthesised
#   dataset when the frame count matches). The old positional form
#   `bench_lines.sh [build_dir] [num_frames] [work_dir]` still works.
set -euo pipefail

BUILD_DIR=build
NUM_FRAMES=20
WORK_DIR=""
SOURCE_DATASET=""
EXTRA_OPTIONS=()
POSITIONAL=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build_dir) BUILD_DIR=$2; shift 2 ;;
    --dataset) SOURCE_DATASET=$2; shift 2 ;;
    --num_frames) NUM_FRAMES=$2; shift 2 ;;
    --work_dir) WORK_DIR=$2; shift 2 ;;
    --) shift; EXTRA_OPTIONS=("$@"); break ;;
    -h|--help) sed -n '2,27p' "$0"; exit 0 ;;
    *) POSITIONAL+=("$1"); shift ;;
  esac
done
[[ ${#POSITIONAL[@]} -ge 1 ]] && BUILD_DIR=${POSITIONAL[0]}
[[ ${#POSITIONAL[@]} -ge 2 ]] && NUM_FRAMES=${POSITIONAL[1]}
[[ ${#POSITIONAL[@]} -ge 3 ]] && WORK_DIR=${POSITIONAL[2]}
BIN="${BUILD_DIR}/colmap-lidar"
[[ -x "${BIN}" ]] || { echo "ERROR: ${BIN} not found; build first" >&2; exit 1; }
SCRIPT_DIR=$(cd "$(dirname "$0")" && pwd)
SOURCE_DIR=$(cd "${SCRIPT_DIR}/.." && pwd)
WORK_DIR=${WORK_DIR:-${SOURCE_DIR}/bench_work/lines}

mkdir -p "${WORK_DIR}"
WORK_DIR=$(cd "${WORK_DIR}" && pwd)
DATASET="${WORK_DIR}/dataset"
WORKSPACE="${WORK_DIR}/workspace"
LOG="${WORK_DIR}/log.txt"
: > "${LOG}"

if [[ -z "${SOURCE_DATASET}" ]]; then
  SOURCE_DATASET="${WORK_DIR}/synthesized"
  if [[ ! -f "${SOURCE_DATASET}/poses_gt.txt" ]] ||
     [[ "$(ls "${SOURCE_DATASET}/images" | wc -l)" != "${NUM_FRAMES}" ]]; then
    echo "== Synthesising ${NUM_FRAMES} frames into ${SOURCE_DATASET}"
    "${BIN}" synthesize --output_path "${SOURCE_DATASET}" \
      --Synthesis.num_frames "${NUM_FRAMES}" --Synthesis.overwrite 1 >> "${LOG}" 2>&1
  fi
fi
SOURCE_DATASET=$(cd "${SOURCE_DATASET}" && pwd)
for f in calibration.yaml poses_gt.txt ground_truth/crease_edges.txt; do
  [[ -f "${SOURCE_DATASET}/${f}" ]] ||
    { echo "ERROR: ${SOURCE_DATASET}/${f} not found" >&2; exit 1; }
done
NUM_FRAMES=$(ls "${SOURCE_DATASET}/images" | wc -l)
# The dataset as lines_table.md names it: relative to the checkout, or its
# base name when it lies outside (no path of this machine in the docs).
DATASET_LABEL=$(realpath --relative-base="${SOURCE_DIR}" "${SOURCE_DATASET}")
[[ "${DATASET_LABEL}" == /* ]] &&
  DATASET_LABEL="$(basename "${SOURCE_DATASET}") (outside the checkout)"

# The work dataset links the source's files; its priors are the ground
# truth, so sparse/prior is the ground-truth model the segments are placed
# with.
rm -rf "${DATASET}"
mkdir -p "${DATASET}"
for f in calibration.yaml images lidar ground_truth; do
  ln -s "${SOURCE_DATASET}/${f}" "${DATASET}/${f}"
done
cp "${SOURCE_DATASET}/poses_gt.txt" "${DATASET}/poses_gt.txt"
cp "${SOURCE_DATASET}/poses_gt.txt" "${DATASET}/poses_prior.txt"

echo "== Importing ${SOURCE_DATASET} (${NUM_FRAMES} frames)"
rm -rf "${WORKSPACE}"
"${BIN}" lidar_importer --dataset_path "${DATASET}" \
  --workspace_path "${WORKSPACE}" --LidarImport.copy_images false \
  --LidarImport.copy_scans false >> "${LOG}" 2>&1

echo "== Extracting lines"
START=$(date +%s.%N)
"${BIN}" line_extractor --database_path "${WORKSPACE}/database.db" \
  --image_path "${DATASET}/images" \
  --debug_path "${WORKSPACE}/lines_debug" "${EXTRA_OPTIONS[@]}" \
  2>> "${LOG}" | tee "${WORK_DIR}/extraction.txt" | tee -a "${LOG}"
END=$(date +%s.%N)
WALL_S=$(echo "${END} - ${START}" | bc)
echo "   wall time: ${WALL_S} s for ${NUM_FRAMES} frames (with overlays)"

# Time on one core, everything included (image and scan reading, the
# pipeline, database writes; no overlays): CPU seconds of a one-thread run,
# which a loaded machine inflates less than wall time.
/usr/bin/time -f "%U %S %e" -o "${WORK_DIR}/time_one_thread.txt" \
  "${BIN}" line_extractor --database_path "${WORKSPACE}/database.db" \
  --image_path "${DATASET}/images" --LineExtraction.num_threads 1 \
  "${EXTRA_OPTIONS[@]}" > "${WORK_DIR}/extraction_one_thread.txt" 2>> "${LOG}"
read -r USER_S SYS_S WALL1_S < "${WORK_DIR}/time_one_thread.txt"
echo "   one thread: $(echo "scale=1; 1000 * (${USER_S} + ${SYS_S}) / ${NUM_FRAMES}" | bc) ms CPU," \
  "$(echo "scale=1; 1000 * ${WALL1_S} / ${NUM_FRAMES}" | bc) ms wall per frame"

"${BIN}" line_exporter --database_path "${WORKSPACE}/database.db" \
  --input_path "${WORKSPACE}/sparse/prior" \
  --output_path "${WORKSPACE}/lines_world.ply" 2>> "${LOG}" | tee -a "${LOG}"

echo "== Evaluating against ${SOURCE_DATASET}/ground_truth/crease_edges.txt"
"${BIN}" line_evaluator --input_path "${WORKSPACE}/lines_world.ply" \
  --ground_truth_path "${SOURCE_DATASET}/ground_truth/crease_edges.txt" \
  --output_path "${WORK_DIR}/line_evaluation.json" 2>> "${LOG}" \
  | tee -a "${LOG}"

echo "== Crease edges observed by both sensors"
/usr/bin/python3 "${SCRIPT_DIR}/observed_crease_edges.py" \
  --dataset "${SOURCE_DATASET}" \
  --output "${WORK_DIR}/observed_crease_edges.txt" | tee -a "${LOG}"
"${BIN}" line_evaluator --input_path "${WORKSPACE}/lines_world.ply" \
  --ground_truth_path "${WORK_DIR}/observed_crease_edges.txt" \
  --output_path "${WORK_DIR}/line_evaluation_observed.json" 2>> "${LOG}" \
  >> "${LOG}"

/usr/bin/python3 - "${WORK_DIR}" "${NUM_FRAMES}" "${DATASET_LABEL}" <<'EOF' \
  | tee "${WORK_DIR}/lines_table.md"
import json, re, sys
work, num_frames, dataset = sys.argv[1], int(sys.argv[2]), sys.argv[3]
all_ = json.load(open(f"{work}/line_evaluation.json"))
obs = json.load(open(f"{work}/line_evaluation_observed.json"))
text = open(f"{work}/extraction.txt").read()
def find(pattern, default="?"):
    m = re.search(pattern, text)
    return m.group(1) if m else default
th = all_["thresholds_m"]
i5 = th.index(0.05)
print(f"Dataset: {dataset} ({num_frames} frames)\n")
print("| Metric | Value |")
print("|---|---|")
print(f"| 3D segments (world) | {all_['num_estimated_segments']} |")
print(f"| Segments per frame | {all_['num_estimated_segments'] / num_frames:.1f} |")
print(f"| Segments entirely within 5 cm of a crease edge | "
      f"{100 * all_['inlier_segment_share'][i5]:.1f}% |")
for t, p in zip(th, all_["length_precision"]):
    print(f"| Length precision @ {100 * t:g} cm | {100 * p:.1f}% |")
for t, r in zip(th, all_["length_recall"]):
    print(f"| Length recall @ {100 * t:g} cm, all crease edges "
          f"({all_['ground_truth_length_m']:.0f} m) | {100 * r:.1f}% |")
for t, r in zip(obs["thresholds_m"], obs["length_recall"]):
    print(f"| Length recall @ {100 * t:g} cm, edges observed by both sensors "
          f"({obs['ground_truth_length_m']:.0f} m) | {100 * r:.1f}% |")
lifted = find(r"lifted to 3D: (\d+ of \d+)")
user_s, sys_s, wall_s = (float(v) for v in
                         open(f"{work}/time_one_thread.txt").read().split())
one = open(f"{work}/extraction_one_thread.txt").read()
m = re.search(r"Time: ([0-9.]+) ms", one)
print(f"| 2D segments lifted to 3D | {lifted} |")
print(f"| Time per frame, one thread, everything included: CPU "
      f"(user + sys) | {1000 * (user_s + sys_s) / num_frames:.0f} ms |")
print(f"| Time per frame, one thread, everything included: wall | "
      f"{1000 * wall_s / num_frames:.0f} ms |")
print(f"| Time per frame, one thread, pipeline stages only (wall) | "
      f"{float(m.group(1)) if m else float('nan'):.0f} ms |")
EOF
echo "Reports: ${WORK_DIR}/line_evaluation.json," \
  "${WORK_DIR}/line_evaluation_observed.json, table:" \
  "${WORK_DIR}/lines_table.md, log: ${LOG}"
