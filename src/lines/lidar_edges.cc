#include "src/lines/lidar_edges.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include <Eigen/Eigenvalues>

#include "colmap_ext/util/cell_key.h"
#include "colmap_ext/util/logging.h"
#include "src/lidar/ring_estimation.h"

namespace colmap_lidar {
namespace {

// One ring's points in azimuth order.
struct Ring {
  // Azimuth steps within [0.5, 1.5] x the median step.
  int num_regular_steps = 0;
  std::vector<int> point_idxs;
  std::vector<double> ranges;
  std::vector<bool> contiguous;
  std::vector<bool> seams;
};

std::vector<uint16_t> RingsOf(const LidarScan& scan, int num_rings) {
  if (scan.HasRings()) {
    return scan.rings;
  }
  std::vector<uint16_t> rings = EstimateRingsFromScanOrder(scan, num_rings);
  if (!rings.empty()) {
    return rings;
  }
  double min_elevation = 90.0;
  double max_elevation = -90.0;
  for (const Eigen::Vector3f& point : scan.points) {
    const double elevation = ElevationDeg(point);
    min_elevation = std::min(min_elevation, elevation);
    max_elevation = std::max(max_elevation, elevation);
  }
  if (!(max_elevation > min_elevation)) {
    max_elevation = min_elevation + 1.0;
  }
  return EstimateRingsFromElevation(scan, num_rings, min_elevation,
                                    max_elevation);
}

std::vector<Ring> BuildRings(const LidarScan& scan,
                             const LidarEdgeOptions& options) {
  const std::vector<uint16_t> ring_ids = RingsOf(scan, options.num_rings);
  int max_ring = 0;
  for (const uint16_t ring : ring_ids) {
    max_ring = std::max<int>(max_ring, ring);
  }
  std::vector<std::vector<std::pair<float, int>>> by_ring(max_ring + 1);
  for (size_t i = 0; i < scan.points.size(); ++i) {
    const Eigen::Vector3f& point = scan.points[i];
    const double range = point.norm();
    if (range < options.min_range || range > options.max_range) {
      continue;
    }
    by_ring[ring_ids[i]].emplace_back(std::atan2(point.y(), point.x()),
                                      static_cast<int>(i));
  }
  // Azimuths relative to the ring's first point in file order, in
  // [0, 2 pi): the ring's seam stays where the sensor started it (KITTI
  // starts the turns straight ahead, where a seam between two lasers at
  // -pi..pi sorting would create spurious range jumps in view).
  for (auto& entries : by_ring) {
    if (entries.empty()) {
      continue;
    }
    const float first = entries.front().first;
    for (auto& entry : entries) {
      float relative = entry.first - first;
      if (relative < 0.0f) {
        relative += static_cast<float>(2.0 * M_PI);
      }
      entry.first = relative;
    }
  }
  std::vector<Ring> rings;
  rings.reserve(by_ring.size());
  std::vector<float> steps;
  for (auto& entries : by_ring) {
    if (entries.size() < 3) {
      continue;
    }
    std::sort(entries.begin(), entries.end());
    Ring ring;
    const size_t n = entries.size();
    ring.point_idxs.resize(n);
    ring.ranges.resize(n);
    steps.resize(n - 1);
    for (size_t i = 0; i < n; ++i) {
      ring.point_idxs[i] = entries[i].second;
      ring.ranges[i] = scan.points[entries[i].second].norm();
      if (i + 1 < n) {
        steps[i] = entries[i + 1].first - entries[i].first;
      }
    }
    std::vector<float> sorted_steps = steps;
    std::nth_element(sorted_steps.begin(),
                     sorted_steps.begin() + sorted_steps.size() / 2,
                     sorted_steps.end());
    const float median_step =
        std::max(sorted_steps[sorted_steps.size() / 2], 1e-6f);
    ring.contiguous.resize(n - 1);
    ring.seams.assign(n - 1, false);
    std::vector<float> elevations(n);
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3f& point = scan.points[ring.point_idxs[i]];
      elevations[i] = std::atan2(point.z(), point.head<2>().norm());
    }
    const float max_elevation_step =
        static_cast<float>(options.max_elevation_step_deg * M_PI / 180.0);
    for (size_t i = 0; i + 1 < n; ++i) {
      // An elevation step at a range jump is the lasers' offset from the
      // origin seen at two ranges (an occlusion), not a seam.
      ring.seams[i] =
          std::abs(elevations[i + 1] - elevations[i]) > max_elevation_step &&
          std::abs(ring.ranges[i + 1] - ring.ranges[i]) <
              options.occlusion_range_gap;
      ring.num_regular_steps += (steps[i] >= 0.5f * median_step &&
                                 steps[i] <= 1.5f * median_step)
                                    ? 1
                                    : 0;
      ring.contiguous[i] =
          steps[i] <= options.max_azimuth_gap_steps * median_step &&
          !ring.seams[i];
    }
    rings.push_back(std::move(ring));
  }
  return rings;
}

// Fraction of regular azimuth steps over all rings.
double RegularStepFraction(const std::vector<Ring>& rings) {
  int64_t num_regular = 0;
  int64_t num_steps = 0;
  for (const Ring& ring : rings) {
    num_regular += ring.num_regular_steps;
    num_steps += static_cast<int64_t>(ring.contiguous.size());
  }
  return num_steps > 0 ? static_cast<double>(num_regular) / num_steps : 0.0;
}

}  // namespace

