// lidar_mapper: the camera + LIDAR structure from motion of the paper
// (Amblard et al., section III: B lines, C association, D adjustment) on a
// COLMAP workspace that holds prior poses (lidar_importer), glued to stock
// COLMAP for the point features:
//
//   1. features   stock `feature_extractor` (CPU SIFT), skipped when every
//                 image has keypoints;
//   2. matches    stock `exhaustive_matcher` up to
//                 exhaustive_max_num_images images, else
//                 `sequential_matcher` (stock matchers skip pairs already
//                 matched). Measured on the default scene (60 frames,
//                 docs/benchmarks/lidar_mapper.md): sequential with overlap
//                 10 (495 pairs) costs 93 CPU s against about 330 for
//                 exhaustive (1770 pairs, estimated from the pair count);
//                 pairs with many inliers lie within 10 frames, farther
//                 ones are mostly 15-inlier repeated-structure matches;
//   3. lines      line_extractor (src/lines) when ext_line_segments is empty;
//   4. initial poses, see init_method below;
//   5. iterations, as COLMAP's mapper alternates BA and triangulation:
//        stock `point_triangulator` with the current poses held fixed
//        (--clear_points 1, intrinsics fixed) -> line association
//        (MatchWorkspaceLines) with tolerances from the current pose
//        uncertainty -> LineBundleAdjuster (points, lines, LIDAR lines,
//        pose priors, the LIDAR graph's edges, and the LIDAR planes of the
//        points found at the current poses, src/sfm/lidar_point_planes.h:
//        on the corridor VLP-16 cell 2.72 -> 2.14 cm after sim3, other
//        cells within 0.2 mm) -> outlier filtering (points and line tracks
//        above a reprojection error), max_num_iterations times (default once)
//        or until the largest camera displacement of an iteration is below
//        max_position_change_m and the largest rotation change below
//        max_rotation_change_deg; with the LIDAR graph's initialisation,
//        after the first round each image is matched again with its
//        nearest images where the adjusted poses and its LIDAR depth put a
//        keypoint's match (src/sfm/pose_guided_matching.h, guided_matching:
//        the corridors 1.74 -> 0.68 cm and 1.38 -> 1.29 cm after sim3), and
//        one more round triangulates with those matches;
//   6. output     <output_path> (default sparse/refined): a COLMAP model
//                 readable by stock colmap, plus lines3D.bin, and a PLY of
//                 the final 3D segments.
//
// Guards (a stock mapper model can be partly broken: collapsed or mirrored
// parts, scale drift; measured on the default scene, one run in a few):
// - The mapper's model is aligned to the priors by LO-RANSAC
//   (RobustAlignReconstructionToPriors, inliers judged on centre AND
//   orientation against the prior sigmas). It is rejected, with a WARNING,
//   unless the consensus holds init_min_num_inliers images and
//   init_min_inlier_ratio of the registered ones and both halves of it
//   agree on the scale; the run then continues as "priors". Images the
//   mapper registered outside a consensus are pending: out of the
//   triangulation and the association, registered by stock
//   `image_registrator` against each iteration's points and taken when the
//   pose lies in the 99.9 % region of their prior (register_pending_images).
//   Images no model registered start at their prior pose.
// - After each adjustment every pose is compared with its prior (centre
//   and rotation angle against the prior sigmas). When more than
//   max_prior_outlier_ratio of the images (and more than before) leave the
//   99.9 % region, the iteration is undone and the iterations stop with a
//   WARNING; single images beyond the 1e-6 region are reset to their prior.
//
// Initialisation (measured on the default synthetic scene, priors with
// 0.5 m / 5 deg noise; see docs/benchmarks/lidar_mapper.md):
// - "mapper": stock `colmap mapper` without priors, its largest
//   model aligned to the prior camera centres by a sim3 (Umeyama). Relative
//   poses are then accurate to about a centimetre and the association works
//   with tight tolerances from the first iteration. Images the mapper did
//   not register start at their prior pose. When the mapper fails (or
//   registers fewer than 3 images) the run continues as "priors", with a
//   warning.
// - "priors": the prior poses directly; the first iteration then adjusts
//   points only (lines are associated from the second iteration on), since
//   with metre-level pose errors the line association is mostly wrong.
// - "model": like "mapper" with the model at init_model_path instead of a
//   stock mapper run (another SfM result; also how the guards are tested).
// - "lidar_graph" (default): the poses of a LIDAR pose graph (src/sfm/
//   lidar_pose_graph.h: scan registration edges between consecutive and
//   nearby frames, the priors as unary factors) for every image; no stock
//   mapper run. The graph's poses are also written to
//   <workspace>/sparse/lidar_mapper/lidar_graph. The default since the
//   benchmark matrix (docs/benchmarks/matrix.md): on the 30-frame quad the
//   stock mapper registered 19 images, the other 11 started at their
//   priors and the refined poses ended 29.6 cm / 1.6 deg off after sim3
//   (1.17 cm / 0.14 deg from the graph); on the KITTI sample the mapper's
//   model made the 3.3 m odometry trajectory 5.4 m long with a 2.0 m step
//   (4.3 m, steps 0.21-0.24 m from the graph); on a 32-ring street both
//   end at 1.4-1.6 cm.
//
// Gauge: the pose priors (sigmas prior_position_sigma_m,
// prior_rotation_sigma_deg) fix the world frame in every iteration
// (LineBAGauge::kPosePriors); the LIDAR lines fix the scale. Since the
// priors are independent per frame, the world frame is known only to about
// sigma / sqrt(N): scripts/pose_gauge_bound.py gives the resulting lower
// bound on the error without alignment (0.116 m expected for the default
// scene's 60 frames and 0.5 m / 5 deg priors).
//
// Code: lidar_mapper.cc runs the steps; the stock colmap runs are in
// stock_colmap_steps.h, step 4 in initial_poses.h, step 5 in
// mapper_iterations.h, the test of a pose against its prior in
// pose_prior_checks.h and the final check against the LIDAR edges in
// lidar_edge_check.h.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "src/lines/line_extractor.h"
#include "src/matching/line_matching_options.h"
#include "src/optim/line_bundle_adjustment.h"
#include "src/sfm/lidar_point_planes.h"
#include "src/sfm/lidar_pose_graph.h"
#include "src/sfm/pose_guided_matching.h"

