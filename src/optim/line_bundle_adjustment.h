// Point + line bundle adjustment with LIDAR constraints (paper section
// III-D, eq. 3): refines camera poses, sparse 3D points and infinite 3D
// lines by minimising
//
//   lambda_R     sum rho_R(|point reprojection error|^2)      (eq. 1)
// + lambda_L     sum rho_L(|line reprojection error|^2)       (eq. 2)
// + lambda_lidar sum rho_D(|LIDAR endpoint offsets / sigma|^2)
// + sum |pose prior residual|^2                               (optional)
//
// with Ceres' Levenberg-Marquardt and a Schur-complement linear solver
// (points and lines eliminated). Lines are optimised as infinite lines in
// the orthonormal representation (line_manifold.h) and turned back into
// segments at the end (ComputeLineSegment). The residual equations are in
// cost_functions.h.
//
// Gauge. The LIDAR residuals compare metric 3D segments in each camera
// frame with the lines, so the scale is observable whenever one LIDAR line
// residual exists; the world frame (3 rotations, 3 translations) is not.
// - LineBAGauge::kFixFirstPose (default): the first image (in the order of
//   Reconstruction::images) that has residuals keeps its input pose, the
//   world frame is the one that image's pose defines (as in visual(-inertial)
//   odometry, whose world is the first camera frame). Pose priors, if
//   enabled, act as additional soft constraints.
// - LineBAGauge::kPosePriors: all poses are free and the pose priors alone
//   fix the world frame (requires both prior sigmas > 0). With priors of
//   sigma s on N images the frame itself is only known to about s/sqrt(N).
// Without LIDAR residuals and without pose priors the scale is free too:
// one translation coordinate of the second constrained image (the axis of
// its largest offset from the first) is also held fixed, with a warning.
//
// Under-constrained views. An image gets residuals from the points and
// lines it observes. Images with fewer than min_constraints_per_image
// scalar residuals (points: 2 each, lines: 2, LIDAR lines: +4) are
// reported in the summary as unconstrained and keep their input pose
// (their observations still constrain the points and lines), unless pose
// priors are enabled, which constrain every image. An image with no lines
// but enough points (or no points but enough lines) is a normal image.
//
// LIDAR registration edges (SetRelativePoseEdges, e.g. the accepted edges
// of the LIDAR pose graph, src/sfm/lidar_pose_graph.h) add
// + lidar_edge_weight sum rho_E(|S r_ij|^2)
// with RelativeLidarPoseCostFunctor (cost_functions.h) per edge whose two
// images are both in the reconstruction: the relative poses stay consistent
// with the scan registrations. An edge gives each of its images 6 scalar
// constraints and fixes the metric scale.
//
// LIDAR planes of points (SetPointPlanes, src/sfm/lidar_point_planes.h: a
// plane of an image's own scan where one of its points lies) add
// + lidar_point_weight sum rho_P(|(n . X_cam - d) / sigma|^2)
// with LidarPointPlaneCostFunctor (cost_functions.h), one residual per plane
// whose image and point are in the adjustment: the LIDAR depth of the
// visual features, metric like the LIDAR line residuals (not in the paper).
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/reconstruction.h"
#include "src/optim/line_track.h"

