#include "src/mvs/dense_cameras.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

// A dense workspace as stock image_undistorter --max_image_size 320 leaves
// it: 848x480 PINHOLE cameras, 320x181 images.
std::string WriteWorkspace(const cv::Size& second_image_size) {
  const std::string dense = JoinPaths(testing::CreateTestDir(), "dense");
  std::filesystem::create_directories(JoinPaths(dense, "images"));
  Reconstruction reconstruction;
  reconstruction.cameras[1] =
      Camera::FromModelName("PINHOLE", 848, 480, {424.0, 420.0, 424.0, 240.0});
  reconstruction.cameras[1].camera_id = 1;
  for (int i = 0; i < 2; ++i) {
    Image image;
    image.image_id = i + 1;
    image.camera_id = 1;
    image.name = "frame" + std::to_string(i) + ".png";
    reconstruction.images.push_back(image);
    const cv::Size size = i == 0 ? cv::Size(320, 181) : second_image_size;
    cv::imwrite(JoinPaths(JoinPaths(dense, "images"), image.name),
                cv::Mat(size, CV_8UC3, cv::Scalar(90, 120, 150)));
  }
  WriteReconstruction(JoinPaths(dense, "sparse"), reconstruction,
                      ModelFormat::kBinary);
  return dense;
}

TEST(ScaleDenseCamerasToImages, ScalesTheCameraToItsImages) {
  const std::string dense = WriteWorkspace(cv::Size(320, 181));
  EXPECT_EQ(ScaleDenseCamerasToImages(dense), 1);
  const Reconstruction scaled = ReadReconstruction(JoinPaths(dense, "sparse"));
  const Camera& camera = scaled.cameras.at(1);
  EXPECT_EQ(camera.width, 320u);
  EXPECT_EQ(camera.height, 181u);
  EXPECT_NEAR(camera.params[0], 424.0 * 320.0 / 848.0, 1e-9);
  EXPECT_NEAR(camera.params[1], 420.0 * 181.0 / 480.0, 1e-9);
  EXPECT_NEAR(camera.params[2], 424.0 * 320.0 / 848.0, 1e-9);
  EXPECT_NEAR(camera.params[3], 240.0 * 181.0 / 480.0, 1e-9);
  EXPECT_EQ(scaled.images.size(), 2u);
  // In step now: a second call changes nothing.
  EXPECT_EQ(ScaleDenseCamerasToImages(dense), 0);
}

TEST(ScaleDenseCamerasToImages, ImagesOfOneCameraWithTwoSizesAreAnError) {
  const std::string dense = WriteWorkspace(cv::Size(300, 170));
  try {
    ScaleDenseCamerasToImages(dense);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("frame1.png"), std::string::npos)
        << error.what();
  }
  // Nothing was written.
  EXPECT_EQ(ReadReconstruction(JoinPaths(dense, "sparse")).cameras.at(1).width,
            848u);
}

TEST(ScaleDenseCamerasToImages, MissingImageIsNamed) {
  const std::string dense = WriteWorkspace(cv::Size(320, 181));
  std::filesystem::remove(JoinPaths(dense, "images/frame1.png"));
  try {
    ScaleDenseCamerasToImages(dense);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("frame1.png"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace colmap_lidar
