#include "src/lines/texture_rejection.h"

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

// Points on the ground plane y = 1.5 (camera frame, y down) on a 5 cm grid.
std::vector<Eigen::Vector3d> GroundPoints() {
  std::vector<Eigen::Vector3d> points;
  for (int i = -40; i <= 40; ++i) {
    for (int j = 0; j <= 80; ++j) {
      points.emplace_back(0.05 * i, 1.5, 4.0 + 0.05 * j);
    }
  }
  return points;
}

TEST(TextureRejection, PaintedStripeOnAPlaneIsTexture) {
  // A stripe edge across the ground at z = 6.
  const Eigen::Vector3d start(-1.0, 1.5, 6.0);
  const Eigen::Vector3d end(1.0, 1.5, 6.0);
  EXPECT_EQ(ClassifyLineSurface(start, end, GroundPoints(), {}),
            LineSurfaceType::kTexture);
}

TEST(TextureRejection, CreaseBetweenGroundAndWallIsAnEdge) {
  // A wall z = 6 standing on the ground (above it: y < 1.5), the ground in
  // front of it only.
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3d& point : GroundPoints()) {
    if (point.z() <= 6.0) {
      points.push_back(point);
    }
  }
  for (int i = -40; i <= 40; ++i) {
    for (int j = 0; j <= 40; ++j) {
      points.emplace_back(0.05 * i, 1.5 - 0.05 * j, 6.0);
    }
  }
  const Eigen::Vector3d start(-1.0, 1.5, 6.0);
  const Eigen::Vector3d end(1.0, 1.5, 6.0);
  EXPECT_EQ(ClassifyLineSurface(start, end, points, {}),
            LineSurfaceType::kCrease);
}

TEST(TextureRejection, OneSidedSurfaceIsAnOcclusion) {
  // The far border of the ground patch at z = 8 (nothing beyond).
  const Eigen::Vector3d start(-1.0, 1.5, 8.0);
  const Eigen::Vector3d end(1.0, 1.5, 8.0);
  TextureRejectionOptions options;
  EXPECT_EQ(ClassifyLineSurface(start, end, GroundPoints(), options),
            LineSurfaceType::kOcclusion);
  EXPECT_EQ(ClassifyLineSurface(start, end, {}, options),
            LineSurfaceType::kUnknown);
}

}  // namespace
}  // namespace colmap_lidar
