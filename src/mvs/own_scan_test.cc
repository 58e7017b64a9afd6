#include "src/mvs/own_scan.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <vector>

#include <gtest/gtest.h>

#include "src/mvs/interpolation.h"
#include "src/mvs/mvs_test_scene.h"

namespace colmap_lidar {
namespace {

TEST(OwnScan, VoxelsNamedInTheVisibility) {
  const FusedVisibility visibility = {{3, 1}, {2}, {}, {1}};
  EXPECT_EQ(OwnScanVoxels(visibility, 1), (std::vector<uint8_t>{1, 0, 0, 1}));
  EXPECT_EQ(OwnScanVoxels(visibility, 5), (std::vector<uint8_t>(4, 0)));
  EXPECT_TRUE(OwnScanVoxels({}, 0).empty());
}

TEST(OwnScan, AngleOutsideZeroToNinetyIsRefused) {
  LidarPatchMatchOptions options;
  EXPECT_TRUE(options.Check());
  options.lidar_own_scan_min_incidence_deg = 0;
  EXPECT_TRUE(options.Check());
  options.lidar_own_scan_min_incidence_deg = 91;
  EXPECT_FALSE(options.Check());
  options.lidar_own_scan_min_incidence_deg = -1;
  EXPECT_FALSE(options.Check());
}

// Only the voxels that the view's own scan hit become its samples; a
// feature replaces the sample of its pixel.
TEST(OwnScan, SamplesOfTheOwnVoxelsOnly) {
  const int width = 320, height = 240;
  const Eigen::Matrix3d K = TestCalibration(width, height);  // f = 200 px.
  const MvsView view = MakeMvsView("v", K, Rigid3d(), width, height,
                                   std::vector<float>(width * height, 0.5f));
  FusedLidarCloud cloud;
  cloud.points = {Eigen::Vector3f(0, 0, 4), Eigen::Vector3f(1, 0, 4),
                  Eigen::Vector3f(-1, 0, 4)};
  cloud.normals.assign(3, Eigen::Vector3f(0, 0, -1));
  cloud.counts.assign(3, 1);
  cloud.visibility = {{2, 0}, {1}, {0}};
  LidarPatchMatchOptions options;
  const std::vector<DepthSample> own =
      OwnScanSamples(view, cloud, 0, {}, options);
  ASSERT_EQ(own.size(), 2u);
  EXPECT_EQ(own[0].col, 110);  // (-1, 0, 4): 160 - 200 / 4.
  EXPECT_EQ(own[1].col, 160);
  const std::vector<DepthSample> with_feature =
      OwnScanSamples(view, cloud, 0, {Eigen::Vector3f(0, 0, 3.9f)}, options);
  ASSERT_EQ(with_feature.size(), 2u);
  EXPECT_TRUE(with_feature[1].from_feature);
  EXPECT_FLOAT_EQ(with_feature[1].depth, 3.9f);
  EXPECT_TRUE(OwnScanSamples(view, cloud, 5, {}, options).empty());
}

// A wall seen at grazing incidence 10-30 m away, unsampled in rows 100-140
// (a gap). The view's own scan samples it on rings every 12th row from 60 to
// 180 with 1 cm of range noise; other frames' scans sample every row, with
// a pose that puts them 3 cm off the wall: 7 to 16 cm along the camera's
// rays, which meet the wall at 63 to 79 deg from its normal. With the own
// scan's precedence at every angle, the interpolated map follows the wall
// where the rings and the fused cloud both cover the view, and stays as it
// was elsewhere: the fused cloud's rows above the rings, and the gap, which
// the fused cloud's interpolation leaves empty (its triangles across it fail
// the edge test) and the own rings alone would bridge (four of their
// spacings). Beyond 72 deg only the pixels whose ray is that far from the
// normal change; at 90 deg none.
TEST(OwnScan, OwnRingsDecideWhereBothCoverTheView) {
  const GrazingWall wall = MakeGrazingWall();
  const int width = wall.view.width, height = wall.view.height;
  const Eigen::Matrix3d& K = wall.K;
  const MvsView& view = wall.view;
  const Eigen::Vector3f& normal = wall.normal;
  UniformStream stream(12345);
  const int min_col = 230, max_col = 280;
  const int min_own_row = 60, max_own_row = 180;
  std::vector<Eigen::Vector3f> own_points, own_normals;
  std::vector<Eigen::Vector3f> all_points, all_normals;
  for (int row = 0; row < height; ++row) {
    const bool sampled = row < 100 || row > 140;
    const bool own_ring =
        sampled && row % 12 == 0 && row >= min_own_row && row <= max_own_row;
    for (int k = 0; k < 4 * (max_col - min_col); ++k) {
      const double col = min_col + (max_col - min_col) * stream.Next();
      const Eigen::Vector3d ray = K.inverse() * Eigen::Vector3d(col, row, 1);
      const double depth = wall.Depth(ray);
      if (depth < 10.0 || depth > 30.0) continue;
      const Eigen::Vector3d point = depth * ray;
      if (own_ring) {
        const double noise =
            0.01 * std::sqrt(3.0) * (2.0 * stream.Next() - 1.0);
        own_points.push_back(
            (point + noise * point.normalized()).cast<float>());
        own_normals.push_back(normal);
      }
      if (sampled) {
        all_points.push_back(
            (point + 0.03 * normal.cast<double>()).cast<float>());
        all_normals.push_back(normal);
      }
    }
  }
  all_points.insert(all_points.end(), own_points.begin(), own_points.end());
  all_normals.insert(all_normals.end(), own_normals.begin(), own_normals.end());
  LidarPatchMatchOptions options;
  options.lidar_own_scan_min_incidence_deg = 0;
  std::vector<uint8_t> across_depth_edge;
  const PlaneMap every_scan = InterpolateSamples(
      view, ProjectLidarSamples(view, all_points, all_normals, options),
      options, &across_depth_edge);
  const std::vector<uint8_t> every_scan_flags = across_depth_edge;
  const std::vector<DepthSample> own_samples =
      ProjectLidarSamples(view, own_points, own_normals, options);
  const PlaneMap own_alone = InterpolateSamples(view, own_samples, options);
  PlaneMap own_first = every_scan;
  const size_t num_replaced =
      PreferOwnScan(view, own_samples, options, &own_first, &across_depth_edge);
  EXPECT_GT(num_replaced, 4000u);
  size_t num_gap = 0, num_gap_own_alone = 0;
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      const size_t i = static_cast<size_t>(row) * width + col;
      if (!(every_scan.depth[i] > 0)) {
        EXPECT_EQ(own_first.depth[i], 0.0f) << row << " " << col;
        if (row > 110 && row < 130 && col > 240 && col < 270) {
          ++num_gap;
          num_gap_own_alone += own_alone.depth[i] > 0;
        }
      } else if (row < min_own_row) {
        EXPECT_EQ(own_first.depth[i], every_scan.depth[i]) << row << " " << col;
      }
    }
  }
  // The gap stays empty, which the own rings alone bridge.
  EXPECT_GT(num_gap, 400u);
  EXPECT_GT(num_gap_own_alone, num_gap / 2);
  // Between the rings: the share of the covered pixels within 5 cm.
  auto share_within_5cm = [&](const PlaneMap& map) {
    size_t num = 0, within = 0;
    for (int row = min_own_row; row <= max_own_row; ++row) {
      for (int col = 0; col < width; ++col) {
        const float depth = map.depth[row * width + col];
        if (!(depth > 0)) continue;
        ++num;
        const double truth =
            wall.Depth(K.inverse() * Eigen::Vector3d(col, row, 1));
        within += std::abs(depth - truth) <= 0.05 ? 1 : 0;
      }
    }
    EXPECT_GT(num, 4000u);
    return static_cast<double>(within) / std::max<size_t>(num, 1);
  };
  const double every = share_within_5cm(every_scan);
  const double own = share_within_5cm(own_first);
  std::cout << "within 5 cm between the rings: every scan " << every
            << ", own scan first " << own << std::endl;
  EXPECT_LT(every, 0.5);
  EXPECT_GT(own, 0.95);
  // Only the grazing pixels (ray more than 72 deg from the normal).
  options.lidar_own_scan_min_incidence_deg = 72;
  PlaneMap grazing = every_scan;
  std::vector<uint8_t> grazing_flags = every_scan_flags;
  const size_t num_grazing =
      PreferOwnScan(view, own_samples, options, &grazing, &grazing_flags);
  EXPECT_GT(num_grazing, 1000u);
  EXPECT_LT(num_grazing, num_replaced - 1000);
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      const size_t i = static_cast<size_t>(row) * width + col;
      if (grazing.depth[i] == every_scan.depth[i]) continue;
      const Eigen::Vector3f ray =
          view.Ray(static_cast<float>(row), static_cast<float>(col));
      EXPECT_LT(std::abs(normal.dot(ray.normalized())),
                std::cos(72 * M_PI / 180) + 0.01)
          << row << " " << col;
    }
  }
  options.lidar_own_scan_min_incidence_deg = 90;
  PlaneMap off = every_scan;
  EXPECT_EQ(PreferOwnScan(view, own_samples, options, &off, &grazing_flags),
            0u);
  EXPECT_EQ(off.depth, every_scan.depth);
  options.lidar_own_scan_min_incidence_deg = 0;
  // No own sample: the map unchanged.
  PlaneMap unchanged = every_scan;
  EXPECT_EQ(PreferOwnScan(view, {}, options, &unchanged, &across_depth_edge),
            0u);
  EXPECT_EQ(unchanged.depth, every_scan.depth);
}

}  // namespace
}  // namespace colmap_lidar
