// What the steps of the relative line pose (relative_line_pose.h) share, and
// its step 1: the two views' segments as lines in their own camera frames,
// the prior cam2_from_cam1, and the candidate correspondences that the prior
// gates (direction, midpoint distance, LBD). Also the small geometric
// helpers of the other steps. Internal to src/matching.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "src/matching/line_matching_options.h"
#include "src/matching/matching_view.h"

namespace colmap_lidar {
namespace relative_pose_internal {

// A segment in its camera frame: endpoints, midpoint, unit direction.
struct Line {
  Eigen::Vector3d start;
  Eigen::Vector3d end;
  Eigen::Vector3d midpoint;
  Eigen::Vector3d direction;
  // Unit normal of the plane through the camera centre and the segment.
  Eigen::Vector3d plane_normal;
};

Line MakeLine(const MatchingSegment& segment);

// A candidate correspondence: segment a of view 1, segment b of view 2,
// b's direction signed to agree with a's under the prior rotation.
struct Candidate {
  int a = -1;
  int b = -1;
  Eigen::Vector3d direction_b;
};

// The segments of view 1 to register against all segments of view 2.
struct LinePoseProblem {
  // lines1[a] is segments1[a] of view 1; lines2[b] is segment b of view 2.
  std::vector<Line> lines1;
  std::vector<Line> lines2;
  std::vector<const std::array<uint8_t, 32>*> descriptors1;
  std::vector<const std::array<uint8_t, 32>*> descriptors2;
  // cam2_from_cam1 of the prior poses.
  Eigen::Matrix3d prior_rotation;
  Eigen::Vector3d prior_translation;
  double focal_length1 = 1.0;
  double focal_length2 = 1.0;
  // Filled by FindCandidates: the candidates, and per line of view 1 the
  // indices of its candidates.
  std::vector<Candidate> candidates;
  std::vector<std::vector<int>> candidates_of;
};

LinePoseProblem MakeLinePoseProblem(const MatchingView& view1,
                                    const std::vector<int>& segments1,
                                    const MatchingView& view2);

// Step 1: every line a of view 1 against every line b of view 2, after the
// prior relative pose: directions within the rotation gate, a's midpoint
// within the distance gate of b's line (EffectiveThresholds at a's depth in
// view 2), LBD distance below t_LBD.
void FindCandidates(const LineMatchingOptions& options,
                    LinePoseProblem* problem);

inline Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d skew;
  skew << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return skew;
}

inline Eigen::Matrix3d OrthogonalProjector(const Eigen::Vector3d& direction) {
  return Eigen::Matrix3d::Identity() - direction * direction.transpose();
}

// Mean distance of a's endpoints, moved by (rotation, translation), to b's
// line.
inline double LineDistance(const Eigen::Matrix3d& rotation,
                           const Eigen::Vector3d& translation, const Line& a,
                           const Line& b) {
  const auto distance = [&](const Eigen::Vector3d& point) {
    const Eigen::Vector3d offset = rotation * point + translation - b.midpoint;
    return (offset - offset.dot(b.direction) * b.direction).norm();
  };
  return 0.5 * (distance(a.start) + distance(a.end));
}

// Angle between two undirected directions, degrees in [0, 90].
inline double AngleDeg(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::acos(std::min(1.0, std::abs(u.dot(v)))) * 180.0 / M_PI;
}

inline double RotationAngleDeg(const Eigen::Matrix3d& rotation) {
  return Eigen::AngleAxisd(rotation).angle() * 180.0 / M_PI;
}

}  // namespace relative_pose_internal
}  // namespace colmap_lidar
