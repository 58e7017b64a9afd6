// The "is l in I_j's field of view" test of Algorithm 1 (paper section
// III-C): a 3D segment in the world frame, taken to a view with its current
// pose, is a candidate for that view when enough of it lies in front of the
// camera, inside the image and, when the view has a LIDAR depth grid, not
// behind the surface the LIDAR saw.
#pragma once

#include <Eigen/Core>

#include "src/matching/line_matching_options.h"
#include "src/matching/matching_view.h"

namespace colmap_lidar {

struct SegmentInView {
  bool visible = false;
  // Fraction of the samples in front, inside the image and not hidden.
  double visible_fraction = 0.0;
  // The part in front of the camera (clipped at min_depth_m), projected,
  // pixels. Meaningful when visible.
  Eigen::Vector2d start2D = Eigen::Vector2d::Zero();
  Eigen::Vector2d end2D = Eigen::Vector2d::Zero();
  // Mean depth of the samples in front of the camera, metres.
  double depth = 0.0;
};

// num_visibility_samples points from start to end (both included) are
// tested; hidden means depth > nearest LIDAR depth * (1 + relative
// tolerance) + absolute tolerance (grown by the pose uncertainty,
// EffectiveThresholds).
SegmentInView ProjectSegmentIntoView(const Eigen::Vector3d& start_in_world,
                                     const Eigen::Vector3d& end_in_world,
                                     const MatchingView& view,
                                     const LineMatchingOptions& options);

}  // namespace colmap_lidar
