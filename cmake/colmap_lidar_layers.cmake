# The layers of the tree and the check that every include runs downwards.
#
# colmap_ext/ (COLMAP interop) is the bottom, the stages of the paper in src/
# sit on it, src/sfm and src/pipeline combine the stages, src/exe (the
# command line) is the top; tests/ and benchmarks/ stand outside and may
# include anything. A file may include headers of its own layer and of lower
# layers; folders within one layer may include each other.
#
# Used twice: included by the top-level CMakeLists.txt, which runs the check
# at configure time, and as a script for the CTest test "layers/includes":
#   cmake -DCOLMAP_LIDAR_SOURCE_DIR=<source dir> -P colmap_lidar_layers.cmake

if(CMAKE_SCRIPT_MODE_FILE)
  cmake_minimum_required(VERSION 3.25)
endif()

# Lowest first; one entry per layer, its folders separated by spaces. A new
# folder under colmap_ext/ or src/ must be added here (the check fails on a
# folder that is in no layer).
set(COLMAP_LIDAR_LAYERS
  "colmap_ext/util"
  "colmap_ext/scene colmap_ext/runner"
  "colmap_ext/model colmap_ext/database"
  "colmap_ext/mvs"
  "src/lidar src/dataset src/synth src/lines src/matching src/optim src/eval src/mvs src/mesh"
  "src/sfm"
  "src/pipeline"
  "src/exe")

# Sets `out_var` to the index of the layer of `folder` (e.g. "src/lines"), or
# -1 when no layer holds it.
function(colmap_lidar_layer_of folder out_var)
  set(index 0)
  foreach(layer IN LISTS COLMAP_LIDAR_LAYERS)
    string(REPLACE " " ";" folders "${layer}")
    if(folder IN_LIST folders)
      set(${out_var} ${index} PARENT_SCOPE)
      return()
    endif()
    math(EXPR index "${index} + 1")
  endforeach()
  set(${out_var} -1 PARENT_SCOPE)
endfunction()

# Fails (FATAL_ERROR) naming every file and line under colmap_ext/ and src/
# that includes a header of a higher layer, and every folder that is in no
# layer.
function(colmap_lidar_check_layers source_dir)
  file(GLOB_RECURSE files RELATIVE "${source_dir}"
       "${source_dir}/colmap_ext/*.h" "${source_dir}/colmap_ext/*.cc"
       "${source_dir}/src/*.h" "${source_dir}/src/*.cc")
  list(SORT files)
  set(include_regex "^[ \t]*#[ \t]*include[ \t]*[\"<]((colmap_ext|src)/[^\">]*)[\">]")
  set(errors "")
  foreach(file IN LISTS files)
    string(REGEX MATCH "^[^/]+/[^/]+" folder "${file}")
    colmap_lidar_layer_of("${folder}" layer)
    if(layer EQUAL -1)
      if(NOT file MATCHES "^[^/]+/[^/]+/")
        string(APPEND errors "\n  ${file}: not inside a module folder")
      elseif(NOT "${folder}" IN_LIST unknown_folders)
        list(APPEND unknown_folders "${folder}")
        string(APPEND errors "\n  ${folder}/: in no layer of "
               "COLMAP_LIDAR_LAYERS (cmake/colmap_lidar_layers.cmake)")
      endif()
    endif()
    # The include lines only; the line numbers are looked up for offenders.
    file(STRINGS "${source_dir}/${file}" includes REGEX "${include_regex}")
    foreach(line IN LISTS includes)
      string(REGEX MATCH "${include_regex}" unused "${line}")
      set(header "${CMAKE_MATCH_1}")
      string(REGEX MATCH "^[^/]+/[^/]+" header_folder "${header}")
      colmap_lidar_layer_of("${header_folder}" header_layer)
      # colmap_ext/ never includes src/, whatever the layer list says.
      if((file MATCHES "^colmap_ext/" AND header MATCHES "^src/") OR
         (layer GREATER -1 AND header_layer GREATER layer))
        file(STRINGS "${source_dir}/${file}" all_lines)
        list(FIND all_lines "${line}" line_index)
        math(EXPR line_number "${line_index} + 1")
        string(APPEND errors "\n  ${file}:${line_number}: includes ${header} "
               "(${header_folder} is above ${folder})")
      endif()
    endforeach()
  endforeach()
  if(errors)
    message(FATAL_ERROR "Includes must run downwards (exe -> pipeline -> sfm "
            "-> stages in src/ -> colmap_ext/; layers in "
            "cmake/colmap_lidar_layers.cmake):${errors}")
  endif()
endfunction()

if(CMAKE_SCRIPT_MODE_FILE)
  if(NOT COLMAP_LIDAR_SOURCE_DIR)
    message(FATAL_ERROR "Usage: cmake -DCOLMAP_LIDAR_SOURCE_DIR=<dir> -P "
            "colmap_lidar_layers.cmake")
  endif()
  colmap_lidar_check_layers("${COLMAP_LIDAR_SOURCE_DIR}")
  message(STATUS "Includes run downwards in ${COLMAP_LIDAR_SOURCE_DIR}")
endif()
