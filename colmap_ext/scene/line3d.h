// One of our 3D line tracks: a finite 3D segment in the world frame and the
// 2D line segments (rows of ext_line_segments) that observe it. Stored next
// to a COLMAP model as lines3D.bin / lines3D.txt; stock colmap ignores them.
#pragma once

#include <vector>

#include "colmap_ext/util/types.h"

namespace colmap_lidar {

struct LineTrackElement {
  image_t image_id = kInvalidImageId;
  // Index of the segment among that image's line segments (database order).
  uint32_t line2D_idx = 0;
};

struct Line3D {
  Eigen::Vector3d start_in_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_in_world = Eigen::Vector3d::Zero();
  // Mean line reprojection error in pixels; -1 when unknown.
  double error = -1.0;
  std::vector<LineTrackElement> track;
};

}  // namespace colmap_lidar
