# Sourced by the benchmark scripts (scripts/baselines/, bench_scale.sh): run_with_progress LABEL
# LOG_FILE CMD... runs CMD with its output appended to LOG_FILE and, while it
# runs, prints "LABEL: N s" once a minute through the caller's log function
# (builds, OpenMVS steps and whole pipelines take minutes); returns CMD's
# exit status.
run_with_progress() {
  local label=$1 log_file=$2
  shift 2
  local start=${SECONDS} last=${SECONDS}
  "$@" >> "${log_file}" 2>&1 &
  local pid=$!
  while kill -0 "${pid}" 2> /dev/null; do
    sleep 2
    if (( SECONDS - last >= 60 )); then
      last=${SECONDS}
      log "${label}: $(( SECONDS - start )) s, $(tail -n 1 "${log_file}" | cut -c1-100)"
    fi
  done
  wait "${pid}"
}
