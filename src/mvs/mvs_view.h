// One view of the dense workspace as PatchMatch sees it: a grey image in
// [0, 1], the calibration at the map resolution and the pose. Pixel (row,
// col) is the image point (x = col, y = row) with no +0.5 offset, COLMAP's
// MVS convention (colmap-formats.md 4.4), so the ray of a pixel is
// K^-1 [col, row, 1] and a camera point X projects to (K X) / X.z directly.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/image.h"

namespace colmap_lidar {

struct MvsView {
  std::string name;
  int width = 0;
  int height = 0;
  // Row-major grey values in [0, 1].
  std::vector<float> gray;
  Eigen::Matrix3f K = Eigen::Matrix3f::Identity();
  Eigen::Matrix3f K_inv = Eigen::Matrix3f::Identity();
  // cam_from_world.
  Eigen::Matrix3f R = Eigen::Matrix3f::Identity();
  Eigen::Vector3f t = Eigen::Vector3f::Zero();

  float At(int row, int col) const { return gray[row * width + col]; }
  // Bilinear; the caller keeps (x, y) inside [0, width-1] x [0, height-1].
  float Sample(float x, float y) const {
    const int x0 = static_cast<int>(x);
    const int y0 = static_cast<int>(y);
    const int x1 = x0 + 1 < width ? x0 + 1 : x0;
    const int y1 = y0 + 1 < height ? y0 + 1 : y0;
    const float fx = x - x0;
    const float fy = y - y0;
    const float* row0 = &gray[y0 * width];
    const float* row1 = &gray[y1 * width];
    const float top = row0[x0] + fx * (row0[x1] - row0[x0]);
    const float bottom = row1[x0] + fx * (row1[x1] - row1[x0]);
    return top + fy * (bottom - top);
  }
  bool InBounds(float x, float y) const {
    return x >= 0 && y >= 0 && x <= width - 1 && y <= height - 1;
  }
  // Camera-frame ray with z = 1.
  Eigen::Vector3f Ray(float row, float col) const {
    return K_inv * Eigen::Vector3f(col, row, 1.0f);
  }
  Eigen::Vector3f CamFromWorld(const Eigen::Vector3f& point_in_world) const {
    return R * point_in_world + t;
  }
  Eigen::Vector3f ProjectionCenter() const { return -R.transpose() * t; }
  // Optical axis in the world.
  Eigen::Vector3f ViewingDirection() const { return R.row(2).transpose(); }
};

// A view from its calibration and pose with the grey image given directly
// (tests, synthetic data). Throws unless gray.size() == width * height.
MvsView MakeMvsView(const std::string& name, const Eigen::Matrix3d& K,
                    const Rigid3d& cam_from_world, int width, int height,
                    std::vector<float> gray);

// Loads `image_path` as grey and takes K from a PINHOLE or SIMPLE_PINHOLE
// camera; when max_image_size > 0 and the larger side exceeds it, the image
// is resized (area filter) and K scaled by map_size / image_size per axis, as
// stereo_fusion scales it for smaller maps. Throws naming the file when it
// cannot be read or its size differs from the camera's.
MvsView LoadMvsView(const std::string& image_path, const Camera& camera,
                    const Image& image, int max_image_size);

}  // namespace colmap_lidar
