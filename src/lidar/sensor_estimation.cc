#include "src/lidar/sensor_estimation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <Eigen/Eigenvalues>

#include "colmap_ext/util/cell_key.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

bool RangeNoiseOptions::Check() const {
  return voxel_size > 0 && min_points_per_voxel >= 4 &&
         max_planarity_ratio > 0 && max_planarity_ratio < 1 &&
         min_spread_fraction >= 0 && min_spread_fraction < 1 &&
         min_incidence_cos >= 0 && min_incidence_cos < 1;
}

RangeNoiseEstimate EstimateRangeNoise(const std::vector<LidarScan>& scans,
                                      const RangeNoiseOptions& options) {
  THROW_CHECK(options.Check(), "RangeNoiseOptions: invalid option values");
  std::vector<double> residuals;
  RangeNoiseEstimate estimate;
  for (const LidarScan& scan : scans) {
    // Each voxel's fit takes the points within a margin around it, from its
    // neighbours too: a plane lying on a voxel face would otherwise be split
    // by the sign of its noise into two half-Gaussians and sigma read low.
    const double size = options.voxel_size;
    const double margin = 0.25 * size;
    auto cell = [size](float v) {
      return static_cast<int64_t>(std::floor(v / size));
    };
    std::unordered_map<int64_t, std::vector<int>> voxels;
    for (size_t i = 0; i < scan.points.size(); ++i) {
      const Eigen::Vector3f& p = scan.points[i];
      if (!p.allFinite()) continue;
      voxels[PackCellKey(cell(p.x()), cell(p.y()), cell(p.z()))].push_back(
          static_cast<int>(i));
    }
    for (const auto& [voxel_key, voxel_indices] : voxels) {
      if (static_cast<int>(voxel_indices.size()) <
          options.min_points_per_voxel) {
        continue;
      }
      const Eigen::Vector3f& p0 = scan.points[voxel_indices[0]];
      const Eigen::Vector3d lo(cell(p0.x()) * size - margin,
                               cell(p0.y()) * size - margin,
                               cell(p0.z()) * size - margin);
      const Eigen::Vector3d hi =
          lo + Eigen::Vector3d::Constant(size + 2 * margin);
      std::vector<int> indices;
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = voxels.find(PackCellKey(
                cell(p0.x()) + dx, cell(p0.y()) + dy, cell(p0.z()) + dz));
            if (it == voxels.end()) continue;
            for (int i : it->second) {
              const Eigen::Vector3d p = scan.points[i].cast<double>();
              if ((p.array() >= lo.array()).all() &&
                  (p.array() <= hi.array()).all()) {
                indices.push_back(i);
              }
            }
          }
        }
      }
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int i : indices) mean += scan.points[i].cast<double>();
      mean /= indices.size();
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (int i : indices) {
        const Eigen::Vector3d d = scan.points[i].cast<double>() - mean;
        cov += d * d.transpose();
      }
      cov /= indices.size();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(cov);
      const Eigen::Vector3d l = solver.eigenvalues();
      const double min_spread = options.min_spread_fraction * size;
      if (l(1) <= 0 || l(0) / l(1) > options.max_planarity_ratio ||
          std::sqrt(l(1)) < min_spread) {
        continue;
      }
      const Eigen::Vector3d normal = solver.eigenvectors().col(0);
      const double cos_incidence = std::abs(normal.dot(mean.normalized()));
      if (cos_incidence < options.min_incidence_cos) continue;
      for (int i : indices) {
        const double r = normal.dot(scan.points[i].cast<double>() - mean);
        residuals.push_back(std::abs(r) / cos_incidence);
      }
      ++estimate.num_voxels;
    }
  }
  if (residuals.empty()) return estimate;
  const size_t mid = residuals.size() / 2;
  std::nth_element(residuals.begin(), residuals.begin() + mid, residuals.end());
  estimate.sigma_m = 1.4826 * residuals[mid];
  estimate.num_points = static_cast<int>(residuals.size());
  return estimate;
}

double SmoothnessThresholdForNoise(double sigma_m, double range_m,
                                   int num_neighbors, double num_stddev,
                                   double min_threshold) {
  THROW_CHECK(range_m > 0.0,
              "SmoothnessThresholdForNoise: range must be > 0, got " << range_m);
  THROW_CHECK(num_neighbors > 0,
              "SmoothnessThresholdForNoise: num_neighbors must be > 0, got " << num_neighbors);
  THROW_CHECK(sigma_m >= 0.0,
              "SmoothnessThresholdForNoise: sigma must be >= 0, got " << sigma_m);
  const double window = 2.0 * num_neighbors;
  const double stddev = sigma_m / range_m * std::sqrt((window + 1) / window);
  return std::max(min_threshold, num_stddev * stddev);
}

}  // namespace colmap_lidar