namespace colmap_lidar {

enum class LineBALossType { kTrivial, kHuber, kSoftL1, kCauchy };
enum class LineBAGauge { kFixFirstPose, kPosePriors };

// "TRIVIAL", "HUBER", "SOFT_L1", "CAUCHY" <-> enum; throws
// colmap_lidar::Error on an unknown name.
LineBALossType LineBALossTypeFromName(const std::string& name);
std::string LineBALossTypeName(LineBALossType loss_type);
// "FIX_FIRST_POSE", "POSE_PRIORS" <-> enum; throws on an unknown name.
LineBAGauge LineBAGaugeFromName(const std::string& name);
std::string LineBAGaugeName(LineBAGauge gauge);

// A relative pose measured between the LIDAR frames of two images (a scan
// registration), with its 6x6 square-root information S (S^T S = Lambda,
// rotation (rad) first, then translation (m); the convention of
// RelativePoseCostFunctor in src/sfm/lidar_pose_graph.h).
struct RelativePoseEdge {
  image_t image_id1 = kInvalidImageId;
  image_t image_id2 = kInvalidImageId;
  Rigid3d lidar1_from_lidar2;
  Rigid3d cam1_from_lidar;
  Rigid3d cam2_from_lidar;
  Eigen::Matrix<double, 6, 6> sqrt_information =
      Eigen::Matrix<double, 6, 6>::Identity();
};

// The LIDAR surface at a 3D point as one image's scan saw it: the plane
// n . x = offset_m in that image's camera frame (|n| = 1), known to sigma_m.
struct PointPlaneObservation {
  image_t image_id = kInvalidImageId;
  point3D_t point3D_id = kInvalidPoint3DId;
  Eigen::Vector3d normal_in_cam = Eigen::Vector3d::UnitZ();
  double offset_m = 0.0;
  double sigma_m = 0.02;
};

struct LineBundleAdjustmentOptions {
  // Weight lambda_R of the point reprojection errors (eq. 3); 0 disables
  // the point residuals.
  double lambda_R = 1.0;
  // Weight lambda_L of the line reprojection errors (eq. 3); 0 disables
  // them.
  double lambda_L = 1.0;
  // Weight of the LIDAR line residuals; 0 disables them (and with them the
  // metric scale).
  double lambda_lidar = 1.0;
  // Standard deviation of the LIDAR endpoints' distance to the true line,
  // metres (range noise plus edge localisation); LIDAR residuals are
  // divided by it.
  double lidar_sigma_m = 0.02;

  // Robust losses per residual type; scales in pixels for points and
  // lines and in units of lidar_sigma_m for LIDAR residuals.
  LineBALossType point_loss_type = LineBALossType::kCauchy;
  double point_loss_scale = 2.0;
  LineBALossType line_loss_type = LineBALossType::kCauchy;
  double line_loss_scale = 2.0;
  LineBALossType lidar_loss_type = LineBALossType::kCauchy;
  double lidar_loss_scale = 3.0;

  // Weight of the LIDAR registration edges (SetRelativePoseEdges); 0
  // disables them. Their Cauchy loss scale is in whitened units (sigmas of
  // the registration's information): 3 keeps a correct registration's
  // residuals (chi-square with 6 DoF, 99% below 4.1 sigma in norm) mostly in
  // the quadratic part and down-weights a wrong registration.
  double lidar_edge_weight = 1.0;
  double lidar_edge_loss_scale = 3.0;

  // Weight of the LIDAR planes of points (SetPointPlanes); 0 disables them.
  // Cauchy loss scale in units of each plane's sigma: a feature off the
  // surface the scan saw there (a thin pole in front of a wall) is
  // down-weighted.
  double lidar_point_weight = 1.0;
  double lidar_point_loss_scale = 3.0;

  // Pose priors on camera centre (metres) and orientation (degrees), on the
  // poses given to LineBundleAdjuster::SetPosePriors or, by default, the
  // input poses. Both 0 = off; both must be > 0 to enable them.
  double prior_position_sigma_m = 0.0;
  double prior_rotation_sigma_deg = 0.0;

  // World-frame gauge, see the file comment.
  LineBAGauge gauge = LineBAGauge::kFixFirstPose;

  // Which intrinsics are refined (all cameras); fixed by default.
  bool refine_focal_length = false;
  bool refine_principal_point = false;
  bool refine_extra_params = false;
  // Whether points and lines are refined (else held fixed).
  bool refine_points = true;
  bool refine_lines = true;

  // Points observed in fewer registered images are left out.
  int min_point_track_length = 2;
  // Points triangulated from poor initial poses can end in a wrong local
  // minimum that the robust loss then ignores. After the first solve,
  // points whose mean reprojection error exceeds this (pixels) are
  // re-triangulated (DLT over their track) from the refined poses and the
  // problem is solved once more. 0 = off.
  double retriangulation_max_error_px = 4.0;
  // Images with fewer scalar residuals are kept fixed (see file comment).
  int min_constraints_per_image = 6;

  // Ceres solver settings.
  int max_num_iterations = 100;
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  // ITERATIVE_SCHUR instead of SPARSE_SCHUR (large problems).
  bool use_iterative_schur = false;
  // -1 = all hardware threads.
  int num_threads = -1;
  // Ceres' per-iteration log on stdout (debugging only).
  bool minimizer_progress_to_stdout = false;

