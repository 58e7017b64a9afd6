# Sourced by scripts/bench_remesh.sh and scripts/bench_redepth.sh, the A/Bs
# on run 1 of a finished benchmark matrix: their command line and the copy of
# a cell's run 1 that a variant starts from. Before sourcing, set TOOL (the
# script's name, for messages), HELP_LINES (the sed range of its header that
# --help prints) and ALLOW_KITTI (1: accept --kitti DIR).
# variant_parse_args "$@" sets ROOT, BIN, WORK, NAME, CELLS, KITTI and
# EXTRA_ARGS (what follows --, for automatic_reconstructor).

log() { echo "[${TOOL} $(date +%H:%M:%S)] $*"; }

variant_parse_args() {
  ROOT=$(pwd)
  BIN="${COLMAP_LIDAR_BIN:-${ROOT}/build/colmap-lidar}"
  WORK=""
  NAME=""
  CELLS=""
  KITTI=""
  EXTRA_ARGS=()
  while [[ $# -gt 0 ]]; do
    case "$1" in
      --work) WORK=$2; shift 2 ;;
      --name) NAME=$2; shift 2 ;;
      --cells) CELLS=$2; shift 2 ;;
      --kitti)
        [[ "${ALLOW_KITTI}" == 1 ]] || { echo "${TOOL}: unknown argument $1" >&2; exit 2; }
        KITTI=$2; shift 2 ;;
      --) shift; EXTRA_ARGS=("$@"); break ;;
      -h|--help) sed -n "${HELP_LINES}p" "$0"; exit 0 ;;
      *) echo "${TOOL}: unknown argument $1" >&2; exit 2 ;;
    esac
  done
  [[ -n "${WORK}" && -d "${WORK}" ]] || { echo "${TOOL}: --work DIR (a matrix work folder) is required" >&2; exit 2; }
  [[ "${NAME}" =~ ^[A-Za-z0-9_.-]+$ ]] || { echo "${TOOL}: --name must be a plain folder name" >&2; exit 2; }
  [[ -x "${BIN}" ]] || { echo "${TOOL}: ${BIN} not found; build first (bash scripts/build.sh)" >&2; exit 1; }
  WORK=$(cd "${WORK}" && pwd)
}

# variant_copy_run1 RUN OUT: OUT/ws becomes a copy of RUN/ws made of hard
# links (every stage writes new files and renames them, so the links are
# never written through), but for real copies of database.db (SQLite writes
# in place) and of the pipeline's logs (appended to), and without the
# evaluation and the report. The copy is made under another name and
# renamed when complete: a copy that fails half-way (a full disk) leaves no
# OUT/ws holding the run's own evaluation, which would pass for the
# variant's.
variant_copy_run1() {
  local run=$1 out=$2
  local partial="${out}/ws.partial"
  rm -rf "${out}"
  mkdir -p "${partial}"
  cp -al "${run}/ws/." "${partial}/"
  rm -f "${partial}/database.db" && cp "${run}/ws/database.db" "${partial}/database.db"
  local log
  for log in "${partial}"/pipeline/*.log; do
    [[ -f "${log}" ]] || continue
    cp --remove-destination "${run}/ws/pipeline/$(basename "${log}")" "${log}"
  done
  rm -rf "${partial}/eval" "${partial}/report"
  mv "${partial}" "${out}/ws"
}
