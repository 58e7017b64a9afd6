// The first and second moments of a point's neighbourhood, for a
// principal-component plane fit (the LIDAR denoising's local planes, the
// line validation's noise estimate).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "src/mesh/radius_grid.h"

namespace colmap_lidar {

struct NeighbourhoodMoments {
  int num_neighbors = 0;
  // Mean of the neighbours relative to the centre, and their covariance
  // (the plane's normal is its smallest eigenvector, the variance across
  // the plane its smallest eigenvalue).
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// The points of `points` within `radius` of `center` (the centre included
// when it is one of them), weighted by max(counts[j], 1) when `counts` is
// given, else 1. `grid` indexes `points` with cells of at least `radius`.
inline NeighbourhoodMoments ComputeNeighbourhoodMoments(
    const std::vector<Eigen::Vector3d>& points, const RadiusGrid& grid,
    const Eigen::Vector3d& center, double radius,
    const std::vector<uint32_t>* counts = nullptr) {
  const double sq_radius = radius * radius;
  double weight_sum = 0;
  NeighbourhoodMoments moments;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  grid.ForEachNear(center, [&](uint32_t j) {
    const Eigen::Vector3d offset = points[j] - center;
    if (offset.squaredNorm() > sq_radius) return;
    const double weight =
        counts == nullptr ? 1.0 : std::max<uint32_t>((*counts)[j], 1);
    weight_sum += weight;
    sum += weight * offset;
    second += weight * offset * offset.transpose();
    ++moments.num_neighbors;
  });
  if (moments.num_neighbors == 0) return moments;
  moments.mean = sum / weight_sum;
  moments.covariance =
      second / weight_sum - moments.mean * moments.mean.transpose();
  return moments;
}

}  // namespace colmap_lidar
