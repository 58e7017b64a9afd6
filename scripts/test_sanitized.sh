#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer + UndefinedBehaviorSanitizer in
# build-asan (-O1 -g1, benchmarks off) and runs CTest without the heavy
# pipeline/automatic_reconstructor test. Any sanitizer report fails its test
# (UBSan halts on the first error; ASan always does). Prints the build and
# test wall times and the tests with sanitizer reports.
#
# Usage: scripts/test_sanitized.sh [ctest args...]   (e.g. -R mvs/)
# Environment: ASAN_BUILD_DIR (default build-asan), ASAN_JOBS (build and
# ctest parallelism, default 2), ASAN_TARGETS (build only these targets),
# ASAN_TESTS (a CTest regex: build only the executables of the matching
# tests, test_<module>_<name> for the test <module>/<name>, and run only
# them; scripts/ci_extra.sh uses it), CC / CXX (default clang-14 /
# clang++-14 when installed, as scripts/install_deps.sh does, else gcc / g++:
# clang builds the sanitized tests in about two thirds of gcc's CPU time).
# Builds take /tmp/colmap-lidar-build.lock, like every build of this checkout.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${ASAN_BUILD_DIR:-build-asan}
jobs=${ASAN_JOBS:-2}
lock=/tmp/colmap-lidar-build.lock
if [ -z "${CC:-}" ] && [ -z "${CXX:-}" ] && command -v clang++-14 >/dev/null; then
  export CC=clang-14 CXX=clang++-14
fi
# float-cast-overflow is part of clang's -fsanitize=undefined but not gcc's.
sanitize="-fsanitize=address,undefined,float-cast-overflow -fno-omit-frame-pointer"
# -g1: line tables (clang: -gline-tables-only), all that the sanitizers'
# stack traces print; full debug information costs compile and link time.
flags="-O1 -g1 -DNDEBUG $sanitize"

# Ninja, where installed, for a new build directory: CMake's Makefiles build
# the targets named by --target one after another (.NOTPARALLEL), which left
# one of the two cores idle most of the time; Ninja builds them together.
generator=()
if [ ! -f "$build_dir/CMakeCache.txt" ] && command -v ninja >/dev/null; then
  generator=(-G Ninja)
fi

start=$(date +%s)
mkdir -p "$build_dir"
flock "$lock" cmake "${generator[@]}" -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="$flags" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="$sanitize" -DCMAKE_SHARED_LINKER_FLAGS="$sanitize" \
  -DCOLMAP_LIDAR_BUILD_BENCHMARKS=OFF -DCOLMAP_LIDAR_BUILD_TESTS=ON \
  > "$build_dir/configure.log" 2>&1 || { cat "$build_dir/configure.log"; exit 1; }
# ASAN_TARGETS: build only these targets (e.g. the tests of a few modules,
# then pass the matching -R to ctest); default: everything.
# ASAN_TESTS: the targets are those of the tests that match the regex.
ctest_select=()
if [ -n "${ASAN_TESTS:-}" ]; then
  ctest_select=(-R "$ASAN_TESTS")
  names=$(cd "$build_dir" && ctest -N -R "$ASAN_TESTS" | sed -n 's/^ *Test *#[0-9]*: //p')
  [ -n "$names" ] || { echo "test_sanitized: no test matches '$ASAN_TESTS'" >&2; exit 2; }
  # Tests without an executable of their own (layers/includes) need none;
  # a target test_x has the directory CMakeFiles/test_x.dir (either generator).
  for n in $names; do
    t="test_${n//\//_}"
    if [ -n "$(find "$build_dir" -type d -name "$t.dir" -print -quit)" ]; then
      ASAN_TARGETS="${ASAN_TARGETS:-} $t"
    fi
  done
  echo "test_sanitized: $(echo "$names" | wc -l) tests match '$ASAN_TESTS'"
fi
flock "$lock" cmake --build "$build_dir" -j"$jobs" ${ASAN_TARGETS:+--target $ASAN_TARGETS} \
  > "$build_dir/sanitized_build.log" 2>&1 ||
  { tail -n 60 "$build_dir/sanitized_build.log"; exit 1; }
built=$(date +%s)
echo "test_sanitized: build $(( built - start )) s"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
if [ -f tests/sanitizer/lsan.supp ]; then
  export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/sanitizer/lsan.supp:print_suppressions=0}
fi
status=0
(cd "$build_dir" && ctest --output-on-failure -j"$jobs" --timeout 1800 \
   -E '^pipeline/automatic_reconstructor$' "${ctest_select[@]}" "$@") || status=$?
echo "test_sanitized: tests $(( $(date +%s) - built )) s"
log="$build_dir/Testing/Temporary/LastTest.log"
if [ -f "$log" ] && grep -qE 'runtime error:|==[0-9]+==ERROR' "$log"; then
  echo "test_sanitized: sanitizer reports:"
  grep -E 'runtime error:|==[0-9]+==ERROR|SUMMARY: ' "$log" | sort | uniq -c | head -40
  status=1
fi
exit $status
