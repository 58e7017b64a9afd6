// Prior camera poses from LIDAR odometry (lidar_odometry.h), for a
// workspace whose recording had none (the KITTI raw sample): the
// `colmap-lidar lidar_odometry` command.
//
// Frames are the database images with an ext_lidar_scans row, in name
// order. The scans are registered in that order; each image then gets
//   world_from_cam = world_from_lidar * inverse(cam_from_lidar)
// written
//  - into the images table's prior columns as this project defines them
//    (prior_q* = cam_from_world rotation, prior_t* = camera position in
//    the world), in one transaction: only images without a prior unless
//    `overwrite_priors`;
//  - as a COLMAP model with those poses and no points in `output_path`
//    (cameras from the database), for all frames, staged and moved into
//    place after the database commit.
//
// The world frame: when the first frame already has a prior, the odometry
// starts from it, so that new priors agree with the old ones; otherwise the
// world is the first camera's frame (its pose is the identity).
#pragma once

#include <string>
#include <vector>

#include "colmap_ext/scene/rigid3.h"
#include "colmap_ext/util/types.h"
#include "src/lidar/lidar_odometry.h"

namespace colmap_lidar {

struct LidarPriorPosesOptions {
  // Replace existing priors; by default only images without one get the
  // odometry's pose.
  bool overwrite_priors = false;

  bool Check() const { return true; }
};

struct LidarPriorPose {
  image_t image_id = kInvalidImageId;
  std::string image_name;
  camera_t camera_id = kInvalidCameraId;
  Rigid3d world_from_cam;
  LidarOdometryFrame odometry;
};

struct LidarPriorPosesSummary {
  // Frames (images with a scan) registered, in name order.
  std::vector<LidarPriorPose> poses;
  size_t num_images_without_scan = 0;
  size_t num_priors_written = 0;
  // Images that kept their existing prior.
  size_t num_priors_kept = 0;
  // Frames whose registration failed (pose = prediction).
  size_t num_failed_registrations = 0;
  // Sum of the distances between consecutive camera centres, metres.
  double trajectory_length_m = 0.0;
  double seconds = 0.0;
};

// Runs the odometry over the workspace's scans (a relative scan path is
// relative to the folder of `database_path`) and writes the priors and the
// model (see above). Throws colmap_lidar::Error naming the file or frame
// on a missing scan, a failed registration (with abort_on_failure), or
// when no image has a scan; the database and `output_path` are then
// unchanged.
LidarPriorPosesSummary RunLidarOdometryPriors(
    const std::string& database_path, const std::string& output_path,
    const LidarOdometryOptions& odometry_options,
    const LidarPriorPosesOptions& options);

}  // namespace colmap_lidar
