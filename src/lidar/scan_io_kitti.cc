// KITTI Velodyne .bin scans of scan_io.h (read only).
#include "src/lidar/scan_io_internal.h"

#include <filesystem>
#include <fstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace scan_io_internal {

size_t KittiBinNumPoints(const std::string& path) {
  CheckFileExists(path, "KITTI LIDAR scan");
  const uintmax_t num_bytes = std::filesystem::file_size(path);
  THROW_CHECK(num_bytes % 16 == 0,
              "KITTI .bin file " << path << " has " << num_bytes
                                 << " bytes, not a multiple of 16 "
                                    "(float32 x y z reflectance records): "
                                    "truncated or not a KITTI scan");
  return static_cast<size_t>(num_bytes / 16);
}

LidarScan ReadKittiBinScan(const std::string& path) {
  const size_t num_points = KittiBinNumPoints(path);
  std::vector<float> values(4 * num_points);
  std::ifstream file = OpenBinaryInput(path);
  file.read(reinterpret_cast<char*>(values.data()),
            static_cast<std::streamsize>(values.size() * sizeof(float)));
  THROW_CHECK(num_points == 0 || file.good(),
              "Cannot read KITTI .bin file " << path);
  LidarScan scan;
  scan.points.resize(num_points);
  scan.intensities.resize(num_points);
  for (size_t i = 0; i < num_points; ++i) {
    scan.points[i] = Eigen::Vector3f(values[4 * i], values[4 * i + 1],
                                     values[4 * i + 2]);
    scan.intensities[i] = values[4 * i + 3];
  }
  return scan;
}

}  // namespace scan_io_internal
}  // namespace colmap_lidar