namespace colmap_lidar {

struct LidarMapperOptions {
  // Stock colmap binary (see ColmapRunnerOptions); empty: $COLMAP_BINARY or
  // `colmap` on PATH.
  std::string colmap_binary = "";
  // Threads for colmap and our stages; <= 0: all cores.
  int num_threads = -1;

  // ---- Features and matches (stock colmap).
  // SiftExtraction.max_image_size.
  int sift_max_image_size = 3200;
  // SiftExtraction.max_num_features.
  int sift_max_num_features = 8192;
  // Exhaustive matching up to this many images, sequential beyond.
  int exhaustive_max_num_images = 30;
  // SequentialMatching.overlap when sequential.
  int sequential_overlap = 10;
  // SequentialMatching.quadratic_overlap: also match i with i + 2^k, which
  // on a walk mostly adds far pairs of repeated structure.
  bool sequential_quadratic_overlap = false;
  // "exact": src/sfm/exact_feature_matcher.h, the stock matchers' pairs and
  // thresholds, exact descriptor matching and seeded verification: the same
  // database gives the same matches, hence the same poses (three runs of the
  // corridor VLP-16 cell agree to 1e-10 mm; with stock matches they differed
  // by up to 24 mm / 0.07 deg), and no cell's poses got worse
  // (docs/benchmarks/matrix.md); slower than stock's (190 pairs of 1280x720
  // images: 91 s against 66 s, both on shared cores).
  // "stock": colmap's exhaustive/sequential_matcher (its matches and
  // inliers differ run after run, also with one thread).
  std::string matcher = "exact";

  // ---- Initial poses: "mapper", "priors", "model" or "lidar_graph" (see
  // the file comment).
  std::string init_method = "lidar_graph";
  // Sparse model for init_method "model" (any frame and scale).
  std::string init_model_path = "";
  // Acceptance of the initial model (see Guards in the file comment).
  int init_min_num_inliers = 8;
  double init_min_inlier_ratio = 0.5;
  // Stock mapper's Mapper.abs_pose_min_num_inliers / _min_inlier_ratio
  // (colmap's defaults). Measured on the default scene: the stock values
  // register 53 of 60 images; 12 / 0.1 register all 60 but the model is
  // wrong (sim3 error of metres, flipped cameras), so do not lower them.
  int mapper_abs_pose_min_num_inliers = 30;
  double mapper_abs_pose_min_inlier_ratio = 0.25;
  // Stock mapper runs (random seeds 0, 1, ...) until one gives a model the
  // prior alignment accepts, >= 1.
  int mapper_num_attempts = 3;
  // Images registered outside a consensus of the initial models stay out of
  // the triangulation and the association (their poses are wrong and
  // dragged the model) and are registered in each iteration by stock
  // `image_registrator` (PnP on the matches to the triangulated points,
  // with the Mapper.abs_pose_* above) against the current model; a pose
  // inside the 99.9 % region of its prior is taken, the image then joins.
  // Off: they stay out for good. (Images no model registered join at their
  // prior pose from the start.)
  bool register_pending_images = true;

