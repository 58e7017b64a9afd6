// A registered image of a sparse model, as in COLMAP's images.bin/.txt.
#pragma once

#include <string>
#include <vector>

#include "colmap_ext/scene/rigid3.h"
#include "colmap_ext/util/types.h"

namespace colmap_lidar {

struct Point2D {
  // Pixel coordinates with COLMAP's SfM convention: the centre of the
  // upper-left pixel is (0.5, 0.5).
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  point3D_t point3D_id = kInvalidPoint3DId;
};

struct Image {
  image_t image_id = kInvalidImageId;
  // Path relative to the image folder, '/' separated.
  std::string name;
  camera_t camera_id = kInvalidCameraId;
  // World-to-camera transform (COLMAP's qvec/tvec).
  Rigid3d cam_from_world;
  std::vector<Point2D> points2D;

  Eigen::Vector3d ProjectionCenter() const {
    return cam_from_world.Inverse().translation;
  }
};

}  // namespace colmap_lidar
