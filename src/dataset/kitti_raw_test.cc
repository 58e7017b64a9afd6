#include "src/dataset/kitti_raw.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {

TEST(KittiRaw, LoadsTheSample) {
  const Recording recording =
      LoadKittiRawRecording(testing::KittiSampleDir(), 2);
  EXPECT_EQ(recording.format, "kitti_raw");
  ASSERT_EQ(recording.frames.size(), 20u);
  EXPECT_EQ(recording.frames[0].name, "0000000000");
  EXPECT_FALSE(recording.frames[0].world_from_cam_prior.has_value());
  const Camera& camera = recording.calibration.camera;
  EXPECT_EQ(camera.ModelName(), "PINHOLE");
  EXPECT_EQ(camera.width, 1242u);
  EXPECT_EQ(camera.height, 375u);
  EXPECT_NEAR(camera.params[0], 721.5377, 1e-9);
  EXPECT_NEAR(camera.params[2], 609.5593 + 0.5, 1e-9);
  // The Velodyne sits about 0.27 m behind and 0.08 m above camera 0; camera
  // 2 is 0.06 m to the left of camera 0. Velodyne x (forward) is camera z.
  const Rigid3d& cam_from_lidar = recording.calibration.cam_from_lidar;
  const Eigen::Vector3d forward = cam_from_lidar.rotation * Eigen::Vector3d::UnitX();
  EXPECT_GT(forward.z(), 0.99);
  const Eigen::Vector3d lidar_in_cam = cam_from_lidar.translation;
  EXPECT_NEAR(lidar_in_cam.z(), -0.27, 0.03);
  EXPECT_NEAR(lidar_in_cam.x(), 0.06 - 0.004, 0.03);
}

// The chain must put the LIDAR points on the image: most points in front of
// the camera project inside it, and the road (points about 1.7 m below the
// sensor) lands in the lower image half.
TEST(KittiRaw, LidarProjectsIntoTheImage) {
  const Recording recording =
      LoadKittiRawRecording(testing::KittiSampleDir(), 2);
  const Camera& camera = recording.calibration.camera;
  const LidarScan scan = ReadLidarScan(recording.frames[0].scan_path);
  int in_front = 0, inside = 0, road = 0, road_low = 0;
  for (const Eigen::Vector3f& point : scan.points) {
    const Eigen::Vector3d in_cam =
        recording.calibration.cam_from_lidar * point.cast<double>();
    if (in_cam.z() < 2.0) continue;
    const Eigen::Vector2d pixel = camera.ImgFromCam(in_cam);
    const bool is_inside = pixel.x() >= 0 && pixel.y() >= 0 &&
                           pixel.x() < camera.width && pixel.y() < camera.height;
    ++in_front;
    inside += is_inside;
    if (is_inside && point.z() < -1.5 && point.z() > -1.9) {
      ++road;
      road_low += pixel.y() > camera.height / 2.0;
    }
  }
  EXPECT_GT(inside, 10000);
  EXPECT_GT(road, 1000);
  EXPECT_GT(static_cast<double>(road_low) / road, 0.99);
}

TEST(KittiRaw, MissingCalibrationIsAnError) {
  const std::string dir = testing::CreateTestDir();
  EXPECT_THROW(LoadKittiRawRecording(dir, 2), Error);
  EXPECT_THROW(LoadKittiRawRecording(testing::KittiSampleDir(), 7), Error);
}

}  // namespace
}  // namespace colmap_lidar
