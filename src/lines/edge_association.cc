#include "src/lines/edge_association.h"

#include <algorithm>
#include <cmath>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// The LIDAR points (camera frame) near the 2D segment in the image, for the
// texture test: the segment's box expanded by `radius` metres seen at the
// nearer endpoint's depth.
std::vector<Eigen::Vector3d> NeighbourPoints(const ViewLineSegment& lifted,
                                             const Camera& camera,
                                             const ProjectedScan& projected,
                                             double radius) {
  const double depth =
      std::max(0.1, std::min(lifted.start3D_in_cam.z(), lifted.end3D_in_cam.z()));
  const double margin = radius * camera.MeanFocalLength() / depth + 2.0;
  const Eigen::Vector2d min =
      lifted.segment2D.start.cwiseMin(lifted.segment2D.end).array() - margin;
  const Eigen::Vector2d max =
      lifted.segment2D.start.cwiseMax(lifted.segment2D.end).array() + margin;
  std::vector<Eigen::Vector3d> points;
  projected.visible_grid.VisitBox(min, max, [&](int idx) {
    points.push_back(projected.points_in_cam[idx]);
  });
  return points;
}

// Whether two ring neighbours are across an occluding contour: their ranges
// differ by more than max_gap or, when that is smaller, ratio times the
// nearer range (the rule of LidarEdgeOptions::occlusion_range_gap / _ratio).
struct RangeJump {
  double max_gap = 0.3;
  double ratio = 0.0;
  bool operator()(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    const double range_a = a.norm();
    const double range_b = b.norm();
    const double gap =
        ratio > 0.0 ? std::min(max_gap, ratio * std::min(range_a, range_b))
                    : max_gap;
    return std::abs(range_a - range_b) > gap;
  }
};

// The ring segment outer -> inner extended beyond `inner` to the plane
// through the origin with normal `normal`, by at most one segment length
// (the crossing lies between inner and its other neighbour). False when
// outer is missing, across a range jump, or the extension is out of reach.
bool ExtendToPlane(const std::vector<Eigen::Vector3d>& points, int inner,
                   int outer, const Eigen::Vector3d& normal,
                   const RangeJump& is_jump, Eigen::Vector3d* crossing) {
  if (outer < 0 || is_jump(points[outer], points[inner])) {
    return false;
  }
  const double side_inner = normal.dot(points[inner]);
  const double side_outer = normal.dot(points[outer]);
  const double difference = side_inner - side_outer;
  if (std::abs(difference) < 1e-12) {
    return false;
  }
  // points[inner] + s * (points[inner] - points[outer]) is on the plane.
  const double s = -side_inner / difference;
  if (!(s >= 0.0 && s <= 1.0)) {
    return false;
  }
  *crossing = points[inner] + s * (points[inner] - points[outer]);
  return true;
}

// The crossing of point idx's ring with the plane through the origin with
// normal `normal`, searched up to max_steps ring steps each way; the
// point itself when there is none or the crossing is a range jump.
Eigen::Vector3d RefineAlongRing(int idx, const Eigen::Vector3d& normal,
                                const ProjectedScan& projected,
                                const RingNeighbors& neighbors,
                                int max_steps, const RangeJump& is_jump) {
  const std::vector<Eigen::Vector3d>& points = projected.points_in_cam;
  const double side = normal.dot(points[idx]);
  for (int step = 0; step < max_steps; ++step) {
    for (const std::vector<int>* direction : {&neighbors.next, &neighbors.prev}) {
      // Walk `step` points from idx, then test the pair (a, b).
      int a = idx;
      for (int i = 0; i < step && a >= 0; ++i) {
        a = (*direction)[a];
      }
      if (a < 0) {
        continue;
      }
      const int b = (*direction)[a];
      if (b < 0) {
        continue;
      }
      const double side_a = normal.dot(points[a]);
      const double side_b = normal.dot(points[b]);
      if ((side_a > 0) == (side_b > 0) && side_a != 0.0) {
        continue;
      }
      if ((side_a > 0) != (side > 0) && step > 0) {
        continue;
      }
      if (is_jump(points[a], points[b])) {
        // An occluding contour: the edge is on the nearer surface. Extend
        // the nearer point's ring polyline (its next point away from the
        // jump) to the plane, by at most one step; else keep the point.
        const bool a_nearer = points[a].norm() < points[b].norm();
        const int near = a_nearer ? a : b;
        const std::vector<int>& away =
            (a_nearer == (direction == &neighbors.next)) ? neighbors.prev
                                                         : neighbors.next;
        const int behind = away[near];
        if (behind >= 0 && !is_jump(points[behind], points[near])) {
          const double side_near = normal.dot(points[near]);
          const double side_behind = normal.dot(points[behind]);
          if (std::abs(side_near - side_behind) > 1e-9) {
            const double t = side_near / (side_near - side_behind);
            if (t >= -1.0 && t <= 0.0) {
              return points[near] + t * (points[behind] - points[near]);
            }
          }
        }
        return points[near];
      }
      // The chord a-b cuts the corner between a's face and b's face: it
      // lies inside a convex crease and in front of a concave one, a bias
      // of up to half a ring step along the viewing ray. Each face's ring
      // polyline extended to the plane meets the crease itself; their mean
      // is unbiased. The chord is the fallback (no outer neighbour, a range
      // jump, or a face nearly parallel to the plane).
      const int a_out = (direction == &neighbors.next ? neighbors.prev
                                                      : neighbors.next)[a];
      const int b_out = (*direction)[b];
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      int num_faces = 0;
      for (const auto& [inner, outer] : {std::pair<int, int>(a, a_out),
                                         std::pair<int, int>(b, b_out)}) {
        Eigen::Vector3d crossing;
        if (ExtendToPlane(points, inner, outer, normal, is_jump,
                          &crossing)) {
          sum += crossing;
          ++num_faces;
        }
      }
      if (num_faces == 2) {
        return 0.5 * sum;
      }
      const double t = side_a / (side_a - side_b);
      return points[a] + t * (points[b] - points[a]);
    }
  }
  return points[idx];
}

}  // namespace