  bool Check() const;
};

struct LineBundleAdjustmentSummary {
  // Images with at least one residual, and how many of them were held
  // fixed (gauge or unconstrained).
  int num_images = 0;
  int num_fixed_images = 0;
  // Images kept at their input pose for lack of constraints (no residual
  // at all, or fewer than min_constraints_per_image without priors).
  std::vector<image_t> unconstrained_image_ids;
  int num_points = 0;
  int num_lines = 0;
  // Line tracks left unchanged: not initialisable, or under-determined (a
  // single view without LIDAR).
  int num_skipped_lines = 0;
  // Residual blocks per type.
  int num_point_residuals = 0;
  int num_line_residuals = 0;
  int num_lidar_residuals = 0;
  int num_pose_prior_residuals = 0;
  int num_lidar_edge_residuals = 0;
  int num_lidar_point_residuals = 0;
  // Ceres costs (1/2 sum of weighted robustified squared residuals).
  double initial_cost = 0.0;
  double final_cost = 0.0;
  // Summed over both solves (see retriangulation_max_error_px).
  int num_iterations = 0;
  double solve_time_s = 0.0;
  int num_retriangulated_points = 0;
  // Ceres' IsSolutionUsable(); false also when there was nothing to solve.
  bool usable = false;
  std::string termination_message;
  // Unweighted mean errors after the solve, pixels (-1 when none).
  double mean_point_error_px = -1.0;
  double mean_line_error_px = -1.0;
  // Root mean of the LIDAR endpoint distances to the lines, metres.
  double rms_lidar_distance_m = -1.0;
  // Mean whitened error |S r| of the LIDAR edges after the solve (-1 when
  // none); about sqrt(6) = 2.4 for registrations with correct information.
  double mean_lidar_edge_error = -1.0;
  // Root mean of the points' distances to their LIDAR planes after the
  // solve, metres (-1 when none).
  double rms_lidar_point_distance_m = -1.0;

  std::string ToString() const;
};

class LineBundleAdjuster {
 public:
  explicit LineBundleAdjuster(const LineBundleAdjustmentOptions& options);

  // Prior cam_from_world per image id, used when the pose-prior sigmas are
  // > 0; images without an entry use their input pose as the prior.
  void SetPosePriors(std::unordered_map<image_t, Rigid3d> cam_from_world_priors);

  // LIDAR registration edges, used when lidar_edge_weight > 0; edges with
  // an image missing from the reconstruction are skipped.
  void SetRelativePoseEdges(std::vector<RelativePoseEdge> edges);

  // LIDAR planes of points, used when lidar_point_weight > 0; planes whose
  // image or point is not adjusted (missing, or a point track shorter than
  // min_point_track_length) are skipped.
  void SetPointPlanes(std::vector<PointPlaneObservation> planes);

  // Refines reconstruction->images[*].cam_from_world, points3D[*].xyz (and
  // .error), camera parameters (if enabled) and each usable line track's
  // plucker_in_world, start/end_in_world and error. Line tracks that are not
  // initialised are initialised first (InitializeLineFromLidar, then
  // InitializeLineFromViews). Does not touch reconstruction->lines3D (see
  // SetReconstructionLines). Throws colmap_lidar::Error on invalid options
  // or a broken reconstruction (CheckConsistency).
  LineBundleAdjustmentSummary Solve(Reconstruction* reconstruction,
                                    std::vector<LineTrack>* line_tracks) const;

 private:
  LineBundleAdjustmentOptions options_;
  std::unordered_map<image_t, Rigid3d> cam_from_world_priors_;
  std::vector<RelativePoseEdge> relative_pose_edges_;
  std::vector<PointPlaneObservation> point_planes_;
};

// Whitened error |S r| of a LIDAR edge under the reconstruction's current
// poses; -1 when an image of the edge is missing.
double ComputeRelativePoseEdgeError(const Reconstruction& reconstruction,
                                    const RelativePoseEdge& edge);

// Mean distance (pixels) of a track's observed endpoints to its projected
// line, with the current poses (the residual of cost_functions.h); -1 when
// the line is not initialised or no observation's image exists.
double ComputeLineReprojectionError(const Reconstruction& reconstruction,
                                    const LineTrack& track);

}  // namespace colmap_lidar
