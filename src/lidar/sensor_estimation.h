// Sensor parameters estimated from the scans themselves, so that thresholds
// need not be tuned for one LIDAR (issue 14). For now: the range noise.
//
// Range noise: the points are bucketed into cubic voxels; in each voxel with
// enough points a plane is fitted by PCA (eigenvalues l0 <= l1 <= l2) and
// kept only when planar (l0 < l1 / 4, both in-plane directions spread). The
// residual of a point along the normal is its range error times
// |cos(angle between beam and normal)|, so residuals are divided by that
// cosine (voxels seen at grazing incidence, cosine below 0.5, are skipped).
// sigma = 1.4826 * median |residual / cos| over all kept points (a MAD, robust
// to the few voxels that straddle a crease).
#pragma once

#include <vector>

#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {

struct RangeNoiseOptions {
  // Edge of the voxels a plane is fitted in, metres.
  double voxel_size = 1.0;
  // Minimum points per voxel for a plane fit.
  int min_points_per_voxel = 30;
  // A voxel is planar when l0 / l1 is below this (dimensionless). Loose on
  // purpose: a tight bound keeps only the voxels whose noise happened to be
  // small and biases sigma low; the median absorbs the creases it lets in.
  double max_planarity_ratio = 0.25;
  // Both in-plane spreads (sqrt(l1), sqrt(l2)) must exceed this fraction of
  // the voxel size, so that a voxel holding one or two rings (nearly a line,
  // whose "plane" would absorb the noise) is skipped.
  double min_spread_fraction = 0.15;
  // Voxels whose mean beam is closer than this to the plane (|cos| of the
  // angle between beam and normal) are skipped.
  double min_incidence_cos = 0.5;

  bool Check() const;
};

struct RangeNoiseEstimate {
  // Standard deviation of the range noise, metres (0 when not estimated).
  double sigma_m = 0.0;
  // Points and voxels the estimate rests on.
  int num_points = 0;
  int num_voxels = 0;
};

// Over the given scans (LIDAR frame, sensor at the origin). Returns
// num_voxels == 0 when no planar voxel was found.
RangeNoiseEstimate EstimateRangeNoise(const std::vector<LidarScan>& scans,
                                      const RangeNoiseOptions& options);

// LeGO-LOAM smoothness threshold for a point at range_m under range noise
// sigma_m: on a flat surface c = |sum_j (r_j - r_i)| / (2k r_i) (k =
// num_neighbors per side) is noise only, with standard deviation
// sigma / r * sqrt((2k + 1) / (2k)) for independent noise; the threshold is
// num_stddev of those, never below min_threshold (the value tuned on the
// OS1-64, so low-noise sensors keep today's behaviour). Throws on
// non-positive range or num_neighbors, negative sigma.
double SmoothnessThresholdForNoise(double sigma_m, double range_m,
                                   int num_neighbors, double num_stddev = 3.0,
                                   double min_threshold = 0.004);

}  // namespace colmap_lidar
