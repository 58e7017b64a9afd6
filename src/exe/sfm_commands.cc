// Subcommands of the point + line structure from motion (paper section
// III-D and the pipeline around it): line_bundle_adjuster, lidar_mapper.
#include <cstdlib>
#include <iostream>
#include <string>

#include "colmap_ext/util/logging.h"
#include "src/dataset/importer.h"
#include "src/exe/commands.h"
#include "src/exe/option_manager.h"
#include "src/exe/option_sections.h"
#include "src/optim/line_bundle_adjustment.h"
#include "src/sfm/lidar_mapper.h"
#include "src/sfm/lidar_mapper_workspace.h"
#include "src/sfm/workspace_line_adjustment.h"

namespace colmap_lidar {

// Section [LineBundleAdjustment]; keep configs/line_bundle_adjuster.ini,
// configs/lidar_mapper.ini and configs/automatic_reconstructor.ini in step.
void AddLineBundleAdjustmentOptions(LineBundleAdjustmentOptions* o,
                                    LineBundleAdjustmentNames* n,
                                    bool with_gauge_and_priors,
                                    OptionManager* options) {
  const std::string s = "LineBundleAdjustment.";
  n->point_loss_type = LineBALossTypeName(o->point_loss_type);
  n->line_loss_type = LineBALossTypeName(o->line_loss_type);
  n->lidar_loss_type = LineBALossTypeName(o->lidar_loss_type);
  n->gauge = LineBAGaugeName(o->gauge);
  options->AddOption(s + "lambda_R", &o->lambda_R,
                     "Weight of the point reprojection errors (eq. 3), >= 0.");
  options->AddOption(s + "lambda_L", &o->lambda_L,
                     "Weight of the line reprojection errors (eq. 3), >= 0.");
  options->AddOption(s + "lambda_lidar", &o->lambda_lidar,
                     "Weight of the LIDAR line residuals (metric scale), "
                     ">= 0; 0 = eq. 3 as published. Not in the paper.");
  options->AddOption(s + "lidar_sigma_m", &o->lidar_sigma_m,
                     "LIDAR endpoint noise, metres, > 0.");
  options->AddOption(s + "point_loss_type", &n->point_loss_type,
                     "TRIVIAL, HUBER, SOFT_L1 or CAUCHY.");
  options->AddOption(s + "point_loss_scale", &o->point_loss_scale,
                     "Point loss scale, pixels, > 0.");
  options->AddOption(s + "line_loss_type", &n->line_loss_type,
                     "TRIVIAL, HUBER, SOFT_L1 or CAUCHY.");
  options->AddOption(s + "line_loss_scale", &o->line_loss_scale,
                     "Line loss scale, pixels, > 0.");
  options->AddOption(s + "lidar_loss_type", &n->lidar_loss_type,
                     "TRIVIAL, HUBER, SOFT_L1 or CAUCHY.");
  options->AddOption(s + "lidar_loss_scale", &o->lidar_loss_scale,
                     "LIDAR loss scale, in lidar_sigma_m units, > 0.");
  options->AddOption(s + "lidar_edge_weight", &o->lidar_edge_weight,
                     "Weight of the LIDAR registration edges (lidar_mapper "
                     "with init_method lidar_graph), >= 0; 0 = off. Not in "
                     "the paper.");
  options->AddOption(s + "lidar_edge_loss_scale", &o->lidar_edge_loss_scale,
                     "Cauchy loss scale of the LIDAR edges, whitened units "
                     "(sigmas), > 0.");
  options->AddOption(s + "lidar_point_weight", &o->lidar_point_weight,
                     "Weight of the LIDAR planes of the sparse points (the "
                     "LIDAR depth of the visual features; lidar_mapper), "
                     ">= 0; 0 = off. Not in the paper.");
  options->AddOption(s + "lidar_point_loss_scale", &o->lidar_point_loss_scale,
                     "Cauchy loss scale of the LIDAR planes of the points, "
                     "in plane sigmas, > 0.");
  if (with_gauge_and_priors) {
    options->AddOption(s + "prior_position_sigma_m",
                       &o->prior_position_sigma_m,
                       "Pose prior on the camera centre, metres; 0 (with "
                       "the rotation sigma) = no priors.");
    options->AddOption(s + "prior_rotation_sigma_deg",
                       &o->prior_rotation_sigma_deg,
                       "Pose prior on the orientation, degrees; 0 = off.");
    options->AddOption(s + "gauge", &n->gauge,
                       "FIX_FIRST_POSE or POSE_PRIORS (needs the prior "
                       "sigmas).");
  }
  options->AddOption(s + "refine_focal_length", &o->refine_focal_length,
                     "Refine the focal length(s), 0/1.");
  options->AddOption(s + "refine_principal_point", &o->refine_principal_point,
                     "Refine the principal point, 0/1.");
  options->AddOption(s + "refine_extra_params", &o->refine_extra_params,
                     "Refine the distortion parameters, 0/1.");
  options->AddOption(s + "refine_points", &o->refine_points,
                     "Refine the 3D points, 0/1.");
  options->AddOption(s + "refine_lines", &o->refine_lines,
                     "Refine the 3D lines, 0/1.");
  options->AddOption(s + "min_point_track_length", &o->min_point_track_length,
                     "Points seen in fewer images are left out, >= 2.");
  options->AddOption(s + "retriangulation_max_error_px",
                     &o->retriangulation_max_error_px,
                     "Re-triangulate points above this error after the "
                     "first solve, pixels; 0 = off.");
  options->AddOption(s + "min_constraints_per_image",
                     &o->min_constraints_per_image,
                     "Images with fewer scalar residuals stay fixed, >= 0.");
  options->AddOption(s + "max_num_iterations", &o->max_num_iterations,
                     "Ceres iterations per solve, > 0.");
  options->AddOption(s + "function_tolerance", &o->function_tolerance,
                     "Ceres function tolerance, > 0.");
  options->AddOption(s + "gradient_tolerance", &o->gradient_tolerance,
                     "Ceres gradient tolerance, > 0.");
  options->AddOption(s + "parameter_tolerance", &o->parameter_tolerance,
                     "Ceres parameter tolerance, > 0.");
  options->AddOption(s + "use_iterative_schur", &o->use_iterative_schur,
                     "ITERATIVE_SCHUR instead of SPARSE_SCHUR, 0/1.");
  options->AddOption(s + "num_threads", &o->num_threads,
                     "Threads; <= 0: all cores.");
  // Names are converted before the struct's own check runs.
  options->AddCheck([o, n] {
    try {
      o->point_loss_type = LineBALossTypeFromName(n->point_loss_type);
      o->line_loss_type = LineBALossTypeFromName(n->line_loss_type);
      o->lidar_loss_type = LineBALossTypeFromName(n->lidar_loss_type);
      o->gauge = LineBAGaugeFromName(n->gauge);
    } catch (const Error& error) {
      LOG(ERROR) << "LineBundleAdjustment: " << error.what();
      return false;
    }
    return o->Check();
  });
}

// Section [LidarMapper]; keep configs/lidar_mapper.ini in step.
void AddLidarMapperOptions(LidarMapperOptions* o, OptionManager* options) {
  const std::string s = "LidarMapper.";
  options->AddOption(s + "colmap_binary", &o->colmap_binary,
                     "Stock colmap binary; empty: $COLMAP_BINARY or PATH.");
  options->AddOption(s + "num_threads", &o->num_threads,
                     "Threads of every stage; <= 0: all cores.");
  options->AddOption(s + "sift_max_image_size", &o->sift_max_image_size,
                     "SiftExtraction.max_image_size, pixels, > 0.");
  options->AddOption(s + "plane_lifting", &o->extraction.planes.enabled,
                     "Line extraction also lifts the segments that no LIDAR "
                     "edge point supports with the LIDAR planes on their "
                     "two sides (as line_extractor's "
                     "--LineExtraction.plane_lifting), 0/1. Not in the "
                     "paper.");
  options->AddOption(s + "sift_max_num_features", &o->sift_max_num_features,
                     "SiftExtraction.max_num_features, > 0.");
  options->AddOption(s + "exhaustive_max_num_images",
                     &o->exhaustive_max_num_images,
                     "Exhaustive matching up to this many images, "
                     "sequential beyond, >= 0.");
  options->AddOption(s + "sequential_overlap", &o->sequential_overlap,
                     "SequentialMatching.overlap, > 0.");
  options->AddOption(s + "sequential_quadratic_overlap",
                     &o->sequential_quadratic_overlap,
                     "SequentialMatching.quadratic_overlap, 0/1.");
  options->AddOption(s + "matcher", &o->matcher,
                     "stock (colmap's exhaustive/sequential_matcher; not "
                     "repeatable) or exact (the same pairs, exact matching "
                     "and seeded verification: the same matches every run).");
  options->AddOption(s + "init_method", &o->init_method,
                     "Initial poses: mapper (stock mapper + robust sim3 to "
                     "the priors), model (init_model_path instead of the "
                     "mapper), priors, or lidar_graph (a pose graph of "
                     "LIDAR scan registrations between consecutive and "
                     "nearby frames with the priors as unary factors; not "
                     "in the paper, whose SfM is the mapper's).");
  options->AddOption(s + "lidar_edge_noise", &o->lidar_graph.edge_noise.enabled,
                     "init_method lidar_graph: measure the registration "
                     "edges' noise per sensor axis from the graph's loop "
                     "closures; add it where it exceeds the registrations' "
                     "floor sigmas (a corridor's axis), lower the floor "
                     "where the closures are cleaner, 0/1.");
  options->AddOption(s + "lidar_graph_skip_one_candidates",
                     &o->lidar_graph.skip_one_candidates,
                     "init_method lidar_graph: frame i + 2 is a loop "
                     "candidate of frame i however far apart their priors "
                     "are (its overlap decides), 0/1.");
  options->AddOption(s + "lidar_graph_loop_radius_m",
                     &o->lidar_graph.loop_radius_m,
                     "init_method lidar_graph: frames at least 2 apart whose "
                     "prior centres lie within this distance are loop "
                     "candidates, metres, >= 0 (0: none).");
  options->AddOption(s + "lidar_graph_max_loop_candidates_per_frame",
                     &o->lidar_graph.max_loop_candidates_per_frame,
                     "init_method lidar_graph: at most this many loop "
                     "candidates per frame (the nearest), >= 0.");
  options->AddOption(s + "point_plane_max_radius_range_fraction",
                     &o->point_planes.max_radius_range_fraction,
                     "LIDAR planes of the points: the scan's neighbours of a "
                     "point are searched up to this fraction of its range "
                     "(a 16-ring scanner's rings are 0.035 apart), > 0.");
  options->AddOption(s + "point_plane_max_rms_sigmas",
                     &o->point_planes.max_rms_sigmas,
                     "LIDAR planes of the points: a neighbourhood is a plane "
                     "when its rms residual is at most this many range-noise "
                     "sigmas (measured on the scans), > 0.");
  options->AddOption(s + "point_plane_max_distance_sigmas",
                     &o->point_planes.max_distance_sigmas,
                     "LIDAR planes of the points: a point farther from its "
                     "plane than this many plane sigmas gets none, > 0.");
  options->AddOption(s + "point_plane_max_range_m",
                     &o->point_planes.max_range_m,
                     "LIDAR planes of the points: none for points farther "
                     "from the camera, metres, > 0.");
  options->AddOption(s + "guided_matching", &o->guided_matching.enabled,
                     "init_method lidar_graph: after the first iteration, "
                     "match again where the adjusted poses and each image's "
                     "LIDAR depth put a keypoint's match (a ratio test among "
                     "the few keypoints there) and triangulate once more "
                     "with those matches, 0/1. Not in the paper.");
  options->AddOption(s + "init_model_path", &o->init_model_path,
                     "Sparse model for init_method model.");
  options->AddOption(s + "init_min_num_inliers", &o->init_min_num_inliers,
                     "The initial model is rejected unless this many images "
                     "agree with their priors, >= 3.");
  options->AddOption(s + "init_min_inlier_ratio", &o->init_min_inlier_ratio,
                     "... and this fraction of its images, [0, 1].");
  options->AddOption(s + "mapper_abs_pose_min_num_inliers",
                     &o->mapper_abs_pose_min_num_inliers,
                     "Stock mapper's Mapper.abs_pose_min_num_inliers, > 0.");
  options->AddOption(s + "mapper_abs_pose_min_inlier_ratio",
                     &o->mapper_abs_pose_min_inlier_ratio,
                     "Stock mapper's Mapper.abs_pose_min_inlier_ratio, "
                     "[0, 1].");
  options->AddOption(s + "mapper_num_attempts", &o->mapper_num_attempts,
                     "Stock mapper runs (random seeds 0, 1, ...) until one "
                     "model agrees with the priors, >= 1.");
  options->AddOption(s + "register_pending_images", &o->register_pending_images,
                     "Images the mapper registered outside a consensus are "
                     "registered by stock image_registrator against each "
                     "iteration's points (pose kept if within its prior's "
                     "99.9 % region) instead of staying out, 0/1. Not in "
                     "the paper.");
  options->AddOption(s + "max_num_iterations", &o->max_num_iterations,
                     "Triangulate / associate / adjust rounds (after a "
                     "points-only round when the initial poses are the "
                     "priors), >= 1; more than 1 (association again on the "
                     "adjusted poses) is not in the paper.");
  options->AddOption(s + "max_position_change_m", &o->max_position_change_m,
                     "Converged when no camera centre moves more, metres.");
  options->AddOption(s + "max_rotation_change_deg",
                     &o->max_rotation_change_deg,
                     "... and no camera turns more, degrees.");
  options->AddOption(s + "initial_pose_sigma_t_m", &o->initial_pose_sigma_t_m,
                     "Association pose uncertainty in the first line "
                     "iteration, metres, >= 0.");
  options->AddOption(s + "initial_pose_sigma_r_deg",
                     &o->initial_pose_sigma_r_deg,
                     "Same, rotation, degrees, >= 0.");
  options->AddOption(s + "refined_pose_sigma_t_m", &o->refined_pose_sigma_t_m,
                     "Association pose uncertainty after a line "
                     "adjustment, metres, >= 0.");
  options->AddOption(s + "refined_pose_sigma_r_deg",
                     &o->refined_pose_sigma_r_deg,
                     "Same, rotation, degrees, >= 0.");
  options->AddOption(s + "max_point_error_px", &o->max_point_error_px,
                     "Points with a larger error are removed after each "
                     "adjustment, pixels, > 0.");
  options->AddOption(s + "max_line_error_px", &o->max_line_error_px,
                     "Line tracks with a larger error are removed, pixels, "
                     "> 0.");
  options->AddOption(s + "triangulation_max_error_px",
                     &o->triangulation_max_error_px,
                     "point_triangulator's Mapper.filter_max_reproj_error, "
                     "pixels, > 0.");
  options->AddOption(s + "prior_position_sigma_m", &o->prior_position_sigma_m,
                     "Pose prior sigma on the camera centre (the gauge), "
                     "metres, > 0.");
  options->AddOption(s + "prior_rotation_sigma_deg",
                     &o->prior_rotation_sigma_deg,
                     "RMS angle of the orientation priors, degrees, > 0 "
                     "(per-axis sigma = this / sqrt(3)).");
  options->AddOption(s + "max_prior_outlier_ratio", &o->max_prior_outlier_ratio,
                     "An iteration leaving more images outside the 99.9 % "
                     "region of their priors is undone, [0, 1]; 1 never "
                     "undoes one. Not in the paper.");
  // The association thresholds most worth tuning; the others keep their
  // defaults (see line_matcher).
  const std::string m = "LineMatching.";
  options->AddOption(m + "t_theta_deg", &o->matching.t_theta_deg,
                     "Algorithm 1 t_theta, degrees, (0, 90].");
  options->AddOption(m + "t_dP_px", &o->matching.t_dP_px,
                     "Algorithm 1 t_dP, pixels, > 0.");
  options->AddOption(m + "t_dO_m", &o->matching.t_dO_m,
                     "Algorithm 1 t_dO, metres, > 0.");
  options->AddOption(m + "t_LBD", &o->matching.t_LBD,
                     "Algorithm 1 t_LBD, bits; 256 disables it.");
  options->AddOption(m + "min_overlap", &o->matching.min_overlap,
                     "Overlap along the line / shorter segment, [0, 1]; 0 "
                     "= Algorithm 1 as published. Not in the paper.");
  options->AddOption(m + "pose_uncertainty_scale",
                     &o->matching.pose_uncertainty_scale,
                     "Thresholds grow by this many pose standard "
                     "deviations, >= 0; 0 = fixed thresholds as published. "
                     "Not in the paper.");
  options->AddOption(m + "max_rival_score_ratio",
                     &o->matching.max_rival_score_ratio,
                     "A view's best match is dropped when a segment side by "
                     "side with it scores below best / this, (0, 1]; 1 = "
                     "off. Not in the paper.");
  options->AddOption(m + "refine_relative_poses",
                     &o->matching.refine_relative_poses,
                     "Register overlapping views on their 3D segments and "
                     "correct the poses by a robust pose graph before "
                     "Algorithm 1, 0/1. Not in the paper.");
  options->AddOption(m + "min_track_length", &o->matching.min_track_length,
                     "Tracks with fewer observations are dropped, >= 2.");
  options->AddCheck([o] { return o->Check(); });
}

int RunLineBundleAdjuster(int argc, char** argv) {
  WorkspaceLineAdjustmentPaths paths;
  LineBundleAdjustmentOptions adjustment;
  LineBundleAdjustmentNames names;

  OptionManager options;
  options.AddRequiredOption("database_path", &paths.database_path,
                            "COLMAP database with ext_line_tracks (from "
                            "line_matcher) and ext_line_segments.");
  options.AddRequiredOption("input_path", &paths.input_path,
                            "Sparse model with the poses (and points3D, "
                            "e.g. from stock point_triangulator).");
  options.AddRequiredOption("output_path", &paths.output_path,
                            "Folder of the refined model (binary, with "
                            "lines3D.bin).");
  options.AddOption("export_ply_path", &paths.lines_ply_path,
                    "PLY line set of the refined 3D segments; empty: "
                    "<output_path>/lines3D.ply.");
  AddLineBundleAdjustmentOptions(&adjustment, &names,
                                 /*with_gauge_and_priors=*/true, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  const WorkspaceLineAdjustmentSummary summary =
      RunWorkspaceLineAdjustment(paths, adjustment);
  if (summary.solved) {
    std::cout << summary.adjustment.ToString() << std::endl;
  }
  if (!summary.error.empty()) {
    LOG(ERROR) << summary.error;
    return EXIT_FAILURE;
  }
  std::cout << "Wrote " << summary.num_images << " images, "
            << summary.num_points3D << " points3D, " << summary.num_lines3D
            << " lines3D to " << paths.output_path << "; segments to "
            << summary.lines_ply_path << std::endl;
  return EXIT_SUCCESS;
}

int RunLidarMapperCommand(int argc, char** argv) {
  LidarMapperPaths paths;
  std::string dataset_path;
  LidarMapperOptions mapper_options;
  LineBundleAdjustmentNames names;

  OptionManager options;
  options.AddRequiredOption("workspace_path", &paths.workspace_path,
                            "Workspace of lidar_importer (database.db, "
                            "images/, prior poses).");
  options.AddOption("dataset_path", &dataset_path,
                    "Recording to import first when the workspace has no "
                    "database yet (import -> features -> lines -> "
                    "association -> adjustment in one command).");
  options.AddOption("database_path", &paths.database_path,
                    "Default <workspace>/database.db.");
  options.AddOption("image_path", &paths.image_path,
                    "Default <workspace>/images.");
  options.AddOption("output_path", &paths.output_path,
                    "Refined model; default <workspace>/sparse/refined.");
  options.AddOption("export_ply_path", &paths.lines_ply_path,
                    "PLY of the final 3D segments; default "
                    "<output_path>/lines3D.ply.");
  AddLidarMapperOptions(&mapper_options, &options);
  AddLineBundleAdjustmentOptions(&mapper_options.adjustment, &names,
                                 /*with_gauge_and_priors=*/false, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  // The import summary is printed before the mapper's long run starts.
  const LidarMapperWorkspace workspace =
      PrepareLidarMapperWorkspace(paths, dataset_path);
  if (!workspace.error.empty()) {
    LOG(ERROR) << workspace.error;
    return EXIT_FAILURE;
  }
  if (workspace.imported) {
    std::cout << FormatImportSummary(workspace.import) << std::endl;
  }
  const LidarMapperSummary summary =
      RunLidarMapper(workspace.paths, mapper_options);
  std::cout << summary.Format() << std::endl;
  return EXIT_SUCCESS;
}

}  // namespace colmap_lidar
