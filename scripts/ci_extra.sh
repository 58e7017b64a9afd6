#!/usr/bin/env bash
# CI, after scripts/test.sh (.ci/run calls both): the robustness checks of
# issue 18 that fit CI's budget.
#  1. AddressSanitizer + UndefinedBehaviorSanitizer run of the unit tests of
#     every reader of outside data and what they stand on: all of colmap_ext
#     (util, scene, model, database, mvs, runner), lidar/scan_io, dataset/*,
#     eval/segment_io and exe/option_manager (scripts/test_sanitized.sh,
#     clang-14, build-asan). The whole suite under ASan does not fit CI's 90
#     minutes next to the plain build and test run; run it locally with
#     `bash scripts/test_sanitized.sh`.
#  2. A short fuzz run of every fuzz target (scripts/fuzz.sh, clang-14,
#     build-fuzz), CI_FUZZ_SECONDS each (default 20).
# Both steps always run; the exit code is non-zero when either fails (a
# failing test, a sanitizer report, a fuzz finding or a build error).
# Measured cost: tests/fuzz/README.md, section "In CI".
#
# Usage: scripts/ci_extra.sh
# Environment: CI_ASAN_TESTS (the CTest regex of step 1), CI_FUZZ_SECONDS.
set -uo pipefail
cd "$(dirname "$0")/.."
asan_tests=${CI_ASAN_TESTS:-'^(util|scene|model|database|mvs|runner)/|^lidar/scan_io$|^dataset/|^eval/segment_io$|^exe/option_manager$'}
fuzz_seconds=${CI_FUZZ_SECONDS:-20}

failed=()
start=$(date +%s)
echo "ci_extra: sanitizer tests ($asan_tests)"
ASAN_TESTS="$asan_tests" bash scripts/test_sanitized.sh || failed+=(sanitizer)
mid=$(date +%s)
echo "ci_extra: sanitizer step $(( mid - start )) s"

echo "ci_extra: fuzzing every target for $fuzz_seconds s"
bash scripts/fuzz.sh "$fuzz_seconds" || failed+=(fuzz)
echo "ci_extra: fuzz step $(( $(date +%s) - mid )) s"

if [ ${#failed[@]} -ne 0 ]; then
  echo "ci_extra: FAILED: ${failed[*]}"
  exit 1
fi
echo "ci_extra: sanitizer tests and fuzzing clean"