double OcclusionRangeGap(const LidarEdgeOptions& options, double range) {
  return options.occlusion_range_ratio > 0.0
             ? std::min(options.occlusion_range_gap,
                        options.occlusion_range_ratio * range)
             : options.occlusion_range_gap;
}

bool LidarEdgeOptions::Check() const {
  if (method != "auto" && method != "ring" && method != "pca") {
    LOG(ERROR) << "LineExtraction.edge_method must be auto, ring or pca, got "
               << method;
    return false;
  }
  if (num_rings < 1 || num_rings > 65535) {
    LOG(ERROR) << "LineExtraction.edge_num_rings must be in [1, 65535]";
    return false;
  }
  if (num_neighbors < 1) {
    LOG(ERROR) << "LineExtraction.edge_num_neighbors must be >= 1";
    return false;
  }
  if (!(smoothness_threshold >= 0.0)) {
    LOG(ERROR) << "LineExtraction.edge_smoothness_threshold must be >= 0";
    return false;
  }
  if (num_sectors < 1) {
    LOG(ERROR) << "LineExtraction.edge_num_sectors must be >= 1";
    return false;
  }
  if (max_edges_per_sector < 1) {
    LOG(ERROR) << "LineExtraction.edge_max_edges_per_sector must be >= 1";
    return false;
  }
  if (!(occlusion_range_gap > 0.0) || !(parallel_beam_ratio > 0.0)) {
    LOG(ERROR) << "LineExtraction.edge_occlusion_range_gap and "
                  "edge_parallel_beam_ratio must be > 0";
    return false;
  }
  if (!(occlusion_range_ratio >= 0.0)) {
    LOG(ERROR) << "LineExtraction.edge_occlusion_range_ratio must be >= 0";
    return false;
  }
  if (!(max_elevation_step_deg > 0.0)) {
    LOG(ERROR) << "LineExtraction.edge_max_elevation_step_deg must be > 0";
    return false;
  }
  if (!(max_azimuth_gap_steps >= 1.0)) {
    LOG(ERROR) << "LineExtraction.edge_max_azimuth_gap_steps must be >= 1";
    return false;
  }
  if (!(min_range >= 0.0 && max_range > min_range)) {
    LOG(ERROR) << "LineExtraction.edge_min_range / edge_max_range: need 0 <= "
                  "min < max";
    return false;
  }
  if (!(min_regular_step_fraction >= 0.0 &&
        min_regular_step_fraction <= 1.0)) {
    LOG(ERROR)
        << "LineExtraction.edge_min_regular_step_fraction must be in [0, 1]";
    return false;
  }
  if (!(pca_radius > 0.0) || pca_min_neighbors < 3 ||
      !(pca_min_surface_variation > 0.0)) {
    LOG(ERROR) << "LineExtraction.edge_pca_*: need radius > 0, min_neighbors "
                  ">= 3, min_surface_variation > 0";
    return false;
  }
  return true;
}

