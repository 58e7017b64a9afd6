// Subcommand of the 3D/3D line association (paper section III-C):
// line_matcher.
#include <cstdlib>
#include <iostream>
#include <string>

#include "colmap_ext/util/logging.h"
#include "src/exe/commands.h"
#include "src/exe/option_manager.h"
#include "src/matching/line_matching_options.h"
#include "src/matching/workspace_line_matching.h"

namespace colmap_lidar {
namespace {

// Section [LineMatching]; keep configs/line_matcher.ini in step.
void AddLineMatchingOptions(LineMatchingOptions* o, OptionManager* options) {
  const std::string s = "LineMatching.";
  options->AddOption(s + "t_theta_deg", &o->t_theta_deg,
                     "Algorithm 1 t_theta: angle between the reprojected and "
                     "the detected segment, degrees, (0, 90].");
  options->AddOption(s + "t_dP_px", &o->t_dP_px,
                     "Algorithm 1 t_dP: mean endpoint to other segment's 2D "
                     "line distance, pixels, > 0.");
  options->AddOption(s + "t_dO_m", &o->t_dO_m,
                     "Algorithm 1 t_dO: midpoint difference orthogonal to "
                     "the 3D segment, metres, > 0.");
  options->AddOption(s + "t_LBD", &o->t_LBD,
                     "Algorithm 1 t_LBD: LBD Hamming distance, bits, > 0; "
                     "256 disables it.");
  options->AddOption(s + "min_overlap", &o->min_overlap,
                     "Extra criterion: overlap along the line / shorter "
                     "segment, [0, 1]; 0 disables it. Not in the paper.");
  options->AddOption(s + "max_rival_score_ratio", &o->max_rival_score_ratio,
                     "Extra criterion: drop the match when a segment side by "
                     "side with it scores within this ratio, (0, 1]; 1 "
                     "disables it. Not in the paper.");
  options->AddOption(s + "pose_sigma_t_m", &o->pose_sigma_t_m,
                     "Prior pose uncertainty: camera centre std per axis, "
                     "metres, >= 0 (0: exact poses).");
  options->AddOption(s + "pose_sigma_r_deg", &o->pose_sigma_r_deg,
                     "Prior pose uncertainty: rotation std, degrees, >= 0.");
  options->AddOption(s + "pose_uncertainty_scale", &o->pose_uncertainty_scale,
                     "Thresholds grow by this many relative-pose standard "
                     "deviations, >= 0; 0: fixed thresholds. Not in the "
                     "paper.");
  options->AddOption(s + "refine_relative_poses", &o->refine_relative_poses,
                     "With pose_sigma_* > 0: register the view pairs on "
                     "their 3D segments, correct the poses by a robust pose "
                     "graph, then match with the exact-pose thresholds "
                     "between views it connects, 0/1. Not in the paper.");
  options->AddOption(s + "relative_pose_min_inliers",
                     &o->relative_pose_min_inliers,
                     "Inlier segments a pair registration needs, >= 2.");
  options->AddOption(s + "relative_pose_inlier_angle_deg",
                     &o->relative_pose_inlier_angle_deg,
                     "Registration inlier scale: angle, degrees, > 0.");
  options->AddOption(s + "relative_pose_inlier_distance_m",
                     &o->relative_pose_inlier_distance_m,
                     "Registration inlier scale: mean endpoint to line "
                     "distance, metres, > 0.");
  options->AddOption(s + "num_visibility_samples",
                     &o->num_visibility_samples,
                     "Points sampled along a segment for the field of view "
                     "test, >= 2.");
  options->AddOption(s + "min_visible_fraction", &o->min_visible_fraction,
                     "Share of samples in the image, in front and not "
                     "hidden for a candidate view, (0, 1].");
  options->AddOption(s + "min_depth_m", &o->min_depth_m,
                     "Samples nearer to the camera are not visible, metres.");
  options->AddOption(s + "use_lidar_visibility", &o->use_lidar_visibility,
                     "Hide samples behind the candidate view's LIDAR "
                     "surface, 0/1.");
  options->AddOption(s + "visibility_cell_px", &o->visibility_cell_px,
                     "Cell of the LIDAR depth image, pixels, >= 1.");
  options->AddOption(s + "visibility_relative_tolerance",
                     &o->visibility_relative_tolerance,
                     "Occlusion tolerance relative to the LIDAR depth, >= 0.");
  options->AddOption(s + "visibility_absolute_tolerance_m",
                     &o->visibility_absolute_tolerance_m,
                     "Occlusion tolerance, metres, >= 0.");
  options->AddOption(s + "cross_check", &o->cross_check,
                     "Keep only mutual best matches, 0/1.");
  options->AddOption(s + "num_threads", &o->num_threads,
                     "Worker threads; <= 0: all cores.");
  options->AddOption(s + "use_clear", &o->use_clear,
                     "Multi-view consistency by CLEAR (else connected "
                     "components, inconsistent ones dropped), 0/1.");
  options->AddOption(s + "clear_max_component_size",
                     &o->clear.max_component_size,
                     "CLEAR: larger components are split first, >= 2.");
  options->AddOption(s + "clear_min_assignment_similarity",
                     &o->clear.min_assignment_similarity,
                     "CLEAR: observations less similar to their object stay "
                     "alone, [-1, 1].");
  options->AddOption(s + "min_track_length", &o->min_track_length,
                     "Tracks with fewer observations are dropped, >= 2.");
  options->AddCheck([o] { return o->Check(); });
}

}  // namespace

int RunLineMatcher(int argc, char** argv) {
  WorkspaceLineMatchingPaths paths;
  LineMatchingOptions matching_options;

  OptionManager options;
  options.AddRequiredOption("database_path", &paths.database_path,
                            "COLMAP database with ext_line_segments (from "
                            "line_extractor).");
  options.AddRequiredOption("input_path", &paths.input_path,
                            "Sparse model whose poses place the segments in "
                            "the world (prior or refined).");
  options.AddOption("output_path", &paths.output_path,
                    "Folder for a copy of the model with the tracks as "
                    "lines3D.bin; empty: none.");
  options.AddOption("export_tracks_path", &paths.tracks_json_path,
                    "JSON file with every track's observations; empty: "
                    "none.");
  AddLineMatchingOptions(&matching_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  const WorkspaceLineMatchingSummary summary =
      RunWorkspaceLineMatching(paths, matching_options);
  if (!summary.error.empty()) {
    LOG(ERROR) << summary.error;
    return EXIT_FAILURE;
  }
  std::cout << summary.association.Format() << std::endl;
  if (!paths.output_path.empty()) {
    std::cout << "Wrote the model with " << summary.num_model_lines3D
              << " lines3D to " << paths.output_path << std::endl;
  }
  if (!paths.tracks_json_path.empty()) {
    std::cout << "Wrote " << summary.num_exported_tracks << " tracks to "
              << paths.tracks_json_path << std::endl;
  }
  return EXIT_SUCCESS;
}

}  // namespace colmap_lidar