  // ---- Iterations: rounds of triangulation, association and adjustment
  // (after a points-only round when the initialisation is the priors).
  // One: more rounds (association again on the adjusted poses) did not pay
  // on the worst cell of the benchmark matrix (corridor VLP-16: 2.14 cm /
  // 0.051 deg after sim3 with 5 rounds, 2.04 cm / 0.038 deg with one; every
  // other cell within 0.01 cm, docs/benchmarks/ablation.md). Pose-guided
  // matching (guided_matching below) adds one round when it adds matches.
  int max_num_iterations = 1;
  // Convergence: largest camera centre change (metres) and rotation change
  // (degrees) of an iteration.
  double max_position_change_m = 0.005;
  double max_rotation_change_deg = 0.05;
  // Pose uncertainty given to the association (LineMatchingOptions
  // pose_sigma_*): in the first line iteration (after the initialisation)
  // and once the poses were adjusted with lines.
  double initial_pose_sigma_t_m = 0.05;
  double initial_pose_sigma_r_deg = 0.2;
  double refined_pose_sigma_t_m = 0.01;
  double refined_pose_sigma_r_deg = 0.05;
  // Outlier filtering after each adjustment: points and line tracks with a
  // larger mean reprojection error (pixels) are removed.
  double max_point_error_px = 4.0;
  double max_line_error_px = 4.0;
  // Stock point_triangulator's Mapper.filter_max_reproj_error, pixels.
  double triangulation_max_error_px = 4.0;

  // ---- Pose priors (the importer's prior columns) in the adjustment and
  // the guards. Position: standard deviation per axis. Rotation: the RMS
  // rotation angle (the paper's and the synthesizer's Sigma_R); the
  // rotation vector's per-axis sigma is this / sqrt(3), which is what the
  // adjustment's prior residual uses.
  double prior_position_sigma_m = 0.5;
  double prior_rotation_sigma_deg = 5.0;
  // Iteration guard: largest fraction of images allowed outside the 99.9 %
  // region of their priors after an adjustment (see the file comment).
  double max_prior_outlier_ratio = 0.1;

  // Stage options; lidar_mapper sets the pose-uncertainty, gauge, prior and
  // thread fields itself.
  LineExtractionOptions extraction;
  LineMatchingOptions matching;
  LineBundleAdjustmentOptions adjustment;
  // init_method "lidar_graph"; lidar_mapper sets its prior sigmas and
  // threads from the fields above.
  LidarPoseGraphOptions lidar_graph;
  // The LIDAR planes of the points (src/sfm/lidar_point_planes.h), terms of
  // every adjustment with points when adjustment.lidar_point_weight > 0;
  // lidar_mapper sets the threads.
  LidarPointPlaneOptions point_planes;
  // Pose-guided matching after the first iteration (init_method
  // lidar_graph; src/sfm/pose_guided_matching.h); lidar_mapper sets its
  // pose sigmas (refined_pose_sigma_*) and threads.
  PoseGuidedMatchingOptions guided_matching;

