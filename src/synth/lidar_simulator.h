// Simulated LIDAR scans: spinning sensors (Velodyne / Ouster layouts) and a
// survey scanner (Leica-BLK360-like tripod stations) for reference.ply.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"
#include "src/synth/ray_tracer.h"
#include "src/synth/synthesis_options.h"

namespace colmap_lidar {

// The beam layout of a spinning LIDAR: one elevation per ring (degrees,
// ascending, ring 0 the lowest beam; may be non-uniform) and the number of
// columns (azimuth steps) per revolution.
struct LidarGeometry {
  std::string model;
  std::vector<double> ring_elevations_deg;
  int columns = 0;
  double MinElevationDeg() const { return ring_elevations_deg.front(); }
  double MaxElevationDeg() const { return ring_elevations_deg.back(); }
};

// "VLP-16, HDL-32E, OS1-64, HDL-64E, OS1-128, custom" (for messages).
std::string LidarModelNames();
bool IsKnownLidarModel(const std::string& model);

// The layout of options.lidar_model (datasheet values):
//   VLP-16   16 rings uniform over [-15, +15] deg, 1800 columns (0.2 deg,
//            10 Hz);
//   HDL-32E  32 rings uniform over [-30.67, +10.67] deg, 2172 columns
//            (0.1657 deg, 10 Hz);
//   OS1-64   64 rings uniform over [-16.6, +16.6] deg, 1024 columns;
//   HDL-64E  64 rings in two uniform blocks: the lower 32 lasers over
//            [-24.9, -8.87] deg, the upper 32 over [-8.33, +2] deg,
//            2048 columns;
//   OS1-128  128 rings uniform over [-22.5, +22.5] deg, 1024 columns;
//   custom   lidar_rings uniform over [lidar_vertical_fov_min_deg, _max_deg]
//            (one ring: the middle), lidar_columns.
// Throws colmap_lidar::Error naming Synthesis.lidar_model for an unknown
// model.
LidarGeometry SynthLidarGeometry(const SynthesisOptions& options);

// The unit beam direction of (ring, column) in the LIDAR frame (x forward,
// y left, z up): elevation geometry.ring_elevations_deg[ring]; column c has
// azimuth 2 pi c / geometry.columns from +x towards +y.
Eigen::Vector3d LidarBeamDirection(const LidarGeometry& geometry, int ring,
                                   int column);

// One instantaneous (de-skewed) sweep of SynthLidarGeometry(options) from
// the sensor at world_from_lidar: every beam that hits the scene within
// [lidar_min_range_m, lidar_max_range_m] and survives the dropout
// (lidar_dropout_probability, lidar_grazing_dropout) gives a point at the
// true range plus Gaussian noise of lidar_range_noise_m along the beam (both
// seeded by options.seed, frame_index and the beam index), in the LIDAR
// frame, ordered by column then ring. Intensity
// in [0, 1] is the mean albedo of the hit material times |cos| of the
// incidence angle; rings are the beam's ring index.
LidarScan SimulateLidarScan(const RayTracer& tracer,
                            const Rigid3d& world_from_lidar,
                            const SynthesisOptions& options, int frame_index);

// A terrestrial survey: from each station (world frame) a spherical scan
// with azimuth and elevation steps of survey_angular_step_deg (elevation
// from -60 to +90 degrees), range up to 60 m, Gaussian range noise
// survey_range_noise_m; all stations merged and reduced to the first point
// per voxel of survey_voxel_size_m, then randomly subsampled to at most
// survey_max_points. World frame; only what the stations see (occlusions
// as a real survey has them).
std::vector<Eigen::Vector3f> SimulateSurvey(
    const RayTracer& tracer, const std::vector<Eigen::Vector3d>& stations,
    const SynthesisOptions& options);

}  // namespace colmap_lidar
