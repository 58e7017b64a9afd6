// Simulated LIDAR scans: an Ouster-OS1-64-like spinning sensor and a
// survey scanner (Leica-BLK360-like tripod stations) for reference.ply.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"
#include "src/synth/ray_tracer.h"
#include "src/synth/synthesis_options.h"

namespace colmap_lidar {

// The unit beam direction of (ring, column) in the LIDAR frame (x forward,
// y left, z up): ring 0 is the lowest beam, rings are spaced uniformly from
// lidar_vertical_fov_min_deg to _max_deg; column c has azimuth
// 2 pi c / lidar_columns from +x towards +y.
Eigen::Vector3d LidarBeamDirection(const SynthesisOptions& options, int ring,
                                   int column);

// One instantaneous (de-skewed) sweep from the sensor at world_from_lidar:
// every beam that hits the scene within [lidar_min_range_m,
// lidar_max_range_m] gives a point at the true range plus Gaussian noise of
// lidar_range_noise_m along the beam (seeded by options.seed and
// frame_index), in the LIDAR frame, ordered by column then ring. Intensity
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
