#include "colmap_ext/scene/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace colmap_lidar {
namespace {

// Message of the colmap_lidar::Error thrown by fn, or "" if none.
template <typename Fn>
std::string ErrorMessage(Fn&& fn) {
  try {
    fn();
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(Camera, FromModelName) {
  const Camera camera =
      Camera::FromModelName("OPENCV", 640, 480, {1, 2, 3, 4, 5, 6, 7, 8});
  EXPECT_EQ(camera.model_id, CameraModelId::kOpenCV);
  EXPECT_EQ(camera.ModelName(), "OPENCV");
  EXPECT_EQ(camera.width, 640u);
  EXPECT_EQ(camera.height, 480u);
  EXPECT_EQ(camera.params.size(), 8u);
  EXPECT_FALSE(camera.has_prior_focal_length);
}

TEST(Camera, FromModelNameErrorsNameModelAndCounts) {
  const std::string count_error = ErrorMessage([] {
    Camera::FromModelName("PINHOLE", 640, 480, {1, 2, 3});
  });
  EXPECT_NE(count_error.find("PINHOLE"), std::string::npos) << count_error;
  EXPECT_NE(count_error.find("expects 4"), std::string::npos) << count_error;
  EXPECT_NE(count_error.find("got 3"), std::string::npos) << count_error;
  const std::string name_error = ErrorMessage([] {
    Camera::FromModelName("PINHOL", 640, 480, {1, 2, 3, 4});
  });
  EXPECT_NE(name_error.find("PINHOL"), std::string::npos) << name_error;
}

TEST(Camera, CheckGivesTheReason) {
  Camera camera =
      Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
  camera.camera_id = 7;
  EXPECT_TRUE(camera.IsValid());
  EXPECT_NO_THROW(camera.Check());

  Camera bad = camera;
  bad.params.push_back(1.0);
  EXPECT_FALSE(bad.IsValid());
  EXPECT_NE(ErrorMessage([&] { bad.Check(); }).find("expects 4"),
            std::string::npos);

  bad = camera;
  bad.params[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(bad.IsValid());
  EXPECT_NE(ErrorMessage([&] { bad.Check(); }).find("not finite"),
            std::string::npos);

  bad = camera;
  bad.height = 0;
  EXPECT_FALSE(bad.IsValid());
  EXPECT_NE(ErrorMessage([&] { bad.Check(); }).find("640x0"),
            std::string::npos);

  bad = camera;
  bad.model_id = static_cast<CameraModelId>(99);
  EXPECT_FALSE(bad.IsValid());
  const std::string message = ErrorMessage([&] { bad.Check(); });
  EXPECT_NE(message.find("99"), std::string::npos) << message;
  EXPECT_NE(message.find("camera 7"), std::string::npos) << message;
}

TEST(Camera, CalibrationMatrixAndMeanFocalLength) {
  const Camera pinhole =
      Camera::FromModelName("PINHOLE", 640, 480, {500, 520, 320, 240});
  EXPECT_DOUBLE_EQ(pinhole.MeanFocalLength(), 510.0);
  Eigen::Matrix3d expected;
  expected << 500, 0, 320, 0, 520, 240, 0, 0, 1;
  EXPECT_EQ(pinhole.CalibrationMatrix(), expected);

  const Camera simple =
      Camera::FromModelName("SIMPLE_RADIAL", 640, 480, {450, 321, 239, 0.1});
  EXPECT_DOUBLE_EQ(simple.MeanFocalLength(), 450.0);
  expected << 450, 0, 321, 0, 450, 239, 0, 0, 1;
  EXPECT_EQ(simple.CalibrationMatrix(), expected);
}

TEST(Camera, ImgFromCamAndCamFromImg) {
  const Camera camera = Camera::FromModelName(
      "OPENCV", 640, 480, {500, 520, 320, 240, -0.1, 0.02, 0.001, 0.002});
  const Eigen::Vector3d point_in_cam(0.4, -0.3, 2.0);
  const Eigen::Vector2d pixel = camera.ImgFromCam(point_in_cam);
  // Same as the model function.
  double x, y;
  OpenCVCameraModel::ImgFromCam(camera.params.data(), 0.4, -0.3, 2.0, &x, &y);
  EXPECT_EQ(pixel, Eigen::Vector2d(x, y));
  const Eigen::Vector2d normalized = camera.CamFromImg(pixel);
  EXPECT_NEAR(normalized.x(), 0.2, 1e-12);
  EXPECT_NEAR(normalized.y(), -0.15, 1e-12);

  Camera invalid = camera;
  invalid.params.pop_back();
  EXPECT_THROW(invalid.ImgFromCam(point_in_cam), Error);
}

}  // namespace
}  // namespace colmap_lidar
