// calibration.yaml of the rig dataset format (shared docs/dataset-format.md):
// the camera (any COLMAP model), the LIDAR-to-camera extrinsics and an
// optional description of the LIDAR.
#pragma once

#include <optional>
#include <string>

#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/rigid3.h"

namespace colmap_lidar {

struct LidarDescription {
  int rings = 0;
  double vertical_fov_min_deg = 0.0;
  double vertical_fov_max_deg = 0.0;
  double range_noise_m = 0.0;
};

struct RigCalibration {
  // camera_id is left invalid; the importer assigns it.
  Camera camera;
  // p_cam = cam_from_lidar * p_lidar.
  Rigid3d cam_from_lidar;
  std::optional<LidarDescription> lidar;
};

// Throws colmap_lidar::Error naming the file and the key on malformed YAML,
// missing keys, an unknown camera model, a wrong parameter count, a
// non-finite value or a non-rigid cam_from_lidar.
RigCalibration ReadCalibration(const std::string& path);
// Writes atomically.
void WriteCalibration(const std::string& path, const RigCalibration& calib);

}  // namespace colmap_lidar
