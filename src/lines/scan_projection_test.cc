#include "src/lines/scan_projection.h"

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

TEST(ScanProjection, PointsBehindANearerSurfaceAreHidden) {
  const Camera camera =
      Camera::FromModelName("PINHOLE", 200, 100, {100, 100, 100, 50});
  LidarScan scan;
  // Identity cam_from_lidar: points given in the camera frame.
  scan.points.emplace_back(0.0f, 0.0f, 5.0f);    // wall point
  scan.points.emplace_back(0.01f, 0.0f, 9.0f);   // behind it, same pixel cell
  scan.points.emplace_back(1.0f, 0.0f, 9.0f);    // far, free line of sight
  scan.points.emplace_back(0.0f, 0.0f, -3.0f);   // behind the camera
  scan.points.emplace_back(30.0f, 0.0f, 5.0f);   // outside the image
  const ProjectedScan projected =
      ProjectScan(scan, camera, Rigid3d(), ScanProjectionOptions());
  EXPECT_EQ(projected.visible, (std::vector<bool>{true, false, true, false,
                                                  false}));
  EXPECT_EQ(projected.num_visible, 2);
  EXPECT_NEAR(projected.pixels[0].x(), 100.0, 1e-9);
  EXPECT_NEAR(projected.pixels[2].x(), 100.0 + 100.0 / 9.0, 1e-9);
  int num_in_grid = 0;
  projected.visible_grid.VisitBox({0, 0}, {200, 100},
                                  [&](int) { ++num_in_grid; });
  EXPECT_EQ(num_in_grid, 2);
}

TEST(ScanProjection, UsesCamFromLidar) {
  const Camera camera =
      Camera::FromModelName("PINHOLE", 200, 100, {100, 100, 100, 50});
  LidarScan scan;
  scan.points.emplace_back(5.0f, 0.0f, 0.0f);  // 5 m ahead in LIDAR axes
  Eigen::Matrix3d rotation;
  rotation << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  const Rigid3d cam_from_lidar(Eigen::Quaterniond(rotation),
                               Eigen::Vector3d(0.0, 0.1, 0.0));
  const ProjectedScan projected =
      ProjectScan(scan, camera, cam_from_lidar, ScanProjectionOptions());
  ASSERT_TRUE(projected.visible[0]);
  EXPECT_NEAR(projected.points_in_cam[0].z(), 5.0, 1e-6);
  EXPECT_NEAR(projected.pixels[0].y(), 50.0 + 100.0 * 0.1 / 5.0, 1e-6);
}

}  // namespace
}  // namespace colmap_lidar
