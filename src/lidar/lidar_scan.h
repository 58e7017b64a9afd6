// One LIDAR scan in the sensor (LIDAR) frame, as read from PLY, PCD or KITTI
// .bin. Optional per-point channels are empty when the file has none.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {

struct LidarScan {
  // Metres, LIDAR frame.
  std::vector<Eigen::Vector3f> points;
  // Return strength as the file gives it (intensity or reflectance).
  std::vector<float> intensities;
  // Laser ring index (0 = lowest beam where the sensor says so).
  std::vector<uint16_t> rings;

  size_t size() const { return points.size(); }
  bool HasIntensities() const { return !intensities.empty(); }
  bool HasRings() const { return !rings.empty(); }
};

}  // namespace colmap_lidar
