# colmap_lidar_add_library(NAME name SRCS ... DEPS ...)
# One static library per module; DEPS are its public link dependencies.
function(colmap_lidar_add_library)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;DEPS" ${ARGN})
  add_library(${ARG_NAME} STATIC ${ARG_SRCS})
  target_include_directories(${ARG_NAME} PUBLIC ${CMAKE_SOURCE_DIR})
  target_link_libraries(${ARG_NAME} PUBLIC ${ARG_DEPS})
endfunction()

# colmap_lidar_add_test(NAME name MODULE module [TIMEOUT seconds] SRCS ... DEPS ...)
# One GoogleTest executable per source file; registered with CTest as
# "<module>/<name>" so that `ctest -R lidar/` runs one module. The tests get
# COLMAP_LIDAR_SHARED_DIR and COLMAP_LIDAR_SOURCE_DIR in their environment.
# TIMEOUT defaults to 600 s. Nothing is registered when tests are off (the
# fuzz and sanitizer builds), so callers never touch a test by name.
function(colmap_lidar_add_test)
  if(NOT COLMAP_LIDAR_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "NAME;MODULE;TIMEOUT" "SRCS;DEPS" ${ARGN})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 600)
  endif()
  # Development aid while several modules grow at once: skip a test whose
  # sources do not exist yet. Off by default, so CI fails on a missing file.
  if(COLMAP_LIDAR_ALLOW_MISSING_TESTS)
    foreach(src ${ARG_SRCS})
      if(NOT EXISTS "${CMAKE_CURRENT_SOURCE_DIR}/${src}")
        message(WARNING "Skipping test ${ARG_MODULE}/${ARG_NAME}: ${src} missing")
        return()
      endif()
    endforeach()
  endif()
  set(target "test_${ARG_MODULE}_${ARG_NAME}")
  add_executable(${target} ${ARG_SRCS})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS} colmap_ext_testing
                        GTest::gtest GTest::gtest_main)
  add_test(NAME "${ARG_MODULE}/${ARG_NAME}" COMMAND ${target})
  set_tests_properties("${ARG_MODULE}/${ARG_NAME}" PROPERTIES
    ENVIRONMENT "COLMAP_LIDAR_SHARED_DIR=${COLMAP_LIDAR_SHARED_DIR};COLMAP_LIDAR_SOURCE_DIR=${CMAKE_SOURCE_DIR};COLMAP_LIDAR_BINARY_DIR=${CMAKE_BINARY_DIR}"
    TIMEOUT ${ARG_TIMEOUT})
endfunction()
