#include "src/lidar/free_space_filter.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <unordered_map>
#include <vector>

#include <glog/logging.h>

#include "colmap_ext/util/cell_key.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/parallel.h"
#include "src/lidar/ring_estimation.h"

namespace colmap_lidar {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
// Elevation gaps below this are returns of the same ring, degrees.
constexpr double kSameRingGapDeg = 0.02;
// Azimuth column width of the ring-gap estimate, degrees: narrow enough
// that a ring crosses a column at one elevation, wide enough to hold a
// return of most rings.
constexpr double kGapColumnDeg = 0.5;
// Cell size bounds, degrees (a ring gap outside them is not a ring gap).
constexpr double kMinCellDeg = 0.05;
constexpr double kMaxCellDeg = 5.0;
// Range images per chunk of voxels: voxels are independent, chunks keep
// the per-voxel work large enough for the threads.
constexpr int kVoxelsPerChunk = 4096;

double AzimuthDeg(const Eigen::Vector3d& p) {
  const double a = std::atan2(p.y(), p.x()) * kRadToDeg;
  return a < 0 ? a + 360.0 : a;
}

// The scans whose origin may lie within `reach` of a point: the origins in
// a grid of cells `reach` wide, the 27 cells around the point. A voxel then
// tests only the scans near it instead of all of them (a scan farther than
// max_range_m gives no evidence anyway): the test grew with the square of
// the frames (600 frames of a 700 m street: 260 s).
class ScanOriginGrid {
 public:
  ScanOriginGrid(const std::vector<Eigen::Vector3d>& origins, double reach)
      : reach_(reach) {
    for (size_t k = 0; k < origins.size(); ++k) {
      cells_[Key(Cell(origins[k]))].push_back(static_cast<uint32_t>(k));
    }
  }

  // Appends the candidates around `point` to `out` (cleared first).
  void Near(const Eigen::Vector3d& point, std::vector<uint32_t>* out) const {
    out->clear();
    const Eigen::Vector3i c = Cell(point);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(Key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it != cells_.end()) {
            out->insert(out->end(), it->second.begin(), it->second.end());
          }
        }
      }
    }
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3d& p) const {
    return (p / reach_).array().floor().cast<int>();
  }
  static int64_t Key(const Eigen::Vector3i& c) {
    return PackCellKey(c.x(), c.y(), c.z());
  }

  double reach_;
  std::unordered_map<int64_t, std::vector<uint32_t>> cells_;
};

}  // namespace

bool FreeSpaceFilterOptions::Check() const {
  if (!(neighborhood_ring_gaps > 0)) {
    LOG(ERROR) << "LidarFusion.free_space_neighborhood_ring_gaps must be > 0";
    return false;
  }
  if (!(margin_voxels > 0)) {
    LOG(ERROR) << "LidarFusion.free_space_margin_voxels must be > 0";
    return false;
  }
  if (min_see_through_frames < 1) {
    LOG(ERROR) << "LidarFusion.free_space_min_see_through_frames must be >= 1";
    return false;
  }
  return true;
}

double EstimateRingGapDeg(const LidarScan& scan) {
  const int num_columns = static_cast<int>(std::lround(360.0 / kGapColumnDeg));
  std::vector<std::vector<float>> columns(num_columns);
  for (const Eigen::Vector3f& point : scan.points) {
    const Eigen::Vector3d p = point.cast<double>();
    if (p.squaredNorm() == 0) {
      continue;
    }
    const int column = std::min(
        num_columns - 1, static_cast<int>(AzimuthDeg(p) / kGapColumnDeg));
    columns[column].push_back(static_cast<float>(ElevationDeg(point)));
  }
  std::vector<float> gaps;
  for (std::vector<float>& column : columns) {
    std::sort(column.begin(), column.end());
    for (size_t i = 1; i < column.size(); ++i) {
      const float gap = column[i] - column[i - 1];
      if (gap > kSameRingGapDeg) {
        gaps.push_back(gap);
      }
    }
  }
  if (gaps.empty()) {
    return 0.0;
  }
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  return gaps[gaps.size() / 2];
}

