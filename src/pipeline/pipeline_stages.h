// The stages of `colmap-lidar automatic_reconstructor`, in pipeline order,
// and the --stages selection ("all", one stage, or "first:last").
#pragma once

#include <string>
#include <vector>

namespace colmap_lidar {

enum class PipelineStage {
  // The built-in default scene, when no recording is given.
  kSynthesize = 0,
  // The recording into the COLMAP workspace (lidar_importer).
  kImport,
  // LIDAR odometry priors, only for images without prior poses.
  kOdometry,
  // Features, matches, lines, association, point + line adjustment
  // (lidar_mapper): sparse/refined.
  kSfm,
  // Stock image_undistorter and the fused LIDAR cloud (lidar_fuser): dense/.
  kDense,
  // LIDAR-initialised PatchMatch: dense/stereo/{depth,normal}_maps.
  kPatchMatch,
  // Stock stereo_fusion: dense/fused.ply (+ .vis).
  kFusion,
  // Delaunay meshing with LIDAR voxels and line samples:
  // dense/meshed-delaunay.ply.
  kMesh,
  // Poses and mesh against the recording's ground truth, when it has one.
  kEvaluate,
  // report/index.html.
  kReport,
};

constexpr int kNumPipelineStages = static_cast<int>(PipelineStage::kReport) + 1;

// "synthesize", "import", "odometry", "sfm", "dense", "patch_match",
// "fusion", "mesh", "evaluate", "report".
const char* PipelineStageName(PipelineStage stage);

// All stages in order.
std::vector<PipelineStage> AllPipelineStages();

// Parses "all", a stage name, or "first:last" (inclusive, either side may
// be empty for the first / last stage). Returns false for an unknown name
// or a range that runs backwards.
bool ParsePipelineStages(const std::string& text,
                         std::vector<PipelineStage>* stages);

}  // namespace colmap_lidar
