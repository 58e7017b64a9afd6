// Fusion of duplicate 3D segments within one view (section III-B: "to avoid
// multiple instances of the same actual line segment in an image, we also
// fuse 3D segments having similar directions and which are located on the
// same infinite line"). Two segments fuse when their directions differ by
// at most max_angle_deg, the endpoints of each lie within
// max_line_distance of the other's infinite line, and their extents along
// the line overlap or leave a gap of at most max_gap. The fused segment's
// 2D segment spans both 2D segments along the longer one's image line, its
// 3D line is refitted to the union of the inliers, and its 3D endpoints are
// again the back-projections of its 2D endpoints. Repeats until stable.
#pragma once

#include <vector>

#include "colmap_ext/scene/camera.h"
#include "src/lines/line_types.h"

namespace colmap_lidar {

struct SegmentFusionOptions {
  // Maximum angle between the 3D directions, degrees.
  double max_angle_deg = 3.0;
  // Maximum distance of an endpoint to the other segment's line, metres.
  double max_line_distance = 0.05;
  // Maximum gap between the extents along the line, metres (0: they must
  // overlap or touch).
  double max_gap = 0.2;

  bool Check() const;
};

// True when a and b satisfy the fusion criteria.
bool AreFusable(const ViewLineSegment& a, const ViewLineSegment& b,
                const SegmentFusionOptions& options);

// points_in_cam: the scan in the camera frame (the segments' inlier indices
// refer to it; used for inliers without a fitted position). min_ray_line_angle_deg as in EdgeAssociationOptions. The
// result is sorted by decreasing 2D length; descriptors are not computed.
std::vector<ViewLineSegment> FuseSegments(
    std::vector<ViewLineSegment> segments,
    const std::vector<Eigen::Vector3d>& points_in_cam, const Camera& camera,
    const SegmentFusionOptions& options, double min_ray_line_angle_deg);

}  // namespace colmap_lidar