SphericalRangeImage::SphericalRangeImage(const LidarScan& scan,
                                         double min_range_m,
                                         double max_range_m, double cell_deg,
                                         int half_width_cells)
    : cell_deg_(cell_deg) {
  THROW_CHECK(cell_deg > 0 && half_width_cells >= 0,
              "SphericalRangeImage: cell_deg must be > 0 and the half width "
              ">= 0");
  double min_elevation = std::numeric_limits<double>::infinity();
  double max_elevation = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3f& point : scan.points) {
    const double range = point.cast<double>().norm();
    if (range < min_range_m || range > max_range_m || range == 0) {
      continue;
    }
    const double elevation = ElevationDeg(point);
    min_elevation = std::min(min_elevation, elevation);
    max_elevation = std::max(max_elevation, elevation);
  }
  if (!(max_elevation >= min_elevation)) {
    return;  // No return in range: every direction gives no evidence.
  }
  min_elevation_deg_ = min_elevation;
  num_rows_ = static_cast<int>((max_elevation - min_elevation) / cell_deg) + 1;
  num_cols_ = std::max(1, static_cast<int>(std::ceil(360.0 / cell_deg)));
  const float kNone = std::numeric_limits<float>::infinity();
  std::vector<float> raw(static_cast<size_t>(num_rows_) * num_cols_, kNone);
  for (const Eigen::Vector3f& point : scan.points) {
    const Eigen::Vector3d p = point.cast<double>();
    const double range = p.norm();
    if (range < min_range_m || range > max_range_m || range == 0) {
      continue;
    }
    const int row = std::min(
        num_rows_ - 1,
        static_cast<int>((ElevationDeg(point) - min_elevation_deg_) / cell_deg));
    const int col =
        std::min(num_cols_ - 1, static_cast<int>(AzimuthDeg(p) / cell_deg));
    float& cell = raw[static_cast<size_t>(row) * num_cols_ + col];
    cell = std::min(cell, static_cast<float>(range));
  }
  // Separable min filter: azimuth (wrapping), then elevation (clamped).
  std::vector<float> along(raw.size(), kNone);
  const int h = half_width_cells;
  for (int row = 0; row < num_rows_; ++row) {
    const float* in = &raw[static_cast<size_t>(row) * num_cols_];
    float* out = &along[static_cast<size_t>(row) * num_cols_];
    for (int col = 0; col < num_cols_; ++col) {
      float nearest = kNone;
      for (int d = -h; d <= h; ++d) {
        const int c = ((col + d) % num_cols_ + num_cols_) % num_cols_;
        nearest = std::min(nearest, in[c]);
      }
      out[col] = nearest;
    }
  }
  nearest_.assign(raw.size(), kNone);
  for (int row = 0; row < num_rows_; ++row) {
    const int first = std::max(0, row - h);
    const int last = std::min(num_rows_ - 1, row + h);
    for (int col = 0; col < num_cols_; ++col) {
      float nearest = kNone;
      for (int r = first; r <= last; ++r) {
        nearest = std::min(nearest, along[static_cast<size_t>(r) * num_cols_ + col]);
      }
      nearest_[static_cast<size_t>(row) * num_cols_ + col] = nearest;
    }
  }
}

double SphericalRangeImage::NearestRangeAround(
    const Eigen::Vector3d& point_in_lidar) const {
  if (num_rows_ == 0 || point_in_lidar.squaredNorm() == 0) {
    return -1.0;
  }
  const double row_position =
      (ElevationDeg(point_in_lidar.cast<float>()) - min_elevation_deg_) / cell_deg_;
  if (row_position < 0 || row_position >= num_rows_) {
    return -1.0;  // Above the highest or below the lowest ring.
  }
  const int row = static_cast<int>(row_position);
  const int col = std::min(num_cols_ - 1,
                           static_cast<int>(AzimuthDeg(point_in_lidar) / cell_deg_));
  const float nearest = nearest_[static_cast<size_t>(row) * num_cols_ + col];
  return std::isfinite(nearest) ? static_cast<double>(nearest) : -1.0;
}

