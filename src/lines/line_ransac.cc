#include "src/lines/line_ransac.h"

#include <random>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

std::vector<int> Inliers(const std::vector<Eigen::Vector3d>& points,
                         const Line3& line, const double inlier_distance) {
  std::vector<int> inliers;
  for (size_t i = 0; i < points.size(); ++i) {
    if (DistanceToLine(line, points[i]) <= inlier_distance) {
      inliers.push_back(static_cast<int>(i));
    }
  }
  return inliers;
}

}  // namespace

bool LineRansacOptions::Check() const {
  if (!(inlier_distance > 0.0)) {
    LOG(ERROR) << "LineExtraction.ransac_inlier_distance must be > 0";
    return false;
  }
  if (max_iterations < 1) {
    LOG(ERROR) << "LineExtraction.ransac_max_iterations must be >= 1";
    return false;
  }
  if (min_inliers < 2) {
    LOG(ERROR) << "LineExtraction.min_inliers must be >= 2";
    return false;
  }
  return true;
}

LineRansacResult FitLineRansac(const std::vector<Eigen::Vector3d>& points,
                               const LineRansacOptions& options) {
  LineRansacResult result;
  const int n = static_cast<int>(points.size());
  if (n < std::max(options.min_inliers, 2)) {
    return result;
  }
  int best_count = 0;
  Line3 best_line;
  auto try_pair = [&](int i, int j) {
    const Eigen::Vector3d difference = points[j] - points[i];
    const double length = difference.norm();
    if (length < 1e-6) {
      return;
    }
    Line3 line;
    line.point = points[i];
    line.direction = difference / length;
    int count = 0;
    for (const Eigen::Vector3d& point : points) {
      count += DistanceToLine(line, point) <= options.inlier_distance ? 1 : 0;
    }
    if (count > best_count) {
      best_count = count;
      best_line = line;
    }
  };
  const int64_t num_pairs = static_cast<int64_t>(n) * (n - 1) / 2;
  if (num_pairs <= options.max_iterations) {
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        try_pair(i, j);
      }
    }
  } else {
    std::mt19937 generator(options.random_seed);
    std::uniform_int_distribution<int> distribution(0, n - 1);
    for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
      const int i = distribution(generator);
      const int j = distribution(generator);
      if (i != j) {
        try_pair(i, j);
      }
    }
  }
  if (best_count < options.min_inliers) {
    return result;
  }
  // Refit on the inliers and take the inliers of the refit (twice, so that
  // the inlier set is consistent with the returned line).
  result.line = best_line;
  result.inliers = Inliers(points, best_line, options.inlier_distance);
  for (int round = 0; round < 2; ++round) {
    const Line3 refit = FitLineLeastSquares(points, result.inliers);
    std::vector<int> inliers = Inliers(points, refit, options.inlier_distance);
    if (static_cast<int>(inliers.size()) < options.min_inliers) {
      break;
    }
    result.line = refit;
    result.inliers = std::move(inliers);
  }
  result.line = FitLineLeastSquares(points, result.inliers);
  result.success =
      static_cast<int>(result.inliers.size()) >= options.min_inliers;
  return result;
}

}  // namespace colmap_lidar