bool EdgeAssociationOptions::Check() const {
  if (!(max_point_distance_px > 0.0)) {
    LOG(ERROR) << "LineExtraction.max_point_distance_px must be > 0";
    return false;
  }
  if (!(min_inlier_coverage >= 0.0 && min_inlier_coverage <= 1.0)) {
    LOG(ERROR) << "LineExtraction.min_inlier_coverage must be in [0, 1]";
    return false;
  }
  if (!(max_reprojection_angle_deg > 0.0 &&
        max_reprojection_angle_deg <= 90.0) ||
      !(max_reprojection_distance_px > 0.0)) {
    LOG(ERROR) << "LineExtraction.max_reprojection_angle_deg must be in (0, "
                  "90] and max_reprojection_distance_px > 0";
    return false;
  }
  if (!(min_ray_line_angle_deg >= 0.0 && min_ray_line_angle_deg < 90.0)) {
    LOG(ERROR) << "LineExtraction.min_ray_line_angle_deg must be in [0, 90)";
    return false;
  }
  if (!(max_refine_move_steps >= 0.0)) {
    LOG(ERROR) << "LineExtraction.max_refine_move_steps must be >= 0";
    return false;
  }
  if (max_refine_steps < 1 || !(refine_max_range_jump > 0.0) ||
      !(refine_range_jump_ratio >= 0.0)) {
    LOG(ERROR) << "LineExtraction.max_refine_steps must be >= 1, "
                  "refine_max_range_jump > 0 and refine_range_jump_ratio >= 0";
    return false;
  }
  if (!(max_endpoint_range > 0.0)) {
    LOG(ERROR) << "LineExtraction.max_endpoint_range must be > 0";
    return false;
  }
  return ransac.Check() && texture.Check();
}

