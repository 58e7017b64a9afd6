// Similarity alignment of a sparse model to prior camera centres: gives a
// stock `colmap mapper` model (arbitrary frame and scale) the metric world
// frame of the LIDAR priors before the line bundle adjustment (lidar_mapper,
// initialisation "mapper"). Umeyama's least-squares estimate on the camera
// centres (Eigen::umeyama).
#pragma once

#include <string>
#include <unordered_map>

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

}  // namespace colmap_lidar
