#include "colmap_ext/mvs/dense_maps.h"

#include <cmath>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

Eigen::Vector3d MvsPixelRay(const Eigen::Matrix3d& K, double row,
                            double col) {
  // Solve K * ray = [col, row, 1] for an upper-triangular K with K(2,2) = 1.
  const double y = (row - K(1, 2)) / K(1, 1);
  const double x = (col - K(0, 2) - K(0, 1) * y) / K(0, 0);
  return Eigen::Vector3d(x, y, 1.0);
}

Eigen::Matrix3d ScaleCalibrationToMap(const Eigen::Matrix3d& K,
                                      size_t image_width, size_t image_height,
                                      size_t map_width, size_t map_height) {
  THROW_CHECK(image_width > 0 && image_height > 0,
              "Image size must be > 0 to scale a calibration");
  const double scale_x =
      static_cast<double>(map_width) / static_cast<double>(image_width);
  const double scale_y =
      static_cast<double>(map_height) / static_cast<double>(image_height);
  Eigen::Matrix3d scaled = K;
  scaled.row(0) *= scale_x;
  scaled.row(1) *= scale_y;
  return scaled;
}

DepthMap::DepthMap(size_t width, size_t height) : mat_(width, height, 1) {}

DepthMap::DepthMap(MatF mat) : mat_(std::move(mat)) {
  THROW_CHECK(mat_.GetDepth() == 1,
              "A depth map needs 1 channel, got " << mat_.GetDepth());
}

bool DepthMap::IsValid(size_t row, size_t col) const {
  const float depth = Get(row, col);
  return std::isfinite(depth) && depth > 0;
}

size_t DepthMap::NumValid() const {
  size_t count = 0;
  for (const float depth : mat_.GetData()) {
    if (std::isfinite(depth) && depth > 0) {
      ++count;
    }
  }
  return count;
}

Eigen::Vector3d DepthMap::BackProject(size_t row, size_t col,
                                      const Eigen::Matrix3d& K) const {
  return static_cast<double>(Get(row, col)) *
         MvsPixelRay(K, static_cast<double>(row), static_cast<double>(col));
}

DepthMap DepthMap::Read(const std::string& path) {
  MatF mat;
  mat.Read(path);
  THROW_CHECK(mat.GetDepth() == 1, "Depth map " << path << " has "
                                                << mat.GetDepth()
                                                << " channels, expected 1");
  return DepthMap(std::move(mat));
}

void DepthMap::Write(const std::string& path) const { mat_.Write(path); }

NormalMap::NormalMap(size_t width, size_t height) : mat_(width, height, 3) {}

NormalMap::NormalMap(MatF mat) : mat_(std::move(mat)) {
  THROW_CHECK(mat_.GetDepth() == 3,
              "A normal map needs 3 channels, got " << mat_.GetDepth());
}

Eigen::Vector3f NormalMap::Get(size_t row, size_t col) const {
  return Eigen::Vector3f(mat_.Get(row, col, 0), mat_.Get(row, col, 1),
                         mat_.Get(row, col, 2));
}

void NormalMap::Set(size_t row, size_t col, const Eigen::Vector3f& normal) {
  for (size_t c = 0; c < 3; ++c) {
    mat_.Set(row, col, c, normal(c));
  }
}

bool NormalMap::IsValid(size_t row, size_t col) const {
  return Get(row, col) != Eigen::Vector3f::Zero();
}

Eigen::Vector3f NormalMap::OrientTowardsCamera(const Eigen::Vector3f& normal,
                                               const Eigen::Vector3f& ray) {
  return normal.dot(ray) > 0 ? Eigen::Vector3f(-normal) : normal;
}

NormalMap NormalMap::Read(const std::string& path) {
  MatF mat;
  mat.Read(path);
  THROW_CHECK(mat.GetDepth() == 3, "Normal map " << path << " has "
                                                 << mat.GetDepth()
                                                 << " channels, expected 3");
  return NormalMap(std::move(mat));
}

void NormalMap::Write(const std::string& path) const { mat_.Write(path); }

}  // namespace colmap_lidar