LiftResult LiftSegment(const LineSegment2D& segment, const Camera& camera,
                       const ProjectedScan& projected,
                       const PixelGrid& edge_grid,
                       const EdgeAssociationOptions& options,
                       ViewLineSegment* lifted,
                       const RingNeighbors* ring_neighbors,
                       std::optional<LineSurfaceType>* surface) {
  if (surface != nullptr) {
    surface->reset();
  }
  const double length = segment.Length();
  const Eigen::Vector2d direction = segment.Direction();
  const Eigen::Vector2d normal(-direction.y(), direction.x());
  const double margin = options.max_point_distance_px;

  // 1. Edge points near the segment.
  std::vector<int> candidate_idxs;
  std::vector<Eigen::Vector3d> candidate_points;
  const Eigen::Vector2d box_min =
      segment.start.cwiseMin(segment.end).array() - margin;
  const Eigen::Vector2d box_max =
      segment.start.cwiseMax(segment.end).array() + margin;
  edge_grid.VisitBox(box_min, box_max, [&](int idx) {
    const Eigen::Vector2d offset = projected.pixels[idx] - segment.start;
    const double along = offset.dot(direction);
    if (along < -margin || along > length + margin ||
        std::abs(offset.dot(normal)) > margin) {
      return;
    }
    candidate_idxs.push_back(idx);
    candidate_points.push_back(projected.points_in_cam[idx]);
  });
  if (static_cast<int>(candidate_idxs.size()) < options.ransac.min_inliers) {
    return LiftResult::kTooFewPoints;
  }
  const Eigen::Vector3d plane_normal =
      ViewingPlaneNormal(camera, segment.start, segment.end);
  if (options.refine_along_rings && ring_neighbors != nullptr &&
      !ring_neighbors->empty()) {
    const std::vector<Eigen::Vector3d>& points = projected.points_in_cam;
    RangeJump is_jump;
    is_jump.max_gap = options.refine_max_range_jump;
    is_jump.ratio = options.refine_range_jump_ratio;
    size_t num_kept = 0;
    for (size_t i = 0; i < candidate_idxs.size(); ++i) {
      const int idx = candidate_idxs[i];
      const Eigen::Vector3d refined = RefineAlongRing(
          idx, plane_normal, projected, *ring_neighbors,
          options.max_refine_steps, is_jump);
      // A crease's edge point is within about one ring step of where its
      // ring crosses the crease; one moved farther was detected at another
      // (nearby) crease and would carry that crease's depth onto this line.
      if (options.max_refine_move_steps > 0.0) {
        const int neighbour = ring_neighbors->next[idx] >= 0
                                  ? ring_neighbors->next[idx]
                                  : ring_neighbors->prev[idx];
        if (neighbour >= 0 &&
            (refined - points[idx]).norm() >
                options.max_refine_move_steps *
                    (points[neighbour] - points[idx]).norm()) {
          continue;
        }
      }
      candidate_idxs[num_kept] = idx;
      candidate_points[num_kept] = refined;
      ++num_kept;
    }
    candidate_idxs.resize(num_kept);
    candidate_points.resize(num_kept);
    if (static_cast<int>(num_kept) < options.ransac.min_inliers) {
      return LiftResult::kTooFewPoints;
    }
  }

  // 2. RANSAC.
  const LineRansacResult ransac =
      FitLineRansac(candidate_points, options.ransac);
  if (!ransac.success) {
    return LiftResult::kRansacFailed;
  }
  Line3 line = ransac.line;
  if (options.fit_in_viewing_plane) {
    line = FitLineInPlane(candidate_points, ransac.inliers, plane_normal);
  }
  double min_along = length;
  double max_along = 0.0;
  double min_t = 1e30;
  double max_t = -1e30;
  for (const int position : ransac.inliers) {
    const double along =
        (projected.pixels[candidate_idxs[position]] - segment.start)
            .dot(direction);
    min_along = std::min(min_along, along);
    max_along = std::max(max_along, along);
    const double t = LineCoordinate(line, candidate_points[position]);
    min_t = std::min(min_t, t);
    max_t = std::max(max_t, t);
  }
  const double coverage =
      (std::clamp(max_along, 0.0, length) - std::clamp(min_along, 0.0, length)) /
      length;
  if (coverage < options.min_inlier_coverage) {
    return LiftResult::kLowCoverage;
  }

  // 3. Reprojection of the fitted line (through its inlier extremes).
  const Eigen::Vector3d first = line.point + min_t * line.direction;
  const Eigen::Vector3d last = line.point + max_t * line.direction;
  if (first.z() <= 0.0 || last.z() <= 0.0) {
    return LiftResult::kReprojection;
  }
  const Eigen::Vector2d first_px = camera.ImgFromCam(first);
  const Eigen::Vector2d last_px = camera.ImgFromCam(last);
  if ((last_px - first_px).norm() < 1.0) {
    return LiftResult::kReprojection;
  }
  const double cos_angle =
      std::abs((last_px - first_px).normalized().dot(direction));
  const double angle_deg =
      std::acos(std::min(1.0, cos_angle)) * 180.0 / M_PI;
  if (angle_deg > options.max_reprojection_angle_deg ||
      DistanceToLine2D(first_px, last_px, segment.start) >
          options.max_reprojection_distance_px ||
      DistanceToLine2D(first_px, last_px, segment.end) >
          options.max_reprojection_distance_px) {
    return LiftResult::kReprojection;
  }

  // 4. Endpoints.
  ViewLineSegment result;
  result.segment2D = segment;
  if (options.max_extrapolation >= 0.0) {
    // Clip the 2D segment to its LIDAR support plus the allowed
    // extrapolation: beyond it the back-projected endpoints rest on an
    // extrapolated 3D line, where a small tilt is a large error.
    const double lo = std::clamp(min_along, 0.0, length);
    const double hi = std::clamp(max_along, 0.0, length);
    const double margin = options.max_extrapolation * (hi - lo);
    const double clip_start = std::max(0.0, lo - margin);
    const double clip_end = std::min(length, hi + margin);
    result.segment2D.start = segment.start + clip_start * direction;
    result.segment2D.end = segment.start + clip_end * direction;
  }
  if (!BackProjectOntoLine(camera, result.segment2D.start, line,
                           options.min_ray_line_angle_deg,
                           &result.start3D_in_cam) ||
      !BackProjectOntoLine(camera, result.segment2D.end, line,
                           options.min_ray_line_angle_deg,
                           &result.end3D_in_cam) ||
      result.start3D_in_cam.norm() > options.max_endpoint_range ||
      result.end3D_in_cam.norm() > options.max_endpoint_range) {
    return LiftResult::kBackProjection;
  }
  std::vector<std::pair<int, Eigen::Vector3d>> inliers;
  inliers.reserve(ransac.inliers.size());
  for (const int position : ransac.inliers) {
    inliers.emplace_back(candidate_idxs[position], candidate_points[position]);
  }
  std::sort(inliers.begin(), inliers.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [idx, point] : inliers) {
    result.inlier_point_idxs.push_back(idx);
    result.inlier_points_in_cam.push_back(point);
  }

  // 5. Texture-only lines.
  if (options.texture.enabled) {
    const LineSurfaceType type = ClassifyLineSurface(
        result.start3D_in_cam, result.end3D_in_cam,
        NeighbourPoints(result, camera, projected, options.texture.radius),
        options.texture);
    if (surface != nullptr) {
      *surface = type;
    }
    if (!IsKeptSurfaceType(type, options.texture)) {
      return LiftResult::kTexture;
    }
  }
  *lifted = std::move(result);
  return LiftResult::kLifted;
}

