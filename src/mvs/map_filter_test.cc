#include "src/mvs/map_filter.h"

#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "src/mvs/mvs_test_scene.h"

namespace colmap_lidar {
namespace {

// Ground 1.5 m below a reference camera and a source 2 m behind it and 1 m
// to its side, both looking along the ground; the reference map is exact,
// the source map `scale` times too deep everywhere.
struct GroundPair {
  static constexpr float kHeightM = 1.5f;
  GroundViewPair views;
  PlaneMap ref_map;

  explicit GroundPair(float scale)
      : views(320, 240, kHeightM, Eigen::Vector3d(1.0, 0.0, -2.0)),
        ref_map(GroundPlaneMap(views.ref, kHeightM, 12.0f)) {
    for (float& depth : views.src_map.depth) depth *= scale;
  }

  // Filters a copy of the reference map; returns the pixels kept.
  size_t Filter(const LidarPatchMatchOptions& options,
                std::vector<uint8_t>* not_fused) const {
    PatchCostComputer cost(views.ref, {&views.src}, options);
    cost.SetSourceMaps({&views.src_map});
    PlaneMap map = ref_map;
    return FilterByConsistency(cost, options, {}, &map, not_fused);
  }
};

LidarPatchMatchOptions OneViewOptions(bool parallax) {
  LidarPatchMatchOptions options;
  options.filter_min_num_consistent = 1;
  options.filter_lidar_as_view = false;
  options.filter_reproj_parallax = parallax;
  options.num_threads = 1;
  return options;
}

// A source depth 0.8 % off (within filter_max_relative_depth_error, 1 %)
// reprojects more than a pixel away on the near ground, under a wide
// triangulation angle: the parallax tolerance keeps those pixels, and keeps
// them out of fusion; a depth 3 % off is dropped with or without it.
TEST(MapFilter, ParallaxToleranceKeepsWhatTheDepthTestAccepts) {
  const GroundPair exact(1.0f);
  const size_t num_ground = exact.ref_map.NumValid();
  std::vector<uint8_t> not_fused;
  const size_t exact_kept = exact.Filter(OneViewOptions(false), &not_fused);
  // The source sees most of the reference's ground and agrees exactly.
  EXPECT_GT(exact_kept, num_ground * 8 / 10);
  for (const uint8_t flag : not_fused) ASSERT_EQ(flag, 0);

  const GroundPair off(1.008f);
  const size_t strict_kept = off.Filter(OneViewOptions(false), &not_fused);
  for (const uint8_t flag : not_fused) ASSERT_EQ(flag, 0);
  const size_t parallax_kept = off.Filter(OneViewOptions(true), &not_fused);
  std::cout << num_ground << " ground pixels: " << exact_kept
            << " kept with the exact source, " << strict_kept
            << " with the source 0.8 % off, " << parallax_kept
            << " with the parallax tolerance" << std::endl;
  EXPECT_LT(strict_kept, exact_kept * 9 / 10);
  EXPECT_GT(parallax_kept, exact_kept * 99 / 100);
  size_t num_not_fused = 0;
  for (const uint8_t flag : not_fused) num_not_fused += flag;
  EXPECT_EQ(num_not_fused, parallax_kept - strict_kept);

  const GroundPair wrong(1.03f);
  EXPECT_EQ(wrong.Filter(OneViewOptions(true), &not_fused), 0u);
}

// The source 3 m ahead of the reference: the ground just ahead of the
// reference lies behind the source or below its image, so only the LIDAR
// measures it. Those pixels return to the prior's plane; the ground the
// source sees keeps the search's depth (here 20 % off, for the filters to
// judge), and pixels without a prior stay as they were.
TEST(MapFilter, LidarKeptWhereNoSourceSeesIt) {
  const int width = 320, height = 240;
  const float ground_height = 1.5f;
  const GroundViewPair views(width, height, ground_height,
                             Eigen::Vector3d(0.0, 0.0, 3.0));
  const PlaneMap truth = GroundPlaneMap(views.ref, ground_height, 12.0f);
  std::vector<float> prior_depth = truth.depth;
  // No prior on the left tenth of the image.
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width / 10; ++col) {
      prior_depth[truth.Index(row, col)] = 0.0f;
    }
  }
  PlaneMap map = truth;
  for (float& depth : map.depth) depth *= 1.2f;
  const LidarPatchMatchOptions options;
  const PatchCostComputer cost(views.ref, {&views.src}, options);
  const size_t num_reset =
      KeepLidarWhereUnseen(cost, prior_depth, truth.normal, &map);
  const Eigen::Matrix3d K = TestCalibration(width, height);
  size_t num_unseen = 0;
  size_t num_seen = 0;
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      const size_t i = truth.Index(row, col);
      if (!(truth.depth[i] > 0)) continue;
      if (!(prior_depth[i] > 0)) {
        ASSERT_EQ(map.depth[i], 1.2f * truth.depth[i]);
        continue;
      }
      // The ground point in the source's frame (same orientation, 3 m on).
      const Eigen::Vector3d point =
          truth.depth[i] * K.inverse() * Eigen::Vector3d(col, row, 1.0) -
          Eigen::Vector3d(0.0, 0.0, 3.0);
      const Eigen::Vector3d projection = K * point;
      const double x = projection.x() / projection.z();
      const double y = projection.y() / projection.z();
      const bool seen = point.z() > 0 && x >= -0.5 && y >= -0.5 &&
                        x < width - 0.5 && y < height - 0.5;
      if (seen) {
        ++num_seen;
        ASSERT_FLOAT_EQ(map.depth[i], 1.2f * truth.depth[i]);
      } else {
        ++num_unseen;
        ASSERT_EQ(map.depth[i], truth.depth[i]);
        ASSERT_EQ(map.normal[i], truth.normal[i]);
        ASSERT_EQ(map.cost[i], kMaxCost);
      }
    }
  }
  EXPECT_EQ(num_reset, num_unseen);
  EXPECT_GT(num_unseen, 1000u);
  EXPECT_GT(num_seen, 1000u);
}

}  // namespace
}  // namespace colmap_lidar
