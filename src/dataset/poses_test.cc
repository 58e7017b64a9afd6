#include "src/dataset/poses.h"

#include <fstream>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

TEST(Poses, ReadsTumLayoutWithFrameNames) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "poses.txt");
  std::ofstream(path) << "# frame tx ty tz qx qy qz qw\n\n"
                      << "000000 1.204 -3.110 1.523 0.0 0.0 0.7071068 0.7071068\n"
                      << "  000001 1 2 3 0 0 0 1  \n";
  const std::vector<FramePose> poses = ReadPoses(path);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].frame, "000000");
  EXPECT_NEAR(poses[0].world_from_cam.translation.x(), 1.204, 1e-15);
  // 90 degrees about z: camera x axis maps to world y.
  const Eigen::Vector3d x_in_world =
      poses[0].world_from_cam.rotation * Eigen::Vector3d::UnitX();
  EXPECT_NEAR((x_in_world - Eigen::Vector3d::UnitY()).norm(), 0, 1e-6);
  EXPECT_NEAR(poses[0].world_from_cam.rotation.norm(), 1.0, 1e-15);
  EXPECT_EQ(poses[1].frame, "000001");
}

TEST(Poses, RoundTrip) {
  const std::string dir = testing::CreateTestDir();
  std::vector<FramePose> poses(3);
  for (int i = 0; i < 3; ++i) {
    poses[i].frame = "f" + std::to_string(i);
    poses[i].world_from_cam = Rigid3d(
        Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * i + 0.05, Eigen::Vector3d(0.2, 1, 0.3).normalized())),
        Eigen::Vector3d(i * 1.0 / 3.0, -2.0 / 7.0, 1e-7));
  }
  const std::string path = JoinPaths(dir, "poses.txt");
  WritePoses(path, poses, "generated\nby a test");
  const std::vector<FramePose> read = ReadPoses(path);
  ASSERT_EQ(read.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(read[i].frame, poses[i].frame);
    EXPECT_EQ(read[i].world_from_cam.translation, poses[i].world_from_cam.translation);
    EXPECT_NEAR(read[i].world_from_cam.rotation.angularDistance(
                    poses[i].world_from_cam.rotation), 0, 1e-14);
  }
}

void ExpectError(const std::string& text, const std::string& fragment) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "poses.txt");
  std::ofstream(path) << text;
  try {
    ReadPoses(path);
    FAIL() << "no error for: " << text;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path + ":"), std::string::npos) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
  }
}

TEST(Poses, RejectsBadLines) {
  ExpectError("a 1 2 3 0 0 0\n", "8 columns");
  ExpectError("a 1 2 x 0 0 0 1\n", "expected a number");
  ExpectError("a 1 2 nan 0 0 0 1\n", "non-finite");
  ExpectError("a 1 2 3 0 0 0 2\n", "not unit");
  ExpectError("a 1 2 3 0 0 0 1\na 1 2 3 0 0 0 1\n", "twice");
}

}  // namespace
}  // namespace colmap_lidar
