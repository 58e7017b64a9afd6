#!/usr/bin/env bash
# Runs one libFuzzer target for SECONDS and prints one summary line:
#   <target>: <executions> executions in <seconds> s, <crashes> crash(es)
# With FUZZ_RUNS=N in the environment the run stops after N executions or
# SECONDS, whichever comes first (the benchmark: 10^6 executions per reader),
# and <seconds> is the time it took.
# The first directory receives what the run learns (new coverage); the seed
# directories are only read. A crash, a hang (> 10 s on one input), an
# out-of-memory (> 2 GB) or a sanitizer report stops the run: its input is
# saved as <work>/../artifacts/<target>-crash-<sha1> and the report is
# printed. Exit code 0 when clean, 1 on any finding, 2 on usage errors.
#
# Usage: run_fuzz_target.sh BINARY SECONDS WORK_CORPUS [SEED_DIR...]
set -uo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 BINARY SECONDS WORK_CORPUS [SEED_DIR...]" >&2
  exit 2
fi
binary=$1
seconds=$2
work=$3
shift 3
name=$(basename "$binary")
if [ ! -x "$binary" ]; then
  echo "$name: not built ($binary)" >&2
  exit 2
fi
artifacts=$(dirname "$work")/artifacts
mkdir -p "$work" "$artifacts"
seeds=()
for dir in "$@"; do
  if [ -d "$dir" ]; then seeds+=("$dir"); fi
done
log=$(dirname "$work")/$name.log

runs=()
if [ -n "${FUZZ_RUNS:-}" ]; then
  if ! [[ $FUZZ_RUNS =~ ^[1-9][0-9]*$ ]]; then
    echo "FUZZ_RUNS must be a positive integer, got '$FUZZ_RUNS'" >&2
    exit 2
  fi
  runs=(-runs="$FUZZ_RUNS")
fi
start=$(date +%s)
# Leaks count as findings; UBSan already aborts (-fno-sanitize-recover).
ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0} \
UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
  "$binary" -max_total_time="$seconds" "${runs[@]}" -timeout=10 \
  -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$artifacts/$name-" \
  "$work" "${seeds[@]}" >"$log" 2>&1
rc=$?
if [ -n "${FUZZ_RUNS:-}" ]; then seconds=$(( $(date +%s) - start )); fi

executions=$(grep -o 'stat::number_executed_units: *[0-9]*' "$log" |
             grep -o '[0-9]*$' | tail -1)
if [ -z "$executions" ]; then
  # A crash ends the run before the final statistics: take the last status
  # line ("#<count> ...").
  executions=$(grep -o '^#[0-9]*' "$log" | tr -d '#' | sort -n | tail -1)
fi
executions=${executions:-0}
crashes=0
if [ $rc -ne 0 ] || grep -qE '^==[0-9]+==ERROR|runtime error:|deadly signal|ALARM: working on the last Unit|out-of-memory' "$log"; then
  crashes=1
fi
echo "$name: $executions executions in $seconds s, $crashes crash(es)"
if [ $crashes -ne 0 ]; then
  echo "---- $name report (full log: $log)"
  grep -nE '==ERROR|runtime error|deadly signal|ALARM|out-of-memory|uncaught|SUMMARY|Test unit written|^    #[0-9]+ ' "$log" | head -40
  exit 1
fi
exit 0
