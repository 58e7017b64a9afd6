#include "src/lines/segment_fusion.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "colmap_ext/util/logging.h"
#include "src/lines/line_geometry.h"

namespace colmap_lidar {
namespace {

Line3 LineOf(const ViewLineSegment& segment) {
  Line3 line;
  line.point = segment.start3D_in_cam;
  line.direction = segment.Direction3D();
  return line;
}

// Merges b into a; false when the merged segment cannot be formed.
bool Merge(const ViewLineSegment& a, const ViewLineSegment& b,
           const std::vector<Eigen::Vector3d>& points_in_cam,
           const Camera& camera, const double min_ray_line_angle_deg,
           ViewLineSegment* merged) {
  const ViewLineSegment& longer =
      a.segment2D.Length() >= b.segment2D.Length() ? a : b;
  const Eigen::Vector2d origin = longer.segment2D.start;
  const Eigen::Vector2d direction = longer.segment2D.Direction();
  double min_along = 0.0;
  double max_along = 0.0;
  for (const Eigen::Vector2d& endpoint :
       {a.segment2D.start, a.segment2D.end, b.segment2D.start,
        b.segment2D.end}) {
    const double along = (endpoint - origin).dot(direction);
    min_along = std::min(min_along, along);
    max_along = std::max(max_along, along);
  }
  ViewLineSegment result;
  result.segment2D.start = origin + min_along * direction;
  result.segment2D.end = origin + max_along * direction;
  // Union of the inliers by scan index, with their fitted positions (the
  // scan position when a segment carries none).
  std::map<int, Eigen::Vector3d> inliers;
  for (const ViewLineSegment* segment : {&a, &b}) {
    for (size_t i = 0; i < segment->inlier_point_idxs.size(); ++i) {
      const int idx = segment->inlier_point_idxs[i];
      inliers.emplace(idx, i < segment->inlier_points_in_cam.size()
                               ? segment->inlier_points_in_cam[i]
                               : points_in_cam[idx]);
    }
  }
  for (const auto& [idx, point] : inliers) {
    result.inlier_point_idxs.push_back(idx);
    result.inlier_points_in_cam.push_back(point);
  }
  Line3 line = LineOf(longer);
  if (result.inlier_points_in_cam.size() >= 2) {
    std::vector<int> all(result.inlier_points_in_cam.size());
    std::iota(all.begin(), all.end(), 0);
    line = FitLineInPlane(result.inlier_points_in_cam, all,
                          ViewingPlaneNormal(camera, result.segment2D.start,
                                             result.segment2D.end));
  }
  if (!BackProjectOntoLine(camera, result.segment2D.start, line,
                           min_ray_line_angle_deg, &result.start3D_in_cam) ||
      !BackProjectOntoLine(camera, result.segment2D.end, line,
                           min_ray_line_angle_deg, &result.end3D_in_cam)) {
    return false;
  }
  *merged = std::move(result);
  return true;
}

}  // namespace

bool SegmentFusionOptions::Check() const {
  if (!(max_angle_deg >= 0.0 && max_angle_deg <= 90.0)) {
    LOG(ERROR) << "LineExtraction.fusion_max_angle_deg must be in [0, 90]";
    return false;
  }
  if (!(max_line_distance >= 0.0) || !(max_gap >= 0.0)) {
    LOG(ERROR) << "LineExtraction.fusion_max_line_distance and "
                  "fusion_max_gap must be >= 0";
    return false;
  }
  return true;
}

bool AreFusable(const ViewLineSegment& a, const ViewLineSegment& b,
                const SegmentFusionOptions& options) {
  const Line3 line_a = LineOf(a);
  const Line3 line_b = LineOf(b);
  const double cos_angle = std::abs(line_a.direction.dot(line_b.direction));
  if (std::acos(std::min(1.0, cos_angle)) * 180.0 / M_PI >
      options.max_angle_deg) {
    return false;
  }
  if (DistanceToLine(line_a, b.start3D_in_cam) > options.max_line_distance ||
      DistanceToLine(line_a, b.end3D_in_cam) > options.max_line_distance ||
      DistanceToLine(line_b, a.start3D_in_cam) > options.max_line_distance ||
      DistanceToLine(line_b, a.end3D_in_cam) > options.max_line_distance) {
    return false;
  }
  const double a_length = (a.end3D_in_cam - a.start3D_in_cam).norm();
  const double t0 = LineCoordinate(line_a, b.start3D_in_cam);
  const double t1 = LineCoordinate(line_a, b.end3D_in_cam);
  const double gap =
      std::max(std::min(t0, t1) - a_length, 0.0 - std::max(t0, t1));
  return gap <= options.max_gap;
}

std::vector<ViewLineSegment> FuseSegments(
    std::vector<ViewLineSegment> segments,
    const std::vector<Eigen::Vector3d>& points_in_cam, const Camera& camera,
    const SegmentFusionOptions& options, const double min_ray_line_angle_deg) {
  auto by_length = [](const ViewLineSegment& a, const ViewLineSegment& b) {
    return a.segment2D.Length() > b.segment2D.Length();
  };
  bool changed = true;
  while (changed) {
    changed = false;
    std::stable_sort(segments.begin(), segments.end(), by_length);
    for (size_t i = 0; i < segments.size() && !changed; ++i) {
      for (size_t j = i + 1; j < segments.size(); ++j) {
        if (!AreFusable(segments[i], segments[j], options)) {
          continue;
        }
        ViewLineSegment merged;
        if (!Merge(segments[i], segments[j], points_in_cam, camera,
                   min_ray_line_angle_deg, &merged)) {
          continue;
        }
        segments[i] = std::move(merged);
        segments.erase(segments.begin() + j);
        changed = true;
        break;
      }
    }
  }
  return segments;
}

}  // namespace colmap_lidar
