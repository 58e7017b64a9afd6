// RANSAC fit of a 3D line to LIDAR edge points (section III-B: "we run
// RANSAC on the set of edge points. Only inliers are kept"). Deterministic:
// all point pairs when there are few, else pairs drawn with a fixed seed.
#pragma once

#include <cstdint>
#include <vector>

#include "src/lines/line_geometry.h"

namespace colmap_lidar {

struct LineRansacOptions {
  // Point-line distance of an inlier, metres.
  double inlier_distance = 0.05;
  // Hypotheses tried at most (all pairs if fewer).
  int max_iterations = 200;
  // Fewer inliers than this is a failure.
  int min_inliers = 5;
  uint32_t random_seed = 0;

  bool Check() const;
};

struct LineRansacResult {
  bool success = false;
  // Least-squares refit on the inliers.
  Line3 line;
  // Positions into the input vector, increasing.
  std::vector<int> inliers;
};

LineRansacResult FitLineRansac(const std::vector<Eigen::Vector3d>& points,
                               const LineRansacOptions& options);

}  // namespace colmap_lidar
