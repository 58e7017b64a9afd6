#include "colmap_ext/util/testing.h"

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <sstream>

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/ply.h"

namespace colmap_lidar {
namespace testing {
namespace {

std::string EnvOr(const char* name, const std::string& fallback) {
  const char* value = std::getenv(name);
  return (value != nullptr && value[0] != '\0') ? value : fallback;
}

// The folders CreateTestDir made in this process, removed at its exit
// (RemoveTestDirs): the pipeline tests leave 0.4 GB each, and a developer's
// disk filled up with thousands of them. Kept when a test failed (to look
// at) or COLMAP_LIDAR_KEEP_TEST_DIRS is set. Forked children leave with
// _exit and run no exit handler; the pid check guards against one that would.
std::mutex test_dirs_mutex;
std::vector<std::string>* test_dirs = new std::vector<std::string>();
pid_t test_dirs_owner = 0;

void RemoveTestDirs() {
  if (::getpid() != test_dirs_owner ||
      std::getenv("COLMAP_LIDAR_KEEP_TEST_DIRS") != nullptr ||
      ::testing::UnitTest::GetInstance()->Failed()) {
    return;
  }
  std::lock_guard<std::mutex> lock(test_dirs_mutex);
  for (const std::string& path : *test_dirs) {
    std::error_code error;
    std::filesystem::remove_all(path, error);
  }
}

}  // namespace

std::string SourceDir() { return EnvOr("COLMAP_LIDAR_SOURCE_DIR", "."); }

std::string BinaryDir() {
  return EnvOr("COLMAP_LIDAR_BINARY_DIR", JoinPaths(SourceDir(), "build"));
}

std::string SharedDir() {
  return EnvOr("COLMAP_LIDAR_SHARED_DIR", JoinPaths(SourceDir(), "../shared"));
}

std::string KittiSampleDir() {
  return JoinPaths(SharedDir(), "data/kitti_raw_2011_09_26_sample");
}

std::string CreateTestDir() {
  static std::atomic<int> counter{0};
  std::ostringstream name;
  name << "colmap_lidar_test_" << ::getpid() << "_" << counter++;
  const std::string path =
      (std::filesystem::temp_directory_path() / name.str()).string();
  std::filesystem::remove_all(path);
  CreateDirIfNotExists(path);
  std::lock_guard<std::mutex> lock(test_dirs_mutex);
  if (test_dirs_owner != ::getpid()) {
    test_dirs_owner = ::getpid();
    test_dirs->clear();
    std::atexit(RemoveTestDirs);
  }
  test_dirs->push_back(path);
  return path;
}

int RunCommand(const std::string& command_line, const std::string& log_path) {
  std::string full = command_line;
  if (!log_path.empty()) {
    full += " > '" + log_path + "' 2>&1";
  }
  const int status = std::system(full.c_str());
  if (status == -1) {
    return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

void WriteXyzPly(const std::string& path,
                 const std::vector<Eigen::Vector3d>& points,
                 const std::vector<std::vector<uint32_t>>& faces) {
  std::vector<double> x, y, z;
  x.reserve(points.size());
  y.reserve(points.size());
  z.reserve(points.size());
  for (const Eigen::Vector3d& point : points) {
    x.push_back(point.x());
    y.push_back(point.y());
    z.push_back(point.z());
  }
  PlyData data;
  data.AddColumn("x", PlyScalarType::kFloat64, x);
  data.AddColumn("y", PlyScalarType::kFloat64, y);
  data.AddColumn("z", PlyScalarType::kFloat64, z);
  data.faces = faces;
  WritePly(path, data);
}

}  // namespace testing
}  // namespace colmap_lidar
