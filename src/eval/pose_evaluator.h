// Camera pose accuracy of a sparse model against ground-truth poses, in the
// manner of evo's APE (Grupp 2017) with Umeyama alignment (Umeyama 1991):
// the estimated camera centres are aligned to the ground-truth centres by a
// similarity (sim3), a rigid transform (se3) or not at all (none), or, as
// Tanks and Temples does, by the fit of the centres AND the orientations
// (se3_axes, sim3_axes; see pose_alignment.h: a fit of the centres alone
// leaves the roll about a straight trajectory free); then, per
// matched image,
//   position error  = |s R c_est + t - c_gt|                       (metres)
//   rotation error  = angle of R_est_aligned^T R_gt                (degrees)
// where c are camera centres, R_est_aligned = R * R_est the aligned
// world_from_cam rotation and R_gt the ground-truth world_from_cam rotation.
//
// Matching: an image matches the ground-truth frame whose name equals the
// image name, else the frame equal to the stem of the image's file name
// ("cam/000042.png" <-> "000042"). Ground-truth frames without an image are
// "missing"; images without a frame are ignored (counted).
//
// Recalls are shares of ALL ground-truth frames (a missing frame counts as
// a failure), so a model that registers half the frames perfectly has
// recall 0.5: position recall at t = #(position error < t) / #GT frames,
// rotation recall likewise, and the paired recall at (t_pos[k], t_rot[k])
// requires both (when both lists have the same length).
//
// Relative pose error per step (evo's RPE with a delta of one frame):
// between consecutive ground-truth frames that both have an image, the
// estimate's motion against the true one, in the first frame's camera,
//   translation error = |R_gt_i^T (c_gt_j - c_gt_i)
//                        - s R_est_i^T (c_est_j - c_est_i)|       (metres)
//   rotation error    = angle of (R_gt_i^T R_gt_j)^T R_est_i^T R_est_j
// with R the world_from_cam rotations and s the alignment's scale (1 for
// none, se3, se3_axes). The alignment's rotation and translation cancel:
// the step errors show drift and jitter that an alignment of the whole
// trajectory averages away. A step across a missing frame is not counted.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "colmap_ext/scene/reconstruction.h"
#include "src/dataset/poses.h"
#include "src/eval/eval_stats.h"

namespace colmap_lidar {

struct PoseEvaluationOptions {
  // Alignment of the estimate to the ground truth before measuring: none |
  // se3 (rotation + translation) | sim3 (plus a uniform scale), estimated
  // by Umeyama on the camera centres of the matched images | se3_axes |
  // sim3_axes, the same fitted to the centres and the camera orientations
  // (AlignCentresAndAxes).
  std::string alignment = "sim3";
  // *_axes only: weight of the orientations against the centres, >= 0; 1
  // puts the axis points at the RMS spread of the centres (pose_alignment.h).
  double axes_weight = 1.0;
  // Position error thresholds in metres for the recalls; positive and
  // strictly increasing.
  std::vector<double> position_thresholds_m = {0.02, 0.05, 0.2, 0.5};
  // Rotation error thresholds in degrees; positive and strictly increasing.
  std::vector<double> rotation_thresholds_deg = {0.5, 1, 5, 10};

  bool Check() const;
};

struct ImagePoseError {
  std::string image_name;
  std::string frame;
  double position_error_m = 0.0;
  double rotation_error_deg = 0.0;
};

struct PoseEvaluation {
  std::string alignment;
  // The applied alignment x_gt ~ scale * rotation * x_est + translation
  // (identity for "none"; scale 1 for "se3" and "se3_axes").
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  size_t num_ground_truth_frames = 0;
  size_t num_model_images = 0;
  size_t num_matched = 0;
  // Ground-truth frames with no image in the model.
  size_t num_missing = 0;
  std::vector<std::string> missing_frames;
  // Model images with no ground-truth frame (ignored).
  size_t num_unmatched_images = 0;

  // Per matched image, in model file order.
  std::vector<ImagePoseError> errors;
  ErrorStats position_stats_m;
  ErrorStats rotation_stats_deg;
  // Relative pose error per step (see the top of this file).
  ErrorStats step_translation_stats_m;
  ErrorStats step_rotation_stats_deg;

  std::vector<double> position_thresholds_m;
  std::vector<double> position_recalls;
  std::vector<double> rotation_thresholds_deg;
  std::vector<double> rotation_recalls;
  // Both errors below (position_thresholds_m[k], rotation_thresholds_deg[k]);
  // empty when the two lists differ in length.
  std::vector<double> pose_recalls;
};

// Throws colmap_lidar::Error when the options are invalid, or when an
// alignment other than none has fewer than 3 matched images (naming the counts), or when
// the matched centres are degenerate (all identical).
// True for the alignment values PoseEvaluationOptions accepts.
bool IsPoseAlignment(const std::string& alignment);

PoseEvaluation EvaluatePoses(const Reconstruction& estimate,
                             const std::vector<FramePose>& ground_truth,
                             const PoseEvaluationOptions& options);

// The applied alignment as a transform x_gt = T * x_est (for carrying
// other data of the estimate, e.g. a mesh, into the ground-truth frame).
Eigen::Affine3d GroundTruthFromEstimate(const PoseEvaluation& evaluation);

// Fixed-width summary table.
std::string FormatPoseEvaluation(const PoseEvaluation& evaluation);
// JSON report (see colmap_ext/util/json.h), written atomically; throws
// naming the path.
void WritePoseEvaluationJson(const std::string& path,
                             const PoseEvaluation& evaluation);

}  // namespace colmap_lidar
