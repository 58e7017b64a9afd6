#include "src/mvs/textureless_fill.h"

#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "src/mvs/mvs_test_scene.h"

namespace colmap_lidar {
namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 120;

Eigen::Matrix3f Intrinsics() {
  return TestCalibration(kWidth, kHeight).cast<float>();
}

// Z-depth of pixel (row, col) on the plane normal . X = offset (camera
// frame), and the normal facing the camera.
float PlaneDepth(const Eigen::Vector3f& normal, float offset, int row,
                 int col) {
  const Eigen::Vector3f ray =
      Intrinsics().inverse() * Eigen::Vector3f(col, row, 1.0f);
  return offset / normal.dot(ray);
}

// A map on the plane where `measured(row, col)`, empty elsewhere.
template <typename Predicate>
PlaneMap PlaneWhere(const Eigen::Vector3f& normal, float offset,
                    Predicate measured) {
  PlaneMap map(kWidth, kHeight);
  const Eigen::Vector3f facing = offset > 0 ? -normal : normal;
  for (int row = 0; row < kHeight; ++row) {
    for (int col = 0; col < kWidth; ++col) {
      if (!measured(row, col)) continue;
      map.depth[map.Index(row, col)] = PlaneDepth(normal, offset, row, col);
      map.normal[map.Index(row, col)] = facing;
    }
  }
  return map;
}

const std::vector<uint8_t> kAllTextureless(kWidth * kHeight, 1);

// A wall 8 m ahead, turned 30 deg about the vertical axis; the LIDAR
// measures its lower half. The upper half is the same plane.
TEST(TexturelessFill, UnmeasuredPartOfAPlaneTakesItsPlane) {
  const Eigen::Vector3f normal =
      Eigen::Vector3f(std::sin(0.5236f), 0.0f, std::cos(0.5236f));
  PlaneMap map =
      PlaneWhere(normal, 8.0f, [](int row, int) { return row >= kHeight / 2; });
  std::vector<uint8_t> filled;
  const size_t num_filled =
      FillTexturelessRegions(Intrinsics(), kAllTextureless,
                             TexturelessFillOptions(), 2.0f, &map, &filled);
  EXPECT_EQ(num_filled, static_cast<size_t>(kWidth) * kHeight / 2);
  for (int row = 0; row < kHeight; ++row) {
    for (int col = 0; col < kWidth; ++col) {
      const size_t i = map.Index(row, col);
      EXPECT_EQ(filled[i], row < kHeight / 2);
      ASSERT_NEAR(map.depth[i], PlaneDepth(normal, 8.0f, row, col), 1e-4f);
      ASSERT_NEAR(std::abs(map.normal[i].dot(normal)), 1.0f, 1e-4f);
      const Eigen::Vector3f ray =
          Intrinsics().inverse() * Eigen::Vector3f(col, row, 1.0f);
      ASSERT_LT(map.normal[i].dot(ray), 0.0f);  // Faces the camera.
      if (filled[i]) {
        ASSERT_EQ(map.cost[i], 2.0f);
      }
    }
  }
}

// A texture edge (a roof line: pixels that are not textureless) separates
// the sky, which holds no measured pixel, from the measured wall.
TEST(TexturelessFill, RegionWithoutMeasuredPixelsStaysEmpty) {
  PlaneMap map = PlaneWhere(Eigen::Vector3f(0, 0, 1), 10.0f,
                            [](int row, int) { return row >= 60; });
  std::vector<uint8_t> textureless = kAllTextureless;
  for (int col = 0; col < kWidth; ++col) {
    for (int row = 56; row < 60; ++row) textureless[row * kWidth + col] = 0;
  }
  EXPECT_EQ(FillTexturelessRegions(Intrinsics(), textureless,
                                   TexturelessFillOptions(), 2.0f, &map),
            0u);
  for (int row = 0; row < 60; ++row) {
    for (int col = 0; col < kWidth; ++col) {
      ASSERT_EQ(map.depth[map.Index(row, col)], 0.0f);
    }
  }
}

// Two walls at different depths in one region: no plane explains 90 % of
// the measured pixels, so nothing is filled.
TEST(TexturelessFill, TwoPlanesInOneRegionAreNotFilled) {
  PlaneMap map = PlaneWhere(
      Eigen::Vector3f(0, 0, 1), 10.0f,
      [](int row, int col) { return row >= 60 && col < kWidth / 2; });
  const PlaneMap far = PlaneWhere(
      Eigen::Vector3f(0, 0, 1), 12.0f,
      [](int row, int col) { return row >= 60 && col >= kWidth / 2; });
  for (size_t i = 0; i < far.depth.size(); ++i) {
    if (far.depth[i] > 0) {
      map.depth[i] = far.depth[i];
      map.normal[i] = far.normal[i];
    }
  }
  EXPECT_EQ(FillTexturelessRegions(Intrinsics(), kAllTextureless,
                                   TexturelessFillOptions(), 2.0f, &map),
            0u);
}

// Measured pixels on one row fix no tilt across it; measured pixels whose
// normals disagree with the plane of their depths are not one surface.
TEST(TexturelessFill, DegenerateOrInconsistentSupportIsNotFilled) {
  PlaneMap line = PlaneWhere(Eigen::Vector3f(0, 0, 1), 10.0f,
                             [](int row, int) { return row == 100; });
  EXPECT_EQ(FillTexturelessRegions(Intrinsics(), kAllTextureless,
                                   TexturelessFillOptions(), 2.0f, &line),
            0u);
  PlaneMap tilted = PlaneWhere(Eigen::Vector3f(0, 0, 1), 10.0f,
                               [](int row, int) { return row >= 60; });
  for (Eigen::Vector3f& n : tilted.normal) {
    if (n.norm() > 0) n = Eigen::Vector3f(0.5f, 0.0f, -1.0f).normalized();
  }
  EXPECT_EQ(FillTexturelessRegions(Intrinsics(), kAllTextureless,
                                   TexturelessFillOptions(), 2.0f, &tilted),
            0u);
}

// The ground 1.5 m below the camera, measured up to 8 m ahead: the plane
// runs to the horizon, the fill stops at twice the farthest measured depth.
TEST(TexturelessFill, StopsAtTwiceTheFarthestMeasuredDepth) {
  const Eigen::Vector3f down(0, 1, 0);  // Camera y points down.
  PlaneMap map = PlaneWhere(down, 1.5f, [](int row, int col) {
    return PlaneDepth(Eigen::Vector3f(0, 1, 0), 1.5f, row, col) > 0 &&
           PlaneDepth(Eigen::Vector3f(0, 1, 0), 1.5f, row, col) <= 8.0f;
  });
  float max_measured = 0;
  for (float d : map.depth) max_measured = std::max(max_measured, d);
  ASSERT_GT(max_measured, 7.0f);
  const size_t num_filled = FillTexturelessRegions(
      Intrinsics(), kAllTextureless, TexturelessFillOptions(), 2.0f, &map);
  EXPECT_GT(num_filled, 0u);
  for (int row = 0; row < kHeight; ++row) {
    for (int col = 0; col < kWidth; ++col) {
      const float truth = PlaneDepth(down, 1.5f, row, col);
      const float depth = map.depth[map.Index(row, col)];
      if (truth > 0 && truth <= 2 * max_measured) {
        ASSERT_NEAR(depth, truth, 1e-3f * truth) << row << " " << col;
      } else {
        ASSERT_EQ(depth, 0.0f) << row << " " << col;
      }
    }
  }
}

TEST(TexturelessFill, OptionsCheck) {
  TexturelessFillOptions options;
  EXPECT_TRUE(options.Check());
  options.min_inlier_ratio = 0.0;
  EXPECT_FALSE(options.Check());
  options = TexturelessFillOptions();
  options.max_normal_angle_deg = 91.0;
  EXPECT_FALSE(options.Check());
  options = TexturelessFillOptions();
  options.max_depth_factor = 0.5;
  EXPECT_FALSE(options.Check());
  options = TexturelessFillOptions();
  options.max_relative_depth_error = std::nan("");
  EXPECT_FALSE(options.Check());
  PlaneMap map(kWidth, kHeight);
  EXPECT_ANY_THROW(FillTexturelessRegions(
      Intrinsics(), {1, 0}, TexturelessFillOptions(), 2.0f, &map));
}

}  // namespace
}  // namespace colmap_lidar
