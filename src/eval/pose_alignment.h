// Alignment of an estimated camera trajectory to the ground truth by the
// camera centres AND orientations, as Tanks and Temples carries a
// reconstruction into the ground-truth frame before comparing surfaces.
//
// A fit of the centres alone (Umeyama 1991) leaves every rotation about the
// line of a straight trajectory free: only the noise of the centres decides
// it, and a mesh carried by that fit comes out tilted about the street. This
// fit adds, per camera, the orientation: it is the closed form of Umeyama on
// the centres plus, per camera, the six points centre +- d * axis (the
// camera's x, y, z axes in the world), with d = sqrt(axes_weight) times the
// RMS spread of the centres (of each trajectory about its centroid; the
// +- keeps the centroids those of the centres). Concretely, with x the
// estimated and y the ground-truth centres, R_est / R_gt the world_from_cam
// rotations and sigma_x, sigma_y the RMS spreads:
//   H = sum_i (y_i - y_mean)(x_i - x_mean)^T / (N sigma_x sigma_y)
//       + axes_weight * sum_i R_gt,i R_est,i^T / N,
//   R = argmax_R tr(R^T H)  (SVD, det(R) = +1),
//   s = sum_i (y_i - y_mean).R(x_i - x_mean) / sum_i |x_i - x_mean|^2
//       (sim3; 1 for se3),  t = y_mean - s R x_mean.
// Both terms of H are dimensionless and at most 1 in norm, so the weighting
// does not depend on the trajectory's size; with coincident centres the
// rotation comes from the orientations alone (se3 only).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace colmap_lidar {

struct TrajectoryAlignment {
  // x_gt ~ scale * rotation * x_est + translation.
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

// Inputs are per matched camera (same length, >= 1; >= 2 distinct centres
// for with_scale): centres and world_from_cam rotations of the estimate and
// of the ground truth. axes_weight >= 0 (0: centres only, which needs >= 3
// non-collinear centres to be determined). Throws colmap_lidar::Error on
// mismatched sizes, an empty input, a negative weight, or (with_scale)
// coincident estimated centres.
TrajectoryAlignment AlignCentresAndAxes(
    const std::vector<Eigen::Vector3d>& centres_est,
    const std::vector<Eigen::Quaterniond>& world_from_cam_est,
    const std::vector<Eigen::Vector3d>& centres_gt,
    const std::vector<Eigen::Quaterniond>& world_from_cam_gt,
    bool with_scale, double axes_weight);

}  // namespace colmap_lidar
