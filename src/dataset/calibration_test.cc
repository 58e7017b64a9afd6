#include "src/dataset/calibration.h"

#include <fstream>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

std::string WriteText(const std::string& dir, const std::string& text) {
  const std::string path = JoinPaths(dir, "calibration.yaml");
  std::ofstream(path) << text;
  return path;
}

const char* kDocExample = R"(camera:
  model: PINHOLE            # a comment
  width: 848
  height: 480
  params: [430.0, 430.0, 424.0, 240.0]
cam_from_lidar:
  - [0, -1, 0, 0.00]
  - [0, 0, -1, -0.08]
  - [1, 0, 0, -0.05]
  - [0, 0, 0, 1]
lidar:
  rings: 64
  vertical_fov_deg: [-16.6, 16.6]
  range_noise_m: 0.015
)";

TEST(Calibration, ReadsTheDocumentedExample) {
  const std::string dir = testing::CreateTestDir();
  const RigCalibration calib = ReadCalibration(WriteText(dir, kDocExample));
  EXPECT_EQ(calib.camera.ModelName(), "PINHOLE");
  EXPECT_EQ(calib.camera.width, 848u);
  EXPECT_EQ(calib.camera.height, 480u);
  ASSERT_EQ(calib.camera.params.size(), 4u);
  EXPECT_DOUBLE_EQ(calib.camera.params[2], 424.0);
  // LIDAR x (forward) becomes camera z.
  const Eigen::Vector3d forward =
      calib.cam_from_lidar * Eigen::Vector3d(1, 0, 0);
  EXPECT_NEAR((forward - Eigen::Vector3d(0, -0.08, 0.95)).norm(), 0, 1e-12);
  ASSERT_TRUE(calib.lidar.has_value());
  EXPECT_EQ(calib.lidar->rings, 64);
  EXPECT_DOUBLE_EQ(calib.lidar->vertical_fov_min_deg, -16.6);
  EXPECT_DOUBLE_EQ(calib.lidar->range_noise_m, 0.015);
}

TEST(Calibration, WriteReadRoundTrip) {
  const std::string dir = testing::CreateTestDir();
  RigCalibration calib;
  calib.camera = Camera::FromModelName(
      "OPENCV", 640, 480, {500, 501, 320.5, 240.5, -0.1, 0.01, 0.001, -0.002});
  calib.cam_from_lidar = Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized())),
      Eigen::Vector3d(0.1, -0.2, 0.3));
  const std::string path = JoinPaths(dir, "out.yaml");
  WriteCalibration(path, calib);
  const RigCalibration read = ReadCalibration(path);
  EXPECT_EQ(read.camera.ModelName(), "OPENCV");
  for (size_t i = 0; i < calib.camera.params.size(); ++i) {
    EXPECT_DOUBLE_EQ(read.camera.params[i], calib.camera.params[i]);
  }
  EXPECT_TRUE(read.cam_from_lidar.ToMatrix().isApprox(
      calib.cam_from_lidar.ToMatrix(), 1e-12));
  EXPECT_FALSE(read.lidar.has_value());
}

void ExpectError(const std::string& text, const std::string& fragment) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = WriteText(dir, text);
  try {
    ReadCalibration(path);
    FAIL() << "no error for: " << text;
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
  }
}

TEST(Calibration, RejectsBadInput) {
  std::string text = kDocExample;
  ExpectError("camera: [unclosed", "malformed YAML");
  ExpectError(std::string(kDocExample).replace(text.find("PINHOLE"), 7, "FISHEYE_X"),
              "FISHEYE_X");
  ExpectError(std::string(kDocExample)
                  .replace(text.find("[430.0, 430.0, 424.0, 240.0]"), 28,
                           "[430.0, 424.0, 240.0]"),
              "camera");
  ExpectError(std::string(kDocExample).replace(text.find("848"), 3, ".nan"),
              "camera.width");
  ExpectError(std::string(kDocExample).replace(text.find("[0, -1, 0, 0.00]"), 16,
                                               "[0, -2, 0, 0.00]"),
              "rigid");
  // A ring count past int's range (found by fuzz_calibration), fractional
  // or negative is named, never converted.
  for (const char* rings : {"1.7e16", "63.5", "-1"}) {
    ExpectError(std::string(kDocExample).replace(text.find("rings: 64"), 9,
                                                 std::string("rings: ") + rings),
                "lidar.rings");
  }
  ExpectError("camera:\n  model: PINHOLE\n", "camera.width");
  ExpectError(std::string(kDocExample).substr(0, text.find("cam_from_lidar")),
              "cam_from_lidar");
  const std::string dir = testing::CreateTestDir();
  EXPECT_THROW(ReadCalibration(JoinPaths(dir, "missing.yaml")), Error);
}

}  // namespace
}  // namespace colmap_lidar
