// LIDAR odometry: world_from_lidar for a sequence of scans, for recordings
// without prior poses (the KITTI raw sample). The paper (section III-A)
// takes its prior poses from the recording's own localisation; this stands
// in for it.
//
// Scan-to-local-map registration: each scan is range-filtered and
// voxel-downsampled, then registered (PCL Generalized-ICP, Segal et al.
// 2009, or PCL NDT, Magnusson 2009) against the union of the last K
// registered scans in the world frame, starting from a constant-velocity
// prediction (the previous frame-to-frame motion applied once more). The
// registered scan then joins the local map and the oldest scan leaves it.
//
// Scans are not de-skewed (KITTI raw is not); at car speeds in a city the
// resulting distortion (a few centimetres) is below the voxel size and the
// registration tolerates it.
//
// GICP needs a covariance per point, in source and target. They are
// computed once per scan, in the LIDAR frame, from its k nearest neighbours
// in the downsampled scan (on `num_threads` threads), then rotated into the
// world when the scan joins the map, instead of PCL recomputing the whole
// map's covariances at every frame.
#pragma once

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {

struct LidarOdometryOptions {
  // Registration: gicp | ndt.
  std::string method = "gicp";
  // Edge of the voxel grid that downsamples each scan (centroid per voxel),
  // metres, > 0.
  double voxel_size_m = 0.5;
  // Points nearer to / farther from the sensor are dropped, metres,
  // 0 <= min < max. The near limit removes the ego vehicle's roof.
  double min_range_m = 3.0;
  double max_range_m = 80.0;
  // The local map holds the last K registered scans, >= 1.
  int local_map_num_scans = 10;
  // Pairs farther apart are no correspondence (GICP), and the overlap
  // below counts source points with a map point this near, metres, > 0.
  double max_correspondence_distance_m = 1.0;
  // Registration iterations at most, >= 1.
  int max_iterations = 50;
  // Convergence: the pose update between two iterations is below this
  // (translation in metres, rotation in radians), > 0.
  double transformation_epsilon = 1e-4;
  // GICP: neighbours per point for its covariance, >= 3.
  int gicp_num_neighbors = 20;
  // NDT: cell size, metres, > 0; and the More-Thuente maximum step, > 0.
  double ndt_resolution_m = 1.5;
  double ndt_step_size = 0.1;
  // A registration fails when fewer than this fraction of the downsampled
  // scan's points have a map point within max_correspondence_distance_m
  // after alignment, [0, 1].
  double min_overlap = 0.5;
  // On a failed registration: throw (naming the frame), or warn and keep
  // the constant-velocity prediction.
  bool abort_on_failure = true;
  // Threads for the per-point covariances; <= 0: all cores.
  int num_threads = -1;

  bool Check() const;
};

struct LidarOdometryFrame {
  // p_world = world_from_lidar * p_lidar.
  Rigid3d world_from_lidar;
  // Fraction of the downsampled scan within max_correspondence_distance_m
  // of the map after alignment (1 for the first frame).
  double overlap = 1.0;
  // Root mean square distance of those points to their nearest map point,
  // metres (0 for the first frame).
  double rmse_m = 0.0;
  bool converged = true;
  // False when the registration failed and the prediction was kept.
  bool registered = true;
  // Points after the range filter and the voxel grid.
  size_t num_points = 0;
  double seconds = 0.0;
};

class LidarOdometry {
 public:
  // The first scan gets `world_from_first_lidar`. Throws when the options
  // fail Check().
  explicit LidarOdometry(const LidarOdometryOptions& options,
                         const Rigid3d& world_from_first_lidar = Rigid3d());
  ~LidarOdometry();
  LidarOdometry(const LidarOdometry&) = delete;
  LidarOdometry& operator=(const LidarOdometry&) = delete;

  // Registers the next scan (LIDAR frame) of the sequence. `frame_name`
  // only names the frame in messages. Throws colmap_lidar::Error naming the
  // frame when the scan has too few points left after filtering (< 10), or
  // when the registration fails and abort_on_failure is set.
  LidarOdometryFrame AddScan(const LidarScan& scan,
                             const std::string& frame_name);

  size_t NumFrames() const { return poses_.size(); }

 private:
  struct MapScan;

  LidarOdometryOptions options_;
  Rigid3d world_from_first_lidar_;
  std::vector<Rigid3d> poses_;
  std::deque<std::shared_ptr<const MapScan>> local_map_;
};

// Runs LidarOdometry over `scans` in order; `frame_names` (same size, or
// empty for "frame <index>") name the frames in messages.
std::vector<LidarOdometryFrame> RunLidarOdometry(
    const std::vector<LidarScan>& scans,
    const std::vector<std::string>& frame_names,
    const LidarOdometryOptions& options,
    const Rigid3d& world_from_first_lidar = Rigid3d());

}  // namespace colmap_lidar
