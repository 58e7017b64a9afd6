#include "src/exe/commands.h"

#include <cstring>

namespace colmap_lidar {

const std::vector<Command>& Commands() {
  static const std::vector<Command> kCommands = {
      {"help", &RunHelp,
       "List the commands; `help <command>` lists its options."},
      {"version", &RunVersion,
       "Print the colmap-lidar version and the stock colmap version."},
      {"automatic_reconstructor", &RunAutomaticReconstructorCommand,
       "Recording -> refined poses, lines, mesh, evaluation and report."},
      {"report", &RunReportCommand,
       "HTML report (tables, plots, renderings) of a pipeline workspace."},
      {"lidar_importer", &RunLidarImporter,
       "Import a camera + LIDAR recording into a COLMAP workspace."},
      {"lidar_odometry", &RunLidarOdometryCommand,
       "Prior poses from LIDAR odometry for a workspace without priors."},
      {"synthesize", &RunSynthesize,
       "Generate a synthetic camera + LIDAR dataset with ground truth."},
      {"pose_evaluator", &RunPoseEvaluator,
       "Evaluate a sparse model's camera poses against ground-truth poses."},
      {"mesh_evaluator", &RunMeshEvaluator,
       "Evaluate a mesh or point cloud against a reference point cloud."},
      {"line_evaluator", &RunLineEvaluator,
       "Evaluate 3D line segments against ground-truth edges."},
      {"depth_evaluator", &RunDepthEvaluator,
       "Evaluate dense depth maps against ground-truth depth maps."},
      {"real_data_evaluator", &RunRealDataEvaluator,
       "Figures without ground truth: LIDAR map crispness, odometry, mesh."},
      {"line_extractor", &RunLineExtractor,
       "Detect 3D line segments per image from the image and its LIDAR scan.",
       /*distributed=*/true},
      {"line_matcher", &RunLineMatcher,
       "Associate 3D line segments across views into line tracks (CLEAR)."},
      {"line_exporter", &RunLineExporter,
       "Export the 3D line segments in a model's world frame as PLY/OBJ."},
      {"line_bundle_adjuster", &RunLineBundleAdjuster,
       "Point + line + LIDAR bundle adjustment of a model with line tracks."},
      {"lidar_mapper", &RunLidarMapperCommand,
       "Camera + LIDAR SfM: features, lines, association, adjustment loop."},
      {"lidar_fuser", &RunLidarFuserCommand,
       "Fuse all registered LIDAR scans into a voxel cloud in the dense "
       "workspace."},
      {"lidar_patch_match_stereo", &RunLidarPatchMatchStereoCommand,
       "LIDAR-initialised PatchMatch stereo writing COLMAP depth/normal maps.",
       /*distributed=*/true},
      {"lidar_delaunay_mesher", &RunLidarDelaunayMesher,
       "Delaunay + graph-cut mesh of fused visual, LIDAR and line points.",
       /*distributed=*/true},
  };
  return kCommands;
}

const Command* FindCommand(const char* name) {
  for (const Command& command : Commands()) {
    if (std::strcmp(command.name, name) == 0) {
      return &command;
    }
  }
  return nullptr;
}

}  // namespace colmap_lidar
