// Moving objects out of the fused LIDAR cloud, by free-space evidence.
//
// A static surface hit by one scan is hit, or hidden, in every other scan
// that looks its way; a vehicle that moved is not: a later (or earlier)
// scan's rays pass through the place where it was and return from what lies
// behind. On the KITTI sample (a traffic jam, 20 frames) 17 % of the LIDAR
// points in the cameras' view moved by 0.3 m or more between frames; fused
// as they are, they smear trails that no static mesh can hold (see
// docs/benchmarks/matrix.md, the KITTI traffic section).
//
// Test, per voxel of the fusion (centroid c) and per scan k (origin o_k):
// the direction of c from o_k falls into a cell of scan k's spherical range
// image (azimuth x elevation); the image is min-filtered over a neighbourhood
// of +-neighborhood_ring_gaps ring spacings in both angles first, so that the
// nearest return around the direction counts (a ray grazing the ground, or
// a pole thinner than a cell, has a nearer neighbour and does not see through
// the surface it runs along). Scan k sees through the voxel when that
// nearest return lies more than margin beyond |c - o_k|. Directions outside
// the scan's elevation span, beyond its range limits, or with no return in
// the neighbourhood (sky, dropouts) give no evidence either way. A voxel is
// moving when at least min_see_through_frames scans see through it and they
// outnumber the scans that hit it: a car parked for the whole recording is hit
// by every scan and stays; the road a car uncovers is hidden (nearer
// return), not seen through, in the scans that saw the car.
//
// Cost: one range image per scan in memory (about 1 MB for a KITTI scan,
// 2 MB for an OS1-128 one) and every voxel tested against the scans whose
// origin lies within max_range_m of it (a grid over the origins; the others
// give no evidence): 6 s for KITTI's 20 scans and 749 k voxels on 2 cores,
// and linear in the frames of a walk longer than the LIDAR's range (it
// was quadratic before: issue 19).
//
// Ring spacing from the data: per scan, the median of the elevation gaps
// between the returns of one azimuth column (gaps below 0.02 deg are the
// same ring); 2 deg for a VLP-16, about 0.4 deg for KITTI's HDL-64E.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {

struct FreeSpaceFilterOptions {
  // Drop moving voxels from the fusion, 0/1.
  bool enabled = true;
  // Half-width of the min-filter neighbourhood, in ring spacings, > 0: one
  // spacing and a half reaches the next ring on both sides.
  double neighborhood_ring_gaps = 1.5;
  // A return must lie this many voxel edges beyond the voxel to see through
  // it, > 0: 5 x 5 cm = 0.25 m, ten times KITTI's 2 cm range noise plus the
  // voxel's own extent, less than a creeping car's move between frames.
  double margin_voxels = 5.0;
  // Scans that must see through a voxel before it can be dropped, >= 1.
  int min_see_through_frames = 2;

  bool Check() const;
};

// The median elevation gap between neighbouring rings of `scan`, degrees
// (see the file comment); 0 when the scan has fewer than two rings' worth
// of returns in any column.
double EstimateRingGapDeg(const LidarScan& scan);

// A scan's spherical range image, min-filtered (see the file comment).
class SphericalRangeImage {
 public:
  // Points outside [min_range_m, max_range_m] are ignored. cell_deg > 0,
  // half_width_cells >= 0: the min filter covers (2 h + 1)^2 cells.
  SphericalRangeImage(const LidarScan& scan, double min_range_m,
                      double max_range_m, double cell_deg,
                      int half_width_cells);

  // The nearest return around the direction of `point_in_lidar`, metres;
  // negative when the direction lies outside the scan's elevation span or
  // no return lies in its neighbourhood.
  double NearestRangeAround(const Eigen::Vector3d& point_in_lidar) const;

 private:
  double cell_deg_ = 1.0;
  double min_elevation_deg_ = 0.0;
  int num_rows_ = 0;
  int num_cols_ = 0;
  // Row-major, +inf where no return lies in the neighbourhood.
  std::vector<float> nearest_;
};

// One scan as the filter sees it.
struct FreeSpaceScan {
  const LidarScan* scan = nullptr;  // LIDAR frame; not owned.
  Rigid3d world_from_lidar;
};

// Per voxel: true = moving. `centroids` are world points; `hit_frames[v]`
// the indices into `scans` of the scans with points in voxel v (any order,
// no duplicates needed). voxel_size_m > 0 scales the margin; points nearer
// / farther than min_range_m / max_range_m from a scanner give it no
// evidence. Throws on options that fail Check() or mismatched sizes.
std::vector<bool> FindMovingVoxels(
    const std::vector<Eigen::Vector3d>& centroids,
    const std::vector<std::vector<uint32_t>>& hit_frames,
    const std::vector<FreeSpaceScan>& scans, double voxel_size_m,
    double min_range_m, double max_range_m,
    const FreeSpaceFilterOptions& options);

}  // namespace colmap_lidar
