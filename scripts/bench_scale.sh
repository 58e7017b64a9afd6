#!/usr/bin/env bash
# The scale benchmark (issue 19): the whole pipeline (`colmap-lidar
# automatic_reconstructor`, default options) on the bent street of the
# matrix made longer, the same walk at the same frame spacing, at several
# frame counts; wall, CPU and peak memory per stage from each run's
# pipeline/stages.json, and each stage's growth exponent between
# consecutive sizes (scripts/scale_table.py -> <work>/scale.md).
#
# The street: `synthesize --Synthesis.preset street_bent` (848x480, 64-ring
# LIDAR, the synthesizer's defaults) with --Synthesis.length_factor f chosen
# so that N frames keep the spacing of 60 frames on the preset's 70 m walk
# (the walk is 90 f - 20 m long: f = (70 N / 60 + 20) / 90), one survey
# station every 18 m along it.
#
# Usage: bash scripts/bench_scale.sh [--work DIR] [--frames 60,200,600]
#          [--threads N] [-- extra automatic_reconstructor options]
#   work    results: DIR/N/{dataset,ws,synthesize.log,pipeline.log,time.txt}
#           (default bench_work/scale); a finished size is kept, and an
#           interrupted one resumes at its first unfinished stage
#   frames  frame counts, ascending (default 60,200,600)
#   threads threads of every stage (default: all cores)
# COLMAP_LIDAR_BIN selects colmap-lidar (default build/colmap-lidar). While
# a step runs, a line per minute gives its time and last log line
# (scripts/progress_lib.sh); the logs of a resumed size are appended to.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
BIN="${COLMAP_LIDAR_BIN:-${ROOT}/build/colmap-lidar}"
PY=/usr/bin/python3
WORK="${ROOT}/bench_work/scale"
FRAMES="60,200,600"
THREADS=-1
EXTRA=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --work) WORK=$2; shift 2 ;;
    --frames) FRAMES=$2; shift 2 ;;
    --threads) THREADS=$2; shift 2 ;;
    --) shift; EXTRA=("$@"); break ;;
    -h|--help) sed -n 2,24p "$0"; exit 0 ;;
    *) echo "bench_scale.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
fail() { echo "bench_scale: $*" >&2; exit 1; }
log() { echo "[bench_scale $(date +%H:%M:%S)] $*"; }
[[ -x "${BIN}" ]] || fail "no colmap-lidar binary at ${BIN} (build first, or set COLMAP_LIDAR_BIN)"
[[ -x /usr/bin/time ]] || fail "/usr/bin/time is missing (Debian package: time)"
IFS=',' read -r -a SIZES <<< "${FRAMES}"
for n in "${SIZES[@]}"; do
  [[ "${n}" =~ ^[1-9][0-9]*$ ]] || fail "--frames: '${n}' is not a positive integer"
done
mkdir -p "${WORK}"

source "${ROOT}/scripts/progress_lib.sh"

for n in "${SIZES[@]}"; do
  dir="${WORK}/${n}"
  if [[ -f "${dir}/done" ]]; then
    log "${n} frames: done before, kept"
    continue
  fi
  mkdir -p "${dir}"
  read -r factor stations < <("${PY}" -c "
import math
n = ${n}
f = max(1.0, (70.0 * n / 60.0 + 20.0) / 90.0)
leg = 45.0 * f
# The stations every 18 m from 9 m inside each end (scene_street_bent.cc).
print('%.6f' % f, 4 if f == 1.0 else int(math.floor((2 * leg - 18.0) / 18.0 + 1e-9)) + 1)")
  if [[ ! -f "${dir}/dataset.done" ]]; then
    log "${n} frames: synthesize (length_factor ${factor}, ${stations} survey stations)"
    rm -rf "${dir}/dataset"
    rm -f "${dir}/synthesize.log"
    run_with_progress "${n} frames: synthesize" "${dir}/synthesize.log" "${BIN}" synthesize --output_path "${dir}/dataset" \
      --Synthesis.preset street_bent --Synthesis.num_frames "${n}" \
      --Synthesis.length_factor "${factor}" \
      --Synthesis.survey_num_stations "${stations}" \
      --Synthesis.num_threads "${THREADS}" ||
      fail "${n} frames: synthesize failed, see ${dir}/synthesize.log"
    touch "${dir}/dataset.done"
  fi
  # An interrupted run resumes at its first unfinished stage (the pipeline's
  # own stage records); time.txt then covers the resumed part only.
  log "${n} frames: automatic_reconstructor"
  run_with_progress "${n} frames: automatic_reconstructor" "${dir}/pipeline.log" /usr/bin/time -v -o "${dir}/time.txt" \
    "${BIN}" automatic_reconstructor --dataset_path "${dir}/dataset" \
    --workspace_path "${dir}/ws" \
    --AutomaticReconstruction.num_threads "${THREADS}" "${EXTRA[@]}" ||
    fail "${n} frames: automatic_reconstructor failed, see ${dir}/pipeline.log"
  touch "${dir}/done"
  log "${n} frames: $(grep -m1 'Elapsed (wall' "${dir}/time.txt" | sed 's/.*: //') wall"
done
"${PY}" scripts/scale_table.py --work "${WORK}" --frames "${FRAMES}" | tee "${WORK}/scale.md"
