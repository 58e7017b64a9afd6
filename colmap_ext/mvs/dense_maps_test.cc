#include "colmap_ext/mvs/dense_maps.h"

#include <cstring>

#include <Eigen/LU>
#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

Eigen::Matrix3d MakeK() {
  Eigen::Matrix3d K;
  K << 280, 0, 160, 0, 300, 120, 0, 0, 1;
  return K;
}

TEST(DenseMaps, PixelRayHasNoHalfPixelOffset) {
  const Eigen::Matrix3d K = MakeK();
  // The principal point pixel (row = cy, col = cx) looks along the axis.
  EXPECT_TRUE(MvsPixelRay(K, 120, 160).isApprox(Eigen::Vector3d(0, 0, 1)));
  const Eigen::Vector3d ray = MvsPixelRay(K, 7, 300);
  const Eigen::Vector3d expected = K.inverse() * Eigen::Vector3d(300, 7, 1);
  EXPECT_NEAR((ray - expected).norm(), 0, 1e-15);
  EXPECT_NEAR(ray.x(), (300.0 - 160.0) / 280.0, 1e-15);
  EXPECT_NEAR(ray.y(), (7.0 - 120.0) / 300.0, 1e-15);
}

TEST(DenseMaps, DepthMapBackProjectAndIo) {
  DepthMap depth_map(320, 240);
  EXPECT_EQ(depth_map.NumValid(), 0u);
  depth_map.Set(10, 200, 2.5f);
  depth_map.Set(239, 319, -1.0f);
  EXPECT_TRUE(depth_map.IsValid(10, 200));
  EXPECT_FALSE(depth_map.IsValid(239, 319));
  EXPECT_EQ(depth_map.NumValid(), 1u);
  const Eigen::Vector3d point = depth_map.BackProject(10, 200, MakeK());
  // z-depth, and the point projects back to (x = col, y = row).
  EXPECT_DOUBLE_EQ(point.z(), 2.5);
  const Eigen::Vector3d pixel = MakeK() * point / point.z();
  EXPECT_NEAR(pixel.x(), 200, 1e-12);
  EXPECT_NEAR(pixel.y(), 10, 1e-12);

  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "a.png.geometric.bin");
  depth_map.Write(path);
  const std::string content = ReadTextFile(path);
  ASSERT_EQ(content.size(), 10u + 320u * 240u * 4u);
  EXPECT_EQ(content.substr(0, 10), "320&240&1&");
  float value;
  std::memcpy(&value, content.data() + 10 + 4 * (10 * 320 + 200), 4);
  EXPECT_EQ(value, 2.5f);
  const DepthMap read = DepthMap::Read(path);
  EXPECT_EQ(read.GetMat().GetData(), depth_map.GetMat().GetData());

  // A 3-channel file is not a depth map, and vice versa.
  const std::string normal_path = JoinPaths(dir, "n.bin");
  NormalMap(4, 3).Write(normal_path);
  EXPECT_THROW(DepthMap::Read(normal_path), Error);
  EXPECT_THROW(NormalMap::Read(path), Error);
}

TEST(DenseMaps, NormalMapIsPlanar) {
  NormalMap normal_map(3, 2);
  normal_map.Set(1, 2, Eigen::Vector3f(0.6f, 0.0f, -0.8f));
  normal_map.Set(0, 1, Eigen::Vector3f(0.0f, -1.0f, 0.0f));
  EXPECT_TRUE(normal_map.IsValid(1, 2));
  EXPECT_FALSE(normal_map.IsValid(0, 0));
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "n.bin");
  normal_map.Write(path);
  const std::string content = ReadTextFile(path);
  ASSERT_EQ(content.size(), 6u + 18u * 4u);
  auto at = [&](size_t index) {
    float value;
    std::memcpy(&value, content.data() + 6 + 4 * index, 4);
    return value;
  };
  // nx plane, then ny plane, then nz plane; pixel (1, 2) is index 5.
  EXPECT_EQ(at(5), 0.6f);
  EXPECT_EQ(at(6 + 5), 0.0f);
  EXPECT_EQ(at(12 + 5), -0.8f);
  EXPECT_EQ(at(6 + 1), -1.0f);
  EXPECT_EQ(NormalMap::Read(path).Get(1, 2), Eigen::Vector3f(0.6f, 0, -0.8f));
}

TEST(DenseMaps, OrientTowardsCameraAndScaling) {
  const Eigen::Vector3f ray(0.1f, 0.2f, 1.0f);
  const Eigen::Vector3f away(0, 0, 1);
  EXPECT_EQ(NormalMap::OrientTowardsCamera(away, ray),
            Eigen::Vector3f(0, 0, -1));
  EXPECT_EQ(NormalMap::OrientTowardsCamera(-away, ray),
            Eigen::Vector3f(0, 0, -1));
  const Eigen::Matrix3d half = ScaleCalibrationToMap(MakeK(), 320, 240, 160, 120);
  EXPECT_DOUBLE_EQ(half(0, 0), 140);
  EXPECT_DOUBLE_EQ(half(0, 2), 80);
  EXPECT_DOUBLE_EQ(half(1, 1), 150);
  EXPECT_DOUBLE_EQ(half(1, 2), 60);
  EXPECT_DOUBLE_EQ(half(2, 2), 1);
}

}  // namespace
}  // namespace colmap_lidar