std::vector<double> ComputeRingSmoothness(const std::vector<double>& ranges,
                                          const std::vector<bool>& contiguous,
                                          const int num_neighbors,
                                          const bool edges_at_gaps,
                                          const std::vector<bool>& seams) {
  const int n = static_cast<int>(ranges.size());
  THROW_CHECK(n == 0 || static_cast<int>(contiguous.size()) == n - 1,
              "ComputeRingSmoothness: contiguous must have n - 1 entries");
  std::vector<double> smoothness(n, -1.0);
  // breaks[i] = number of non-contiguous pairs among (0,1) .. (i-1,i).
  std::vector<int> breaks(n, 0);
  for (int i = 1; i < n; ++i) {
    breaks[i] = breaks[i - 1] + (contiguous[i - 1] ? 0 : 1);
  }
  const int k = num_neighbors;
  for (int i = k; i + k < n; ++i) {
    if (breaks[i + k] != breaks[i - k]) {
      // A gap right after i with k contiguous points before, or right
      // before i with k contiguous points after.
      auto is_gap = [&](int pair) {
        return !contiguous[pair] && (seams.empty() || !seams[pair]);
      };
      const bool gap_after = is_gap(i) && breaks[i] == breaks[i - k];
      const bool gap_before = is_gap(i - 1) && breaks[i + k] == breaks[i];
      if (edges_at_gaps && (gap_after || gap_before)) {
        smoothness[i] = 1.0;
      }
      continue;
    }
    double sum = 0.0;
    for (int j = i - k; j <= i + k; ++j) {
      sum += ranges[j];
    }
    sum -= (2 * k + 1) * ranges[i];
    smoothness[i] = std::abs(sum) / (2 * k * ranges[i]);
  }
  return smoothness;
}

std::vector<int> SelectRingEdges(const std::vector<double>& ranges,
                                 const std::vector<bool>& contiguous,
                                 const LidarEdgeOptions& options,
                                 const std::vector<bool>& seams) {
  const int n = static_cast<int>(ranges.size());
  const int k = options.num_neighbors;
  const std::vector<double> smoothness =
      ComputeRingSmoothness(ranges, contiguous, k, options.edges_at_gaps,
                            seams);
  std::vector<bool> excluded(n, false);
  auto exclude = [&](int from, int to) {
    for (int j = std::max(from, 0); j <= std::min(to, n - 1); ++j) {
      excluded[j] = true;
    }
  };
  // Occluded side of a depth jump: the farther points next to the jump.
  for (int i = 0; i + 1 < n; ++i) {
    if (!contiguous[i]) {
      continue;
    }
    const double difference = ranges[i] - ranges[i + 1];
    const double gap = OcclusionRangeGap(
        options, std::min(ranges[i], ranges[i + 1]));
    if (difference > gap) {
      exclude(i - k, i);
    } else if (-difference > gap) {
      exclude(i + 1, i + 1 + k);
    }
  }
  // Surfaces nearly parallel to the beam.
  for (int i = 1; i + 1 < n; ++i) {
    const double limit = options.parallel_beam_ratio * ranges[i];
    if (std::abs(ranges[i - 1] - ranges[i]) > limit &&
        std::abs(ranges[i + 1] - ranges[i]) > limit) {
      excluded[i] = true;
    }
  }

  std::vector<int> edges;
  const int first = k;
  const int last = n - k;  // exclusive
  if (last <= first) {
    return edges;
  }
  std::vector<int> order;
  for (int sector = 0; sector < options.num_sectors; ++sector) {
    const int begin = first + (last - first) * sector / options.num_sectors;
    const int end = first + (last - first) * (sector + 1) / options.num_sectors;
    order.resize(end - begin);
    std::iota(order.begin(), order.end(), begin);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return smoothness[a] > smoothness[b];
    });
    int count = 0;
    for (const int i : order) {
      if (smoothness[i] <= options.smoothness_threshold ||
          count >= options.max_edges_per_sector) {
        break;
      }
      if (excluded[i]) {
        continue;
      }
      edges.push_back(i);
      ++count;
      exclude(i - k, i + k);
    }
  }
  std::sort(edges.begin(), edges.end());
  return edges;
}

