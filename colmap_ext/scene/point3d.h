// A sparse 3D point with its track, as in COLMAP's points3D.bin/.txt.
#pragma once

#include <vector>

#include "colmap_ext/util/types.h"

namespace colmap_lidar {

struct TrackElement {
  image_t image_id = kInvalidImageId;
  point2D_t point2D_idx = kInvalidPoint2DIdx;
};

struct Point3D {
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  Vector3ub color = Vector3ub::Zero();
  // Mean reprojection error in pixels; -1 when unknown.
  double error = -1.0;
  std::vector<TrackElement> track;
};

}  // namespace colmap_lidar
