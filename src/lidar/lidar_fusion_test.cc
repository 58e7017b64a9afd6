#include "src/lidar/lidar_fusion.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

// Points on the plane z = 2.05 (world, mid-voxel), seen by scanners below it: the normals
// must be (0, 0, -1) (facing the scanners).
LidarScan PlaneScan(const Rigid3d& world_from_lidar, int n, double half_size,
                    std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(-half_size, half_size);
  const Rigid3d lidar_from_world = world_from_lidar.Inverse();
  LidarScan scan;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d point_in_world(uniform(*rng), uniform(*rng), 2.05);
    scan.points.push_back((lidar_from_world * point_in_world).cast<float>());
  }
  return scan;
}

TEST(LidarFusion, CountsNormalsAndVisibilityOnAPlane) {
  std::mt19937 rng(3);
  Rigid3d world_from_lidar0;
  Rigid3d world_from_lidar1(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())),
      Eigen::Vector3d(0.5, 0.0, 0.1));
  const LidarScan scan0 = PlaneScan(world_from_lidar0, 20000, 1.0, &rng);
  const LidarScan scan1 = PlaneScan(world_from_lidar1, 10000, 0.5, &rng);
  LidarFusionOptions options;
  options.voxel_size_m = 0.1;
  const FusedLidarCloud cloud = FuseLidarScans(
      {{3, &scan0, world_from_lidar0}, {7, &scan1, world_from_lidar1}},
      options);

  // 2 m x 2 m at 10 cm: 20 x 20 voxels in one layer.
  EXPECT_EQ(cloud.size(), 400u);
  size_t total = 0;
  size_t num_seen_by_both = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    total += cloud.counts[i];
    EXPECT_NEAR(cloud.points[i].z(), 2.05f, 1e-4);
    EXPECT_NEAR(cloud.normals[i].z(), -1.0f, 1e-3) << i;
    ASSERT_FALSE(cloud.visibility[i].empty());
    for (uint32_t idx : cloud.visibility[i]) {
      EXPECT_TRUE(idx == 3 || idx == 7);
    }
    if (cloud.visibility[i].size() == 2) {
      ++num_seen_by_both;
      // The frame with the most points first.
      const double x = cloud.points[i].x();
      const double y = cloud.points[i].y();
      if (std::abs(x) < 0.4 && std::abs(y) < 0.4) {
        EXPECT_EQ(cloud.visibility[i][0], 7u);  // 10000 / 1 m^2 > 20000 / 4 m^2
      }
    }
  }
  EXPECT_EQ(total, 30000u);
  EXPECT_EQ(num_seen_by_both, 100u);  // The inner 1 m x 1 m.

  // Density: a 10 cm voxel of the 2 m square gets ~50 points of scan0.
  options.min_points_per_voxel = 1000;
  EXPECT_EQ(FuseLidarScans({{0, &scan0, world_from_lidar0}}, options).size(),
            0u);
}

TEST(LidarFusion, CapsVisibilityAndSkipsRanges) {
  std::mt19937 rng(4);
  std::vector<LidarScan> scans;
  for (int i = 0; i < 5; ++i) {
    scans.push_back(PlaneScan(Rigid3d(), 500, 0.2, &rng));
  }
  std::vector<LidarFusionInput> inputs;
  for (int i = 0; i < 5; ++i) {
    inputs.push_back({static_cast<uint32_t>(i), &scans[i], Rigid3d()});
  }
  LidarFusionOptions options;
  options.voxel_size_m = 1.0;
  options.max_num_visible_images = 2;
  FusedLidarCloud cloud = FuseLidarScans(inputs, options);
  ASSERT_GE(cloud.size(), 1u);
  for (const auto& vis : cloud.visibility) {
    EXPECT_LE(vis.size(), 2u);
  }
  options.max_range_m = 1.5;  // All points are >= 2 m away.
  EXPECT_EQ(FuseLidarScans(inputs, options).size(), 0u);
  options.voxel_size_m = 0;
  EXPECT_FALSE(options.Check());
}

TEST(LidarFusion, FilesRoundTrip) {
  std::mt19937 rng(5);
  const LidarScan scan = PlaneScan(Rigid3d(), 2000, 0.5, &rng);
  LidarFusionOptions options;
  options.voxel_size_m = 0.1;
  const FusedLidarCloud cloud =
      FuseLidarScans({{2, &scan, Rigid3d()}}, options);
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "lidar_fused.ply");
  WriteFusedLidarCloud(path, cloud);
  const FusedLidarCloud read = ReadFusedLidarCloud(path);
  ASSERT_EQ(read.size(), cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(read.points[i], cloud.points[i]);
    EXPECT_EQ(read.normals[i], cloud.normals[i]);
    EXPECT_EQ(read.counts[i], cloud.counts[i]);
    EXPECT_EQ(read.visibility[i], cloud.visibility[i]);
  }
  const std::string header = ReadTextFile(path).substr(0, 300);
  EXPECT_NE(header.find("property uint count"), std::string::npos) << header;

  WriteLidarOrigins(JoinPaths(dir, "lidar_origins.txt"),
                    {{"a.png", Eigen::Vector3d(1, 2, 3.5)}});
  const auto origins = ReadLidarOriginList(JoinPaths(dir, "lidar_origins.txt"));
  ASSERT_EQ(origins.size(), 1u);
  EXPECT_EQ(origins[0].image_name, "a.png");
  EXPECT_EQ(origins[0].position_in_world, Eigen::Vector3d(1, 2, 3.5));
}

}  // namespace
}  // namespace colmap_lidar
