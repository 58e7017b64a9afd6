// Crispness of the LIDAR map (see real_data_evaluator.h).
#include "src/eval/real_data_evaluator.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <Eigen/Eigenvalues>

#include "colmap_ext/util/logging.h"
#include "src/lidar/gicp_helpers.h"

namespace colmap_lidar {
namespace {

// Value at quantile q of `values` (nearest rank); 0 when empty.
double Quantile(std::vector<double> values, double q) {
  if (values.empty()) {
    return 0.0;
  }
  const size_t k = std::min(
      values.size() - 1,
      static_cast<size_t>(std::floor(q * static_cast<double>(values.size()))));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

struct CellKeyHash {
  size_t operator()(const Eigen::Vector3i& key) const {
    return static_cast<size_t>(key.x()) * 73856093u ^
           static_cast<size_t>(key.y()) * 19349663u ^
           static_cast<size_t>(key.z()) * 83492791u;
  }
};

Eigen::Vector3i CellOf(const Eigen::Vector3d& point, double cell_m) {
  return Eigen::Vector3i(static_cast<int>(std::floor(point.x() / cell_m)),
                         static_cast<int>(std::floor(point.y() / cell_m)),
                         static_cast<int>(std::floor(point.z() / cell_m)));
}

}  // namespace

double CrispnessVoxelSize(const LidarScan& first_scan,
                          const RealDataEvaluationOptions& options) {
  if (options.crispness_voxel_size_m > 0.0) {
    return options.crispness_voxel_size_m;
  }
  std::vector<double> ranges;
  ranges.reserve(first_scan.size());
  for (const Eigen::Vector3f& point : first_scan.points) {
    const double range = point.cast<double>().norm();
    if (range >= options.registration.min_range_m &&
        range <= options.registration.max_range_m) {
      ranges.push_back(range);
    }
  }
  const double median_range = Quantile(std::move(ranges), 0.5);
  return std::clamp(median_range * options.crispness_voxel_angle_deg * M_PI /
                        180.0,
                    0.05, 0.3);
}

std::vector<Eigen::Vector3d> ThinScan(const LidarScan& scan, double voxel_m,
                                      const RealDataEvaluationOptions& options) {
  THROW_CHECK(voxel_m > 0.0, "ThinScan: voxel " << voxel_m << " m");
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    size_t order = 0;
  };
  std::unordered_map<Eigen::Vector3i, Cell, CellKeyHash> cells;
  for (const Eigen::Vector3f& point_f : scan.points) {
    const Eigen::Vector3d point = point_f.cast<double>();
    const double range = point.norm();
    if (!point.allFinite() || range < options.registration.min_range_m ||
        range > options.registration.max_range_m) {
      continue;
    }
    Cell& cell = cells[CellOf(point, voxel_m)];
    if (cell.count == 0) {
      cell.order = cells.size();
    }
    cell.sum += point;
    ++cell.count;
  }
  // In first-seen order, so that strided queries sample the whole scan
  // deterministically.
  std::vector<std::pair<size_t, Eigen::Vector3d>> ordered;
  ordered.reserve(cells.size());
  for (const auto& [key, cell] : cells) {
    ordered.emplace_back(cell.order, cell.sum / cell.count);
  }
  std::sort(ordered.begin(), ordered.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::Vector3d> thinned;
  thinned.reserve(ordered.size());
  for (const auto& entry : ordered) {
    thinned.push_back(entry.second);
  }
  return thinned;
}

CrispnessStats EvaluateCrispness(
    const std::vector<std::vector<Eigen::Vector3d>>& thinned_scans,
    const std::vector<Rigid3d>& world_from_lidar, double radius_m,
    const RealDataEvaluationOptions& options) {
  THROW_CHECK(options.Check(), "invalid RealDataEvaluation options");
  THROW_CHECK(thinned_scans.size() == world_from_lidar.size() &&
                  thinned_scans.size() >= 2,
              "Crispness needs >= 2 scans with one pose each, got "
                  << thinned_scans.size() << " scans and "
                  << world_from_lidar.size() << " poses");
  THROW_CHECK(radius_m > 0.0, "Crispness radius " << radius_m << " m");
  const size_t num_scans = thinned_scans.size();

  // All points in the world, and a hash grid of radius-sized cells.
  std::vector<Eigen::Vector3d> points;
  std::vector<uint32_t> scan_of_point;
  std::vector<size_t> scan_begin(num_scans + 1, 0);
  for (size_t s = 0; s < num_scans; ++s) {
    scan_begin[s] = points.size();
    for (const Eigen::Vector3d& point : thinned_scans[s]) {
      points.push_back(world_from_lidar[s] * point);
      scan_of_point.push_back(static_cast<uint32_t>(s));
    }
  }
  scan_begin[num_scans] = points.size();
  std::unordered_map<Eigen::Vector3i, std::vector<uint32_t>, CellKeyHash> grid;
  for (size_t i = 0; i < points.size(); ++i) {
    grid[CellOf(points[i], radius_m)].push_back(static_cast<uint32_t>(i));
  }

  // Queries: evenly strided points of every scan.
  std::vector<uint32_t> queries;
  for (size_t s = 0; s < num_scans; ++s) {
    const size_t count = scan_begin[s + 1] - scan_begin[s];
    const size_t stride = std::max<size_t>(
        1, (count + options.crispness_max_queries_per_scan - 1) /
               options.crispness_max_queries_per_scan);
    for (size_t k = 0; k < count; k += stride) {
      queries.push_back(static_cast<uint32_t>(scan_begin[s] + k));
    }
  }
  // Distance per query; negative: no plane.
  std::vector<double> distances(queries.size(), -1.0);
  const double radius_squared = radius_m * radius_m;
  ParallelFor(queries.size(), options.num_threads, [&](size_t begin,
                                                          size_t end) {
    std::vector<Eigen::Vector3d> neighbors;
    for (size_t q = begin; q < end; ++q) {
      const Eigen::Vector3d& query = points[queries[q]];
      const uint32_t own_scan = scan_of_point[queries[q]];
      const Eigen::Vector3i cell = CellOf(query, radius_m);
      neighbors.clear();
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = grid.find(cell + Eigen::Vector3i(dx, dy, dz));
            if (it == grid.end()) {
              continue;
            }
            for (const uint32_t index : it->second) {
              if (scan_of_point[index] != own_scan &&
                  (points[index] - query).squaredNorm() <= radius_squared) {
                neighbors.push_back(points[index]);
              }
            }
          }
        }
      }
      if (static_cast<int>(neighbors.size()) <
          options.crispness_min_neighbors) {
        continue;
      }
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (const Eigen::Vector3d& neighbor : neighbors) {
        centroid += neighbor;
      }
      centroid /= static_cast<double>(neighbors.size());
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (const Eigen::Vector3d& neighbor : neighbors) {
        const Eigen::Vector3d d = neighbor - centroid;
        covariance += d * d.transpose();
      }
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
      const Eigen::Vector3d eigenvalues = solver.eigenvalues();  // Ascending.
      if (!(eigenvalues(1) >=
                options.crispness_min_planarity * eigenvalues(2) &&
            eigenvalues(2) > 0.0)) {
        continue;
      }
      const Eigen::Vector3d normal = solver.eigenvectors().col(0);
      distances[q] = std::abs(normal.dot(query - centroid));
    }
  });

  CrispnessStats stats;
  stats.num_queries = queries.size();
  std::vector<double> valid;
  std::vector<std::vector<double>> per_frame(num_scans);
  for (size_t q = 0; q < queries.size(); ++q) {
    if (distances[q] >= 0.0) {
      valid.push_back(distances[q]);
      per_frame[scan_of_point[queries[q]]].push_back(distances[q]);
    }
  }
  stats.num_planes = valid.size();
  stats.coverage = queries.empty() ? 0.0
                                   : static_cast<double>(valid.size()) /
                                         static_cast<double>(queries.size());
  stats.median_m = Quantile(valid, 0.5);
  stats.p90_m = Quantile(std::move(valid), 0.9);
  for (std::vector<double>& frame : per_frame) {
    stats.frame_median_m.push_back(Quantile(std::move(frame), 0.5));
  }
  return stats;
}

}  // namespace colmap_lidar
