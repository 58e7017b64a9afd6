// The subcommands of the colmap-lidar executable, in COLMAP's manner
// (src/colmap/exe/colmap.cc): a table of (name, RunX, description). Each
// RunX(argc, argv) gets argv[0] = the subcommand name, declares its options
// with an OptionManager, parses, checks paths and calls one typed library
// function. It returns the process exit code; it may throw
// colmap_lidar::Error, which main() turns into "ERROR: <message>" and exit
// code 1.
//
// To add a command: declare its RunX below, add one row to the table in
// commands.cc, and put RunX in exe/<topic>_commands.cc (listed in
// exe/CMakeLists.txt). Add configs/<name>.ini with all its options
// (`colmap-lidar <name> --check_options` prints them); tests/cli_test.cc
// checks that every preset parses.
#pragma once

#include <vector>

namespace colmap_lidar {

struct Command {
  const char* name;
  int (*run)(int argc, char** argv);
  // One line, shown by `colmap-lidar help`.
  const char* description;
  // The command splits its work over the ranks of an mpirun / srun job
  // (colmap_ext/util/process_group.h); the others refuse to run on more
  // than one rank.
  bool distributed = false;
};

// All commands, in the order `colmap-lidar help` lists them.
const std::vector<Command>& Commands();

// Returns nullptr when there is no command of that name.
const Command* FindCommand(const char* name);

// colmap_lidar.cc
int RunHelp(int argc, char** argv);
int RunVersion(int argc, char** argv);

// dataset_commands.cc
int RunLidarImporter(int argc, char** argv);

// synth_commands.cc
int RunSynthesize(int argc, char** argv);

// line_commands.cc
int RunLineExtractor(int argc, char** argv);
int RunLineExporter(int argc, char** argv);

// matching_commands.cc
int RunLineMatcher(int argc, char** argv);

// eval_commands.cc
int RunPoseEvaluator(int argc, char** argv);
int RunMeshEvaluator(int argc, char** argv);
int RunLineEvaluator(int argc, char** argv);
int RunDepthEvaluator(int argc, char** argv);
int RunRealDataEvaluator(int argc, char** argv);

// mvs_commands.cc (the library functions RunLidarFuser and
// RunLidarPatchMatchStereo do the work).
int RunLidarFuserCommand(int argc, char** argv);
int RunLidarPatchMatchStereoCommand(int argc, char** argv);

// mesh_commands.cc
int RunLidarDelaunayMesher(int argc, char** argv);

// odometry_commands.cc
int RunLidarOdometryCommand(int argc, char** argv);

// sfm_commands.cc
int RunLineBundleAdjuster(int argc, char** argv);
int RunLidarMapperCommand(int argc, char** argv);

// pipeline_commands.cc
int RunAutomaticReconstructorCommand(int argc, char** argv);
int RunReportCommand(int argc, char** argv);

}  // namespace colmap_lidar
