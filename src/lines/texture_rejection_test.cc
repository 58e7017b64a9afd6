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
  // The far border of the ground patch at z = 8 (a quay's edge): the rays
  // that pass it end on a wall 4 m behind, below the ground's level.
  std::vector<Eigen::Vector3d> points = GroundPoints();
  for (int i = -40; i <= 40; ++i) {
    for (int j = -20; j <= 60; ++j) {
      points.emplace_back(0.05 * i, 0.05 * j, 12.0);
    }
  }
  const Eigen::Vector3d start(-1.0, 1.5, 8.0);
  const Eigen::Vector3d end(1.0, 1.5, 8.0);
  TextureRejectionOptions options;
  EXPECT_EQ(ClassifyLineSurface(start, end, points, options),
            LineSurfaceType::kOcclusion);
  // Nothing seen past it (no return, e.g. sky): the LIDAR cannot tell.
  EXPECT_EQ(ClassifyLineSurface(start, end, GroundPoints(), options),
            LineSurfaceType::kUnknown);
  options.min_open_space_points = 0;  // An empty side is open space.
  EXPECT_EQ(ClassifyLineSurface(start, end, GroundPoints(), options),
            LineSurfaceType::kOcclusion);
  EXPECT_EQ(ClassifyLineSurface(start, end, {}, options),
            LineSurfaceType::kUnknown);
}

TEST(TextureRejection, GapBetweenRingsIsNoOpenSpace) {
  // A paving joint across the ground at z = 6, just past a ring of a
  // 32-ring LIDAR (a band z in [5.8, 5.95]); the next ring lies 1.3 m
  // farther (z = 7.3): nothing within the radius on the far side, but the
  // rays past the line end on the ground's extension.
  std::vector<Eigen::Vector3d> points;
  for (int i = -50; i <= 50; ++i) {
    for (const double z : {5.8, 5.85, 5.9, 5.95, 7.3, 7.35}) {
      points.emplace_back(0.02 * i, 1.5, z);
    }
  }
  const Eigen::Vector3d start(-1.0, 1.5, 6.0);
  const Eigen::Vector3d end(1.0, 1.5, 6.0);
  TextureRejectionOptions options;
  EXPECT_EQ(ClassifyLineSurface(start, end, points, options),
            LineSurfaceType::kTexture);
  options.min_open_space_points = 0;  // The rule before: an occlusion.
  EXPECT_EQ(ClassifyLineSurface(start, end, points, options),
            LineSurfaceType::kOcclusion);
}

TEST(TextureRejection, PointsWithinTheNoiseOfTheLineDoNotDecide) {
  // A joint across the ground at z = 6 between two pairs of rings (0.15 and
  // 0.2 m on each side). Three rows of points 2.5-3.5 cm above the line: on
  // a 2 cm-noise scan, the noise of the ring the line was fitted to. Their
  // angle about the line is that of a wall, and they outnumber the ground's
  // points on their side.
  std::vector<Eigen::Vector3d> points;
  for (int i = -50; i <= 50; ++i) {
    for (const double z : {5.8, 5.85, 6.15, 6.2}) {
      points.emplace_back(0.02 * i, 1.5, z);
    }
    for (const double height : {0.025, 0.03, 0.035}) {
      points.emplace_back(0.02 * i, 1.5 - height, 6.0);
    }
  }
  const Eigen::Vector3d start(-1.0, 1.5, 6.0);
  const Eigen::Vector3d end(1.0, 1.5, 6.0);
  TextureRejectionOptions options;
  options.range_noise_m = 0.02;  // Exclusion 6 cm.
  EXPECT_EQ(ClassifyLineSurface(start, end, points, options),
            LineSurfaceType::kTexture);
  // Without the noise (exclusion_distance only) they make a crease.
  options.range_noise_m = 0.0;
  EXPECT_EQ(ClassifyLineSurface(start, end, points, options),
            LineSurfaceType::kCrease);
  options.range_noise_m = 0.02;
  options.exclusion_noise_sigmas = 0.0;
  EXPECT_EQ(ClassifyLineSurface(start, end, points, options),
            LineSurfaceType::kCrease);
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
