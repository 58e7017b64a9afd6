# Included by the top-level CMakeLists.txt when COLMAP_LIDAR_BUILD_FUZZERS is
# ON: instruments every library for libFuzzer (coverage), AddressSanitizer and
# UndefinedBehaviorSanitizer. Use a build directory of its own, configured
# with clang (scripts/fuzz.sh does: CC=clang-14 CXX=clang++-14, build-fuzz).
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "COLMAP_LIDAR_BUILD_FUZZERS needs clang (libFuzzer); "
                      "configure with CC=clang-14 CXX=clang++-14")
endif()
# Libraries get coverage instrumentation but no libFuzzer main; the fuzz
# targets add -fsanitize=fuzzer at link time (tests/fuzz/CMakeLists.txt).
# UBSan findings abort, so that libFuzzer records them as crashes.
# Line tables are all that the crash reports print; full debug information
# costs compile and link time. These options follow the build type's flags
# on the command line, so -gline-tables-only overrides RelWithDebInfo's -g.
add_compile_options(-fsanitize=fuzzer-no-link,address,undefined
                    -fno-sanitize-recover=undefined -fno-omit-frame-pointer
                    -gline-tables-only)
add_link_options(-fsanitize=address,undefined)
# The fuzz targets are registered as CTest tests fuzz/<target>.
enable_testing()