std::vector<ViewLineSegment> LiftSegments(
    const std::vector<LineSegment2D>& segments, const Camera& camera,
    const ProjectedScan& projected, const std::vector<int>& edge_point_idxs,
    const EdgeAssociationOptions& options, std::vector<int>* counts,
    const RingNeighbors* ring_neighbors, std::vector<LineSegment2D>* not_lifted,
    std::vector<LiftResult>* results,
    std::vector<std::optional<LineSurfaceType>>* surfaces) {
  PixelGrid edge_grid(static_cast<int>(camera.width),
                      static_cast<int>(camera.height), 16);
  for (const int idx : edge_point_idxs) {
    if (projected.visible[idx]) {
      edge_grid.Insert(idx, projected.pixels[idx]);
    }
  }
  if (counts != nullptr) {
    counts->assign(static_cast<int>(LiftResult::kTexture) + 1, 0);
  }
  if (results != nullptr) {
    results->clear();
    results->reserve(segments.size());
  }
  if (surfaces != nullptr) {
    surfaces->clear();
    surfaces->reserve(segments.size());
  }
  std::vector<ViewLineSegment> lifted_segments;
  for (const LineSegment2D& segment : segments) {
    ViewLineSegment lifted;
    std::optional<LineSurfaceType> surface;
    const LiftResult result =
        LiftSegment(segment, camera, projected, edge_grid, options, &lifted,
                    ring_neighbors, &surface);
    if (surfaces != nullptr) {
      surfaces->push_back(surface);
    }
    if (counts != nullptr) {
      ++(*counts)[static_cast<int>(result)];
    }
    if (results != nullptr) {
      results->push_back(result);
    }
    if (result == LiftResult::kLifted) {
      lifted_segments.push_back(std::move(lifted));
    } else if (not_lifted != nullptr) {
      not_lifted->push_back(segment);
    }
  }
  return lifted_segments;
}

const char* LiftResultName(const LiftResult result) {
  switch (result) {
    case LiftResult::kLifted:
      return "lifted";
    case LiftResult::kTooFewPoints:
      return "too_few_points";
    case LiftResult::kRansacFailed:
      return "ransac_failed";
    case LiftResult::kLowCoverage:
      return "low_coverage";
    case LiftResult::kReprojection:
      return "reprojection";
    case LiftResult::kBackProjection:
      return "back_projection";
    case LiftResult::kTexture:
      return "texture";
  }
  return "unknown";
}

}  // namespace colmap_lidar
