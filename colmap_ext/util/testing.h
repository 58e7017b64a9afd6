// Helpers for the GoogleTest suites: where the shared real data, the stock
// colmap binary and a fresh temporary folder are.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {
namespace testing {

// ../shared beside the source tree (COLMAP_LIDAR_SHARED_DIR from CTest).
std::string SharedDir();
// The KITTI raw sample folder (contains 2011_09_26/).
std::string KittiSampleDir();
// The source tree (COLMAP_LIDAR_SOURCE_DIR from CTest).
std::string SourceDir();
// The build tree, where build/colmap-lidar lives.
std::string BinaryDir();
// A new empty folder under the system temp dir, unique per call; removed
// when the process exits, unless a test failed or the environment has
// COLMAP_LIDAR_KEEP_TEST_DIRS.
std::string CreateTestDir();
// Runs a shell command line and returns its exit code; stdout and stderr go
// to `log_path` when not empty.
int RunCommand(const std::string& command_line,
               const std::string& log_path = "");
// Writes `points` as a binary PLY with float64 x, y, z and, if given, the
// faces (vertex indices) as its face element.
void WriteXyzPly(const std::string& path,
                 const std::vector<Eigen::Vector3d>& points,
                 const std::vector<std::vector<uint32_t>>& faces = {});

}  // namespace testing
}  // namespace colmap_lidar
