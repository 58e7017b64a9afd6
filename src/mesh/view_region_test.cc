#include "src/mesh/view_region.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// One 100x100 camera at the origin looking along +z (focal 50 px, principal
// point at the centre: a 90-degree field of view) and a LIDAR origin beside
// it; visual points at depths 1..20 m on the optical axis.
MeshingInput CameraAndLidarInput() {
  MeshingInput input;
  MeshingSensor camera;
  camera.is_camera = true;
  camera.image_width = 100;
  camera.image_height = 100;
  Eigen::Matrix3d k;
  k << 50, 0, 50, 0, 50, 50, 0, 0, 1;
  camera.proj_matrix = k * Eigen::Matrix3x4d::Identity();
  input.sensors.push_back(camera);
  MeshingSensor lidar;
  lidar.position_in_world = Eigen::Vector3d(0, -1, 0);
  input.sensors.push_back(lidar);
  for (int depth = 1; depth <= 20; ++depth) {
    input.AddPoint(Eigen::Vector3d(0, 0, depth), MeshingPointSource::kVisual,
                   1.f, {0});
  }
  return input;
}

TEST(ViewRegion, MaxDepthIsAQuantileOfTheVisualDepths) {
  const MeshingInput input = CameraAndLidarInput();
  ViewRegionOptions options;
  options.depth_quantile = 0.5;
  options.depth_factor = 2.0;
  // Median of 1..20 (rank 10 of 0..19 -> 11 m), doubled.
  EXPECT_NEAR(ViewRegionMaxDepth(options, input), 22.0, 1e-9);
  options.depth_factor = 0;
  EXPECT_EQ(ViewRegionMaxDepth(options, input), 0.0);
  options.depth_quantile = 0;
  EXPECT_THROW(ViewRegionMaxDepth(options, input), Error);
}

TEST(ViewRegion, KeepsPointsInAnImageWithinTheDepth) {
  MeshingInput input = CameraAndLidarInput();
  // LIDAR points: in view (kept), behind the camera, outside the 90-degree
  // cone, beyond the depth bound.
  input.AddPoint(Eigen::Vector3d(1, 1, 5), MeshingPointSource::kLidar, 1.f,
                 {1});
  input.AddPoint(Eigen::Vector3d(0, 0, -5), MeshingPointSource::kLidar, 1.f,
                 {1});
  input.AddPoint(Eigen::Vector3d(8, 0, 5), MeshingPointSource::kLidar, 1.f,
                 {1});
  input.AddPoint(Eigen::Vector3d(0, 0, 30), MeshingPointSource::kLidar, 1.f,
                 {1});
  EXPECT_TRUE(IsInViewRegion(input, 25.0, Eigen::Vector3d(1, 1, 5)));
  EXPECT_FALSE(IsInViewRegion(input, 25.0, Eigen::Vector3d(0, 0, -5)));
  EXPECT_EQ(CropToViewRegion(25.0, &input), 3u);
  ASSERT_EQ(input.NumPoints(), 21u);
  EXPECT_EQ(input.positions.back(), Eigen::Vector3d(1, 1, 5));
  EXPECT_EQ(input.sources.back(), MeshingPointSource::kLidar);
  EXPECT_EQ(input.visibility.back(), std::vector<uint32_t>{1});
  input.Check();
  // No bound: nothing removed.
  EXPECT_EQ(CropToViewRegion(0.0, &input), 0u);
}

TEST(ViewRegion, LidarOnlyInputIsNotCropped) {
  MeshingInput input;
  MeshingSensor lidar;
  input.sensors.push_back(lidar);
  input.AddPoint(Eigen::Vector3d(0, 0, 1), MeshingPointSource::kLidar, 1.f,
                 {0});
  ViewRegionOptions options;
  options.depth_factor = 2.0;
  EXPECT_EQ(ViewRegionMaxDepth(options, input), 0.0);
  EXPECT_EQ(CropToViewRegion(10.0, &input), 0u);
}

}  // namespace
}  // namespace colmap_lidar