std::vector<int> DetectLidarEdgesPca(const LidarScan& scan,
                                     const LidarEdgeOptions& options) {
  const double radius = options.pca_radius;
  const double inv_cell = 1.0 / radius;
  std::unordered_map<int64_t, std::vector<int>> grid;
  std::vector<Eigen::Vector3i> cells(scan.points.size());
  for (size_t i = 0; i < scan.points.size(); ++i) {
    const Eigen::Vector3f& p = scan.points[i];
    cells[i] = Eigen::Vector3i(static_cast<int>(std::floor(p.x() * inv_cell)),
                               static_cast<int>(std::floor(p.y() * inv_cell)),
                               static_cast<int>(std::floor(p.z() * inv_cell)));
    grid[PackCellKey(cells[i].x(), cells[i].y(), cells[i].z())].push_back(
        static_cast<int>(i));
  }
  std::vector<int> edges;
  const double radius2 = radius * radius;
  for (size_t i = 0; i < scan.points.size(); ++i) {
    const Eigen::Vector3d center = scan.points[i].cast<double>();
    const double range = center.norm();
    if (range < options.min_range || range > options.max_range) {
      continue;
    }
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d sum2 = Eigen::Matrix3d::Zero();
    int count = 0;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(PackCellKey(
              cells[i].x() + dx, cells[i].y() + dy, cells[i].z() + dz));
          if (it == grid.end()) {
            continue;
          }
          for (const int j : it->second) {
            const Eigen::Vector3d q = scan.points[j].cast<double>() - center;
            if (q.squaredNorm() <= radius2) {
              sum += q;
              sum2 += q * q.transpose();
              ++count;
            }
          }
        }
      }
    }
    if (count < options.pca_min_neighbors) {
      continue;
    }
    const Eigen::Vector3d mean = sum / count;
    const Eigen::Matrix3d covariance = sum2 / count - mean * mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(covariance, Eigen::EigenvaluesOnly);
    const Eigen::Vector3d eigenvalues = solver.eigenvalues();
    const double total = eigenvalues.sum();
    if (total > 0 &&
        eigenvalues(0) / total > options.pca_min_surface_variation) {
      edges.push_back(static_cast<int>(i));
    }
  }
  return edges;
}

std::vector<int> DetectLidarEdges(const LidarScan& scan,
                                  const LidarEdgeOptions& options,
                                  RingNeighbors* ring_neighbors) {
  if (ring_neighbors != nullptr) {
    ring_neighbors->prev.clear();
    ring_neighbors->next.clear();
  }
  THROW_CHECK(scan.rings.empty() || scan.rings.size() == scan.points.size(),
              "DetectLidarEdges: ring channel size differs from points");
  if (options.method == "pca") {
    return DetectLidarEdgesPca(scan, options);
  }
  const std::vector<Ring> rings = BuildRings(scan, options);
  if (options.method == "auto") {
    const double fraction = RegularStepFraction(rings);
    if (fraction < options.min_regular_step_fraction) {
      LOG(WARNING) << "Scan does not look ring-organised (" << fraction
                   << " of the azimuth steps are regular); using the PCA "
                      "edge detector";
      return DetectLidarEdgesPca(scan, options);
    }
  }
  if (ring_neighbors != nullptr) {
    ring_neighbors->prev.assign(scan.points.size(), -1);
    ring_neighbors->next.assign(scan.points.size(), -1);
    for (const Ring& ring : rings) {
      for (size_t i = 0; i + 1 < ring.point_idxs.size(); ++i) {
        if (ring.contiguous[i]) {
          ring_neighbors->next[ring.point_idxs[i]] = ring.point_idxs[i + 1];
          ring_neighbors->prev[ring.point_idxs[i + 1]] = ring.point_idxs[i];
        }
      }
    }
  }
  std::vector<int> edges;
  for (const Ring& ring : rings) {
    for (const int position :
         SelectRingEdges(ring.ranges, ring.contiguous, options, ring.seams)) {
      edges.push_back(ring.point_idxs[position]);
    }
  }
  std::sort(edges.begin(), edges.end());
  return edges;
}

}  // namespace colmap_lidar