std::vector<bool> FindMovingVoxels(
    const std::vector<Eigen::Vector3d>& centroids,
    const std::vector<std::vector<uint32_t>>& hit_frames,
    const std::vector<FreeSpaceScan>& scans, double voxel_size_m,
    double min_range_m, double max_range_m,
    const FreeSpaceFilterOptions& options) {
  THROW_CHECK(options.Check(), "invalid free-space filter options");
  THROW_CHECK(centroids.size() == hit_frames.size(),
              "FindMovingVoxels: " << centroids.size() << " centroids but "
                                   << hit_frames.size() << " hit lists");
  THROW_CHECK(voxel_size_m > 0, "FindMovingVoxels: voxel size must be > 0");
  std::vector<bool> moving(centroids.size(), false);
  if (!options.enabled || scans.size() < 2) {
    return moving;
  }
  // One range image per scan, its cells half a ring gap wide.
  std::vector<SphericalRangeImage> images;
  std::vector<Rigid3d> lidar_from_world;
  images.reserve(scans.size());
  std::vector<double> gaps;
  for (const FreeSpaceScan& scan : scans) {
    THROW_CHECK(scan.scan != nullptr, "FindMovingVoxels: a scan is missing");
    double gap = EstimateRingGapDeg(*scan.scan);
    if (!(gap > 0)) {
      gap = 2.0 * kMinCellDeg;
    }
    gaps.push_back(gap);
    const double cell = std::clamp(0.5 * gap, kMinCellDeg, kMaxCellDeg);
    const int half_width = static_cast<int>(
        std::ceil(options.neighborhood_ring_gaps * gap / cell - 1e-9));
    images.emplace_back(*scan.scan, min_range_m, max_range_m, cell,
                        half_width);
    lidar_from_world.push_back(scan.world_from_lidar.Inverse());
  }
  const double margin = options.margin_voxels * voxel_size_m;
  // Scans beyond max_range_m of a voxel are skipped before the exact range
  // test; 1 m of slack keeps every scan that test could keep. An unbounded
  // range (or a scene too large for the grid's cells) tests them all.
  std::vector<Eigen::Vector3d> origins;
  for (const FreeSpaceScan& scan : scans) {
    origins.push_back(scan.world_from_lidar.translation);
  }
  const double reach = max_range_m + 1.0;
  std::optional<ScanOriginGrid> grid;
  double extent = 0.0;
  for (const Eigen::Vector3d& origin : origins) {
    extent = std::max(extent, origin.cwiseAbs().maxCoeff());
  }
  if (std::isfinite(reach) && extent / reach < 1e5) {
    grid.emplace(origins, reach);
  }
  const int num_voxels = static_cast<int>(centroids.size());
  const int num_chunks = (num_voxels + kVoxelsPerChunk - 1) / kVoxelsPerChunk;
  std::vector<char> flags(centroids.size(), 0);
  ParallelFor(0, num_chunks, -1, [&](int chunk) {
    const int end = std::min(num_voxels, (chunk + 1) * kVoxelsPerChunk);
    std::vector<char> hit(scans.size(), 0);
    std::vector<uint32_t> candidates;
    if (!grid) {
      for (size_t k = 0; k < scans.size(); ++k) {
        candidates.push_back(static_cast<uint32_t>(k));
      }
    }
    for (int v = chunk * kVoxelsPerChunk; v < end; ++v) {
      if (grid) grid->Near(centroids[v], &candidates);
      int num_hit = 0;
      for (const uint32_t k : hit_frames[v]) {
        if (k < hit.size() && !hit[k]) {
          hit[k] = 1;
          ++num_hit;
        }
      }
      int num_through = 0;
      for (const uint32_t k : candidates) {
        if (hit[k]) {
          continue;
        }
        const Eigen::Vector3d p = lidar_from_world[k] * centroids[v];
        const double range = p.norm();
        if (range < min_range_m || range > max_range_m) {
          continue;
        }
        const double nearest = images[k].NearestRangeAround(p);
        if (nearest >= 0 && nearest > range + margin) {
          ++num_through;
        }
      }
      for (const uint32_t k : hit_frames[v]) {
        if (k < hit.size()) hit[k] = 0;
      }
      flags[v] = num_through >= options.min_see_through_frames &&
                 num_through > num_hit;
    }
  });
  size_t num_moving = 0;
  for (size_t v = 0; v < flags.size(); ++v) {
    moving[v] = flags[v] != 0;
    num_moving += flags[v] != 0;
  }
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  LOG(INFO) << "LIDAR free-space filter: " << num_moving << " of "
            << centroids.size() << " voxels seen through by other scans "
            << "(moving objects) dropped; ring gap " << gaps[gaps.size() / 2]
            << " deg (median of " << scans.size() << " scans), margin "
            << margin << " m";
  return moving;
}

}  // namespace colmap_lidar
