#include "src/lines/texture_rejection.h"

#include <cmath>

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

TEST(TextureRejection, TextureLineNextToAKerbIsTexture) {
  // A painted line across the ground at z = 6, 15 cm in front of a 5 cm
  // kerb (z = 6.15): the faces are hinged on the line, so the few kerb
  // points within the radius do not make it an edge.
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3d& point : GroundPoints()) {
    if (point.z() <= 6.15 + 1e-9) {
      points.push_back(point);
    }
  }
  for (int i = -40; i <= 40; ++i) {
    for (const double height : {0.025, 0.05}) {
      points.emplace_back(0.05 * i, 1.5 - height, 6.15);
    }
  }
  const Eigen::Vector3d start(-1.0, 1.5, 6.0);
  const Eigen::Vector3d end(1.0, 1.5, 6.0);
  const TextureRejectionOptions options;
  const LineSurfaceType type = ClassifyLineSurface(start, end, points, options);
  EXPECT_EQ(type, LineSurfaceType::kTexture);
  EXPECT_FALSE(IsKeptSurfaceType(type, options));
  // The kerb's own edge is a crease.
  EXPECT_EQ(ClassifyLineSurface(Eigen::Vector3d(-1.0, 1.5, 6.15),
                                Eigen::Vector3d(1.0, 1.5, 6.15), points,
                                options),
            LineSurfaceType::kCrease);
}

TEST(TextureRejection, CylinderOutlineIsASilhouette) {
  // The visible half of a vertical cylinder of radius 0.15 m at 6 m (a tree
  // trunk), nothing behind it within the radius: its outline x = 0.15 is no
  // crease; a planar face's border is kept (see OneSidedSurface...).
  const double radius = 0.15;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i <= 30; ++i) {
    const double angle = M_PI * i / 30.0;
    for (int j = -20; j <= 20; ++j) {
      points.emplace_back(radius * std::cos(angle), 0.05 * j,
                          6.0 - radius * std::sin(angle));
    }
  }
  const Eigen::Vector3d start(radius, -1.0, 6.0);
  const Eigen::Vector3d end(radius, 1.0, 6.0);
  TextureRejectionOptions options;
  const LineSurfaceType type = ClassifyLineSurface(start, end, points, options);
  EXPECT_EQ(type, LineSurfaceType::kSilhouette);
  EXPECT_FALSE(IsKeptSurfaceType(type, options));
  EXPECT_TRUE(IsKeptSurfaceType(LineSurfaceType::kOcclusion, options));
  options.keep_occlusions = false;
  EXPECT_FALSE(IsKeptSurfaceType(LineSurfaceType::kOcclusion, options));
}

}  // namespace
}  // namespace colmap_lidar
