// Similarity alignment of a sparse model to prior camera centres: gives a
// stock `colmap mapper` model (arbitrary frame and scale) the metric world
// frame of the LIDAR priors before the line bundle adjustment (lidar_mapper,
// initialisation "mapper"). Umeyama's least-squares estimate on the camera
// centres (Eigen::umeyama), and a robust (LO-RANSAC) variant that also
// decides whether the model can be trusted at all.
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/reconstruction.h"

namespace colmap_lidar {

// x_target = scale * rotation * x_source + translation.
struct Sim3d {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator*(const Eigen::Vector3d& x) const {
    return scale * (rotation * x) + translation;
  }
};

// Applies `target_from_source` to every pose (camera centres and
// orientations) and point of `model`; lines3D endpoints too.
void TransformReconstruction(const Sim3d& target_from_source,
                             Reconstruction* model);

struct PriorAlignmentSummary {
  int num_images = 0;
  Sim3d prior_from_model;
  // Root mean square distance between the aligned and the prior centres,
  // metres (about sqrt(3) times the per-axis prior noise).
  double rms_residual_m = 0.0;
};

// Estimates the sim3 taking the model's camera centres onto the prior
// centres of the same images (cam_from_world priors by image id) and
// applies it to `model`. Throws colmap_lidar::Error when fewer than 3
// images have a prior or their centres are degenerate (collinear within
// 1 mm).
PriorAlignmentSummary AlignReconstructionToPriors(
    const std::unordered_map<image_t, Rigid3d>& cam_from_world_priors,
    Reconstruction* model);

// Robust alignment of a possibly broken model (stock mapper models can
// hold collapsed or mirrored parts, or drift in scale) to noisy priors.
struct RobustPriorAlignmentOptions {
  // Prior noise: per-axis standard deviation of the camera centres
  // (metres) and RMS rotation angle (degrees).
  double position_sigma_m = 0.5;
  double rotation_sigma_deg = 5.0;
  // An image agrees with its prior when its centre error is below
  // position_num_sigmas sigmas (3.76: the 99.7 % quantile of the norm of a
  // 3-D Gaussian error) and its rotation error below rotation_num_sigmas
  // RMS angles (3: 99.7 % when the angle is Gaussian, as the synthesizer
  // draws it; more for a Gaussian rotation vector).
  double position_num_sigmas = 3.76;
  double rotation_num_sigmas = 3.0;
  // Random minimal samples (3 centres) before the local optimisation.
  int num_trials = 1000;
  unsigned int random_seed = 1;
  // Acceptance: at least this many consensus images, and this fraction of
  // the model images with a prior.
  int min_num_inliers = 8;
  double min_inlier_ratio = 0.5;
  // Scale consistency: the consensus is split in two halves along its main
  // axis; their sim3 scales must agree within this many standard deviations
  // (from the prior noise and each half's extent) plus 2 %.
  double max_scale_num_sigmas = 3.0;

  bool Check() const;
};

struct RobustPriorAlignmentSummary {
  // Model images with a prior.
  int num_images = 0;
  // The consensus, and the other model images with a prior.
  std::vector<image_t> inlier_image_ids;
  std::vector<image_t> outlier_image_ids;
  Sim3d prior_from_model;
  // Over the consensus: RMS centre distance (metres) and rotation error
  // (degrees) to the priors after the alignment.
  double rms_residual_m = -1.0;
  double rms_rotation_error_deg = -1.0;
  // Scales of the two halves of the consensus (0 when not computed).
  double half_scales[2] = {0.0, 0.0};
  // True when the model passed every test; `rejection` says why not.
  bool accepted = false;
  std::string rejection;

  std::string Format() const;
};

// LO-RANSAC sim3 from the model's camera centres to the prior centres,
// inliers judged on centre and orientation (so a mirrored part never
// agrees), then the acceptance tests of the options. When accepted, the
// sim3 is applied to the whole `model` (outliers included: the caller
// decides what to do with them); otherwise `model` is left unchanged.
// Never throws on bad models; throws colmap_lidar::Error on invalid options.
RobustPriorAlignmentSummary RobustAlignReconstructionToPriors(
    const std::unordered_map<image_t, Rigid3d>& cam_from_world_priors,
    const RobustPriorAlignmentOptions& options, Reconstruction* model);

}  // namespace colmap_lidar
