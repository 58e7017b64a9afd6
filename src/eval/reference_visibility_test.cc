#include "src/eval/reference_visibility.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// One 640x480 PINHOLE camera at the origin looking along +z (COLMAP's
// camera frame: x right, y down).
Reconstruction OneCamera() {
  Reconstruction model;
  Camera camera =
      Camera::FromModelName("PINHOLE", 640, 480, {320.0, 320.0, 320.0, 240.0});
  camera.camera_id = 1;
  model.cameras[1] = camera;
  Image image;
  image.image_id = 1;
  image.camera_id = 1;
  image.name = "000000.png";
  model.images.push_back(image);
  return model;
}

// A square of points every `step` metres in the plane z = `depth`.
void AddWall(double depth, double half_size, double step,
             std::vector<Eigen::Vector3d>* points) {
  for (double x = -half_size; x <= half_size + 1e-9; x += step) {
    for (double y = -half_size; y <= half_size + 1e-9; y += step) {
      points->emplace_back(x, y, depth);
    }
  }
}

TEST(ReferenceVisibility, MeasuresTheSpacing) {
  std::vector<Eigen::Vector3d> points;
  AddWall(5.0, 1.0, 0.02, &points);
  EXPECT_NEAR(MedianPointSpacing(points), 0.02, 1e-9);
}

TEST(ReferenceVisibility, AWallHidesWhatIsBehindIt) {
  std::vector<Eigen::Vector3d> points;
  AddWall(5.0, 1.0, 0.02, &points);  // In front, 2 x 2 m.
  const size_t num_front = points.size();
  AddWall(8.0, 1.0, 0.02, &points);  // Behind it, inside its shadow.
  const size_t num_back = points.size() - num_front;
  points.emplace_back(0.0, 0.0, -3.0);  // Behind the camera.
  points.emplace_back(50.0, 0.0, 5.0);  // Outside the image.
  const std::vector<bool> visible =
      VisibleFromCameras(points, OneCamera(), ReferenceVisibilityOptions());
  size_t front = 0;
  size_t back = 0;
  for (size_t i = 0; i < num_front; ++i) front += visible[i];
  for (size_t i = num_front; i < num_front + num_back; ++i) back += visible[i];
  EXPECT_EQ(front, num_front);
  EXPECT_EQ(back, 0u);
  EXPECT_FALSE(visible[num_front + num_back]);
  EXPECT_FALSE(visible[num_front + num_back + 1]);

  // Farther than max_depth_m: unseen.
  ReferenceVisibilityOptions near_only;
  near_only.max_depth_m = 4.0;
  const std::vector<bool> none =
      VisibleFromCameras(points, OneCamera(), near_only);
  EXPECT_EQ(std::count(none.begin(), none.end(), true), 0);
}

TEST(ReferenceVisibility, GroundSeenAtAGrazingAngleStaysVisible) {
  // Ground 1.5 m below the camera, 2 to 30 m ahead, 2 cm spacing.
  std::vector<Eigen::Vector3d> points;
  for (double z = 2.0; z <= 30.0; z += 0.02) {
    for (double x = -2.0; x <= 2.0; x += 0.02) {
      points.emplace_back(x, 1.5, z);
    }
  }
  const std::vector<bool> visible =
      VisibleFromCameras(points, OneCamera(), ReferenceVisibilityOptions());
  const double share =
      static_cast<double>(std::count(visible.begin(), visible.end(), true)) /
      points.size();
  EXPECT_GT(share, 0.98);
}

TEST(ReferenceVisibility, BadOptionsAndMissingCameraThrow) {
  std::vector<Eigen::Vector3d> points = {{0, 0, 5}};
  ReferenceVisibilityOptions bad;
  bad.relative_tolerance = -1.0;
  EXPECT_THROW(VisibleFromCameras(points, OneCamera(), bad), Error);
  Reconstruction no_camera = OneCamera();
  no_camera.cameras.clear();
  EXPECT_THROW(
      VisibleFromCameras(points, no_camera, ReferenceVisibilityOptions()),
      Error);
}

}  // namespace
}  // namespace colmap_lidar