  bool Check() const;
};

struct LidarMapperIteration {
  // Undone by the guard (the model kept the poses before it).
  bool rejected = false;
  // Images outside the 99.9 % region of their prior after the adjustment.
  int num_prior_outliers = 0;
  int num_points = 0;
  int num_line_tracks = 0;
  // The LIDAR planes given to the adjustment (num_planes 0 when off).
  LidarPointPlaneSummary point_planes;
  LineBundleAdjustmentSummary adjustment;
  double max_position_change_m = 0.0;
  double mean_position_change_m = 0.0;
  double max_rotation_change_deg = 0.0;
  int num_filtered_points = 0;
  int num_filtered_lines = 0;
  // Pending images placed by image_registrator in this iteration.
  int num_registered_images = 0;
  double seconds = 0.0;
};

struct LidarMapperSummary {
  int num_images = 0;
  // Images registered by the initialisation (all, for "priors").
  int num_initial_images = 0;
  double prior_alignment_rms_m = -1.0;
  // The initialisation used in the end: "mapper", "model", "priors", or
  // "priors (fallback)" when the initial model was rejected.
  std::string init_used;
  // RobustPriorAlignmentSummary::Format() of the initial model.
  std::string init_alignment;
  // Images registered outside a consensus, and how many of them the
  // iterations registered (register_pending_images); the rest keep their
  // prior pose, out of the adjustment.
  int num_pending_images = 0;
  int num_registered_pending = 0;
  // Registered images of the initial model outside the consensus (they
  // start at their prior pose).
  int num_init_outliers = 0;
  // Iterations undone by the guard, and images reset to their prior.
  int num_rejected_iterations = 0;
  int num_reset_images = 0;
  std::vector<LidarMapperIteration> iterations;
  bool converged = false;
  int num_points = 0;
  int num_lines = 0;
  std::string output_path;
  std::string lines_ply_path;
  double features_seconds = 0.0;
  double lines_seconds = 0.0;
  double init_seconds = 0.0;
  double iterations_seconds = 0.0;
  double adjustment_seconds = 0.0;
  double total_seconds = 0.0;
  // Processor time (user + system, this process and the colmap runs) per
  // stage and in total, seconds: comparable on a shared machine.
  double features_cpu_seconds = 0.0;
  double lines_cpu_seconds = 0.0;
  double init_cpu_seconds = 0.0;
  double iterations_cpu_seconds = 0.0;
  double total_cpu_seconds = 0.0;
  // init_method lidar_graph: the graph's accepted edges, terms of every
  // adjustment (adjustment.lidar_edge_weight), and their mean whitened error
  // under the input (graph) and the final poses; frames with an edge beyond
  // the chi-square(6) 99.9 % quantile after the iterations; whether the
  // input poses were kept because the iterations violated the edges (mean
  // error more than doubled and up by more than sqrt(6), the expected norm
  // of a correct edge).
  int num_lidar_edges = 0;
  // Pose-guided matching's outcome (PoseGuidedMatchingSummary::ToString;
  // empty when it did not run) and the triangulation database it wrote
  // (empty when it added no match).
  std::string guided_matching;
  std::string guided_database_path;
  double lidar_edge_error_input = -1.0;
  double lidar_edge_error_final = -1.0;
  int num_lidar_edge_violated_frames = 0;
  bool kept_lidar_graph_poses = false;
  // Images of the output that observe no 3D point (no features, or none
  // matched: night, blur, a blank wall): their poses come from the LIDAR
  // edges and their priors alone (init_method lidar_graph), or from the
  // prior alone without an edge. Logged with a warning.
  std::vector<std::string> images_without_points;

  std::string Format() const;
  // One line for the pipeline's stage record and report: counts, whether
  // it converged, and what a user must know of the poses (frames posed by
  // the LIDAR graph alone, edges violated, graph poses kept).
  std::string Outcome() const;
};

struct LidarMapperPaths {
  // Workspace with database.db, images/ and sparse/prior (lidar_importer).
  std::string workspace_path;
  // Defaults (empty): <workspace>/database.db, <workspace>/images,
  // <workspace>/sparse/refined, <output_path>/lines3D.ply.
  std::string database_path;
  std::string image_path;
  std::string output_path;
  std::string lines_ply_path;
};

// The image pairs lidar_mapper matches (exhaustive_max_num_images,
// sequential_overlap, sequential_quadratic_overlap; MatchingPairs of
// src/sfm/exact_feature_matcher.h) among the images of the database.
std::vector<std::pair<image_t, image_t>> LidarMapperMatchingPairs(
    const std::string& database_path, const LidarMapperOptions& options);

// Runs the pipeline of the file comment. Intermediate models go to
// <workspace>/sparse/lidar_mapper/, stock colmap's output to
// <workspace>/lidar_mapper_colmap.log. Throws colmap_lidar::Error naming
// the file or stage on a missing database, fewer than 3 images with
// priors, or a failed colmap run (other than the mapper, see above).
LidarMapperSummary RunLidarMapper(const LidarMapperPaths& paths,
                                  const LidarMapperOptions& options);

// Removes points whose error exceeds max_error_px (or whose track is
// shorter than 2) and the references to them; returns how many.
int FilterPoints(double max_error_px, Reconstruction* model);

// Writes the line tracks' segments (world frame) as a PLY line set
// (src/eval/segment_io.h format).
void WriteLines3DPly(const std::string& path, const Reconstruction& model);

}  // namespace colmap_lidar
