#include "src/mvs/mvs_view.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

MvsView MakeMvsView(const std::string& name, const Eigen::Matrix3d& K,
                    const Rigid3d& cam_from_world, int width, int height,
                    std::vector<float> gray) {
  THROW_CHECK(width > 0 && height > 0 &&
                  gray.size() == static_cast<size_t>(width) * height,
              "view " << name << ": image of " << gray.size()
                      << " values for " << width << "x" << height);
  MvsView view;
  view.name = name;
  view.width = width;
  view.height = height;
  view.gray = std::move(gray);
  view.K = K.cast<float>();
  view.K_inv = K.inverse().cast<float>();
  view.R = cam_from_world.rotation.toRotationMatrix().cast<float>();
  view.t = cam_from_world.translation.cast<float>();
  return view;
}

MvsView LoadMvsView(const std::string& image_path, const Camera& camera,
                    const Image& image, int max_image_size) {
  THROW_CHECK(camera.ModelName() == "PINHOLE" ||
                  camera.ModelName() == "SIMPLE_PINHOLE",
              "camera " << camera.camera_id << " of " << image.name << " is "
                        << camera.ModelName()
                        << "; the dense workspace needs undistorted "
                           "PINHOLE cameras");
  cv::Mat gray = cv::imread(image_path, cv::IMREAD_GRAYSCALE);
  THROW_CHECK(!gray.empty(), "cannot read image " << image_path);
  THROW_CHECK(static_cast<uint64_t>(gray.cols) == camera.width &&
                  static_cast<uint64_t>(gray.rows) == camera.height,
              "image " << image_path << " is " << gray.cols << "x" << gray.rows
                       << " but its camera is " << camera.width << "x"
                       << camera.height);
  Eigen::Matrix3d K = camera.CalibrationMatrix();
  if (max_image_size > 0 && std::max(gray.cols, gray.rows) > max_image_size) {
    const double scale =
        static_cast<double>(max_image_size) / std::max(gray.cols, gray.rows);
    const int width = std::max(1, static_cast<int>(std::lround(gray.cols * scale)));
    const int height = std::max(1, static_cast<int>(std::lround(gray.rows * scale)));
    const double sx = static_cast<double>(width) / gray.cols;
    const double sy = static_cast<double>(height) / gray.rows;
    cv::Mat resized;
    cv::resize(gray, resized, cv::Size(width, height), 0, 0, cv::INTER_AREA);
    gray = resized;
    K(0, 0) *= sx;
    K(0, 2) *= sx;
    K(1, 1) *= sy;
    K(1, 2) *= sy;
  }
  std::vector<float> values(static_cast<size_t>(gray.cols) * gray.rows);
  for (int row = 0; row < gray.rows; ++row) {
    const uint8_t* src = gray.ptr<uint8_t>(row);
    for (int col = 0; col < gray.cols; ++col) {
      values[row * gray.cols + col] = src[col] / 255.0f;
    }
  }
  return MakeMvsView(image.name, K, image.cam_from_world, gray.cols, gray.rows,
                     std::move(values));
}

}  // namespace colmap_lidar
