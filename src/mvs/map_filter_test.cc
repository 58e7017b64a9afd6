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

}  // namespace
}  // namespace colmap_lidar
