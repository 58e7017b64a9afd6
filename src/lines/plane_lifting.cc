#include "src/lines/plane_lifting.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>

#include "colmap_ext/util/logging.h"
#include "src/lines/line_geometry.h"

namespace colmap_lidar {
namespace {

constexpr double kPi = 3.14159265358979323846;
// An empty side is open space only this far inside the LIDAR's elevation
// limits, degrees (about a ring spacing of a 32-ring unit).
constexpr double kOpenSpaceElevationMarginDeg = 1.5;

// n . x + d = 0, |n| = 1.
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double d = 0.0;
  double Distance(const Eigen::Vector3d& point) const {
    return std::abs(normal.dot(point) + d);
  }
  // Depth (z) where the ray through `ray` (z = 1) meets the plane; false
  // when the ray is within min_angle_rad of the plane or it is met behind
  // the camera.
  bool DepthAlong(const Eigen::Vector3d& ray, double min_angle_rad,
                  double* depth) const {
    const double denominator = normal.dot(ray);
    if (std::abs(denominator) / ray.norm() < std::sin(min_angle_rad)) {
      return false;
    }
    *depth = -d / denominator;
    return *depth > 0.0;
  }
};

struct SideBand {
  std::vector<Eigen::Vector3d> points;
  // Position of each point along the segment, pixels from its start.
  std::vector<double> along;
};

struct SidePlane {
  Plane plane;
  // Along-segment stretch of the inliers, pixels, clamped to the segment.
  double lo = 0.0;
  double hi = 0.0;
};

// PCA plane of points[idxs]; eigenvalues ascending in *eigenvalues.
Plane FitPlanePca(const std::vector<Eigen::Vector3d>& points,
                  const std::vector<int>& idxs, Eigen::Vector3d* eigenvalues) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const int i : idxs) {
    mean += points[i];
  }
  mean /= static_cast<double>(idxs.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const int i : idxs) {
    const Eigen::Vector3d offset = points[i] - mean;
    covariance += offset * offset.transpose();
  }
  covariance /= static_cast<double>(idxs.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Plane plane;
  plane.normal = solver.eigenvectors().col(0).normalized();
  plane.d = -plane.normal.dot(mean);
  *eigenvalues = solver.eigenvalues();
  return plane;
}

// RANSAC over point triples (seeded: the same input gives the same plane),
// then PCA on the inliers. False when no plane has enough, spread inliers.
bool FitSidePlane(const SideBand& band, double inlier_distance,
                  double min_spread_m, int min_points, double length,
                  SidePlane* side) {
  const int n = static_cast<int>(band.points.size());
  if (n < min_points) {
    return false;
  }
  std::mt19937 rng(static_cast<uint32_t>(n) * 2654435761u);
  std::uniform_int_distribution<int> pick(0, n - 1);
  int best_count = 0;
  Plane best;
  const int num_iterations = std::min(100, n * (n - 1) * (n - 2) / 6);
  for (int iteration = 0; iteration < num_iterations; ++iteration) {
    const int a = pick(rng);
    const int b = pick(rng);
    const int c = pick(rng);
    const Eigen::Vector3d normal =
        (band.points[b] - band.points[a]).cross(band.points[c] - band.points[a]);
    if (normal.norm() < 1e-9) {
      continue;
    }
    Plane plane;
    plane.normal = normal.normalized();
    plane.d = -plane.normal.dot(band.points[a]);
    int count = 0;
    for (const Eigen::Vector3d& point : band.points) {
      count += plane.Distance(point) <= inlier_distance ? 1 : 0;
    }
    if (count > best_count) {
      best_count = count;
      best = plane;
    }
  }
  if (best_count < min_points) {
    return false;
  }
  std::vector<int> inliers;
  for (int i = 0; i < n; ++i) {
    if (best.Distance(band.points[i]) <= inlier_distance) {
      inliers.push_back(i);
    }
  }
  Eigen::Vector3d eigenvalues;
  const Plane refined = FitPlanePca(band.points, inliers, &eigenvalues);
  // The two in-plane spreads: a ring alone (nearly a line) fixes no plane.
  if (std::sqrt(std::max(0.0, eigenvalues(1))) < min_spread_m) {
    return false;
  }
  side->plane = refined;
  side->lo = length;
  side->hi = 0.0;
  int num_kept = 0;
  for (const int i : inliers) {
    if (refined.Distance(band.points[i]) <= inlier_distance) {
      side->lo = std::min(side->lo, std::clamp(band.along[i], 0.0, length));
      side->hi = std::max(side->hi, std::clamp(band.along[i], 0.0, length));
      ++num_kept;
    }
  }
  return num_kept >= min_points;
}

// Whether the LIDAR points within `width` pixels of the segment agree that
// the near plane ends there: on the near side they lie on the near plane
// (or in front of it), on the far side behind it by more than min_step_m;
// at most max_violations of the points that take a side may disagree, and
// each side needs one point that agrees (an empty far side is open space,
// decided by the caller). candidates: (distance, index) per side, sorted.
// *near_points receives the near side's points that agree, with their
// distances from the segment (pixels), nearest first.
bool LocalStepAtSegment(
    const std::array<std::vector<std::pair<double, int>>, 2>& candidates,
    const ProjectedScan& projected, const Plane& near_plane, int near_side,
    double width, double inlier_distance, double min_step_m,
    double min_ray_angle_rad, double max_violations,
    std::vector<std::pair<double, Eigen::Vector3d>>* near_points) {
  near_points->clear();
  int num_agree[2] = {0, 0};
  int num_disagree[2] = {0, 0};
  for (int s = 0; s < 2; ++s) {
    for (const auto& [distance, idx] : candidates[s]) {
      if (distance > width) break;
      const Eigen::Vector3d& point = projected.points_in_cam[idx];
      double depth = 0.0;
      // Signed: > 0 when the point lies behind the near plane.
      const double behind =
          near_plane.DepthAlong(point / point.z(), min_ray_angle_rad, &depth)
              ? point.z() - depth
              : 1e9;
      const bool on_plane = near_plane.Distance(point) <= inlier_distance;
      if (s == near_side) {
        if (behind > min_step_m) {
          ++num_disagree[s];
        } else if (on_plane || behind < 0.0) {
          ++num_agree[s];
          near_points->emplace_back(distance, point);
        }
      } else {
        if (on_plane) {
          ++num_disagree[s];
        } else if (behind > min_step_m) {
          ++num_agree[s];
        }
      }
    }
  }
  for (int s = 0; s < 2; ++s) {
    const int total = num_agree[s] + num_disagree[s];
    if (total == 0) {
      if (s == near_side) return false;
      continue;  // Open space on the far side.
    }
    if (num_agree[s] == 0 ||
        static_cast<double>(num_disagree[s]) > max_violations * total) {
      return false;
    }
  }
  return true;
}

Eigen::Vector3d Ray(const Camera& camera, const Eigen::Vector2d& pixel) {
  return camera.CamFromImg(pixel).homogeneous();
}

// The segment's 2D endpoints with their 3D endpoints, to set them in turn.
std::array<std::pair<Eigen::Vector2d, Eigen::Vector3d*>, 2> EndpointsOf(
    ViewLineSegment* segment) {
  return {std::make_pair(segment->segment2D.start, &segment->start3D_in_cam),
          std::make_pair(segment->segment2D.end, &segment->end3D_in_cam)};
}

}  // namespace

bool PlaneLiftingOptions::Check() const {
  if (!(band_gap_px >= 0.0) || !(max_band_fraction > 0.0) ||
      !(max_band_fraction <= 0.5)) {
    LOG(ERROR) << "LineExtraction.plane_band_gap_px must be >= 0 and "
                  "plane_max_band_fraction in (0, 0.5]";
    return false;
  }
  if (min_side_points < 3 || max_side_points < min_side_points) {
    LOG(ERROR) << "LineExtraction.plane_min_side_points must be >= 3 and <= "
                  "plane_max_side_points";
    return false;
  }
  if (!(range_noise_m >= 0.0) || !(min_plane_spread >= 0.0) ||
      !(min_step_sigmas > 0.0)) {
    LOG(ERROR) << "LineExtraction.plane_range_noise_m and "
                  "plane_min_plane_spread must be >= 0, plane_min_step_sigmas "
                  "> 0";
    return false;
  }
  if (!(min_crease_angle_deg > 0.0 && min_crease_angle_deg <= 90.0)) {
    LOG(ERROR) << "LineExtraction.plane_min_crease_angle_deg must be in (0, 90]";
    return false;
  }
  if (!(boundary_band_fraction > 0.0 && boundary_band_fraction <= 1.0) ||
      !(max_boundary_violations >= 0.0 && max_boundary_violations < 1.0)) {
    LOG(ERROR) << "LineExtraction.plane_boundary_band_fraction must be in "
                  "(0, 1] and plane_max_boundary_violations in [0, 1)";
    return false;
  }
  if (!(min_coverage >= 0.0 && min_coverage <= 1.0)) {
    LOG(ERROR) << "LineExtraction.plane_min_coverage must be in [0, 1]";
    return false;
  }
  return true;
}

PlaneLiftResult LiftSegmentByPlanes(const LineSegment2D& segment,
                                    const Camera& camera,
                                    const ProjectedScan& projected,
                                    const PlaneLiftingOptions& options,
                                    const double range_noise_m,
                                    const double max_reprojection_angle_deg,
                                    const double max_reprojection_distance_px,
                                    const double min_ray_line_angle_deg,
                                    ViewLineSegment* lifted) {
  const double length = segment.Length();
  if (!(length > 1.0)) {
    return PlaneLiftResult::kNoPlanes;
  }
  const Eigen::Vector2d direction = segment.Direction();
  const Eigen::Vector2d normal(-direction.y(), direction.x());
  const double max_band_px =
      options.max_band_fraction *
      std::hypot(static_cast<double>(camera.width),
                 static_cast<double>(camera.height));
  const double sigma = std::max(range_noise_m, 0.004);
  const double inlier_distance = std::max(0.01, 2.5 * sigma);
  const double min_spread_m = options.min_plane_spread * sigma;
  const double min_step_m = std::max(0.04, options.min_step_sigmas * sigma);
  const double min_ray_angle_rad = min_ray_line_angle_deg * kPi / 180.0;

  // 1. Candidates: (perpendicular distance, index) per side.
  std::array<std::vector<std::pair<double, int>>, 2> candidates;
  const Eigen::Vector2d box_min =
      segment.start.cwiseMin(segment.end).array() - max_band_px;
  const Eigen::Vector2d box_max =
      segment.start.cwiseMax(segment.end).array() + max_band_px;
  projected.visible_grid.VisitBox(box_min, box_max, [&](int idx) {
    const Eigen::Vector2d offset = projected.pixels[idx] - segment.start;
    const double along = offset.dot(direction);
    const double across = offset.dot(normal);
    if (along < 0.0 || along > length || std::abs(across) < options.band_gap_px ||
        std::abs(across) > max_band_px) {
      return;
    }
    candidates[across > 0.0 ? 1 : 0].emplace_back(std::abs(across), idx);
  });
  // 2. A plane per side, from the narrowest band that holds one: the band
  // widens (an eighth, a quarter, half, all of max_band_px) until its points
  // span more than one ring, so that the plane is the surface next to the
  // segment rather than one farther out. At most max_side_points points per
  // band, spread evenly over it.
  std::array<SideBand, 2> bands;
  std::array<SidePlane, 2> sides;
  std::array<bool, 2> has_plane = {false, false};
  for (int s = 0; s < 2; ++s) {
    std::sort(candidates[s].begin(), candidates[s].end());
    for (const double fraction : {0.125, 0.25, 0.5, 1.0}) {
      const double width = fraction * max_band_px;
      const size_t num_within = static_cast<size_t>(
          std::upper_bound(candidates[s].begin(), candidates[s].end(),
                           std::make_pair(width, -1),
                           [](const std::pair<double, int>& a,
                              const std::pair<double, int>& b) {
                             return a.first < b.first;
                           }) -
          candidates[s].begin());
      if (static_cast<int>(num_within) < options.min_side_points) {
        continue;
      }
      const double stride =
          std::max(1.0, static_cast<double>(num_within) /
                            static_cast<double>(options.max_side_points));
      bands[s] = SideBand();
      for (double k = 0.0; k < static_cast<double>(num_within); k += stride) {
        const int idx = candidates[s][static_cast<size_t>(k)].second;
        bands[s].points.push_back(projected.points_in_cam[idx]);
        bands[s].along.push_back(
            (projected.pixels[idx] - segment.start).dot(direction));
      }
      has_plane[s] = FitSidePlane(bands[s], inlier_distance, min_spread_m,
                                  options.min_side_points, length, &sides[s]);
      if (has_plane[s]) {
        break;
      }
    }
  }
  VLOG(3) << "plane lifting " << segment.start.transpose() << " -> "
          << segment.end.transpose() << ": bands " << bands[0].points.size()
          << " / " << bands[1].points.size() << " points, planes "
          << has_plane[0] << " / " << has_plane[1];
  if (!has_plane[0] && !has_plane[1]) {
    return PlaneLiftResult::kNoPlanes;
  }

  // 3. What the sides make of the segment.
  int near_side = -1;  // an occluding / step edge on this side's plane
  // The cut with the near plane is scaled by this (snap_to_near_points).
  double near_depth_scale = 1.0;
  bool crease = false;
  double lo = 0.0;
  double hi = length;
  if (has_plane[0] && has_plane[1]) {
    lo = std::max(sides[0].lo, sides[1].lo);
    hi = std::min(sides[0].hi, sides[1].hi);
    if (hi - lo < options.min_coverage * length) {
      return PlaneLiftResult::kLowCoverage;
    }
    // Depths of both planes along the rays at the ends and the middle of
    // the supported stretch: equal where the surfaces meet at the segment.
    int num_side0_nearer = 0;
    int num_side1_nearer = 0;
    int num_meeting = 0;
    for (const double t : {lo, 0.5 * (lo + hi), hi}) {
      const Eigen::Vector3d ray = Ray(camera, segment.start + t * direction);
      double depth0 = 0.0;
      double depth1 = 0.0;
      const bool ok0 =
          sides[0].plane.DepthAlong(ray, min_ray_angle_rad, &depth0);
      const bool ok1 =
          sides[1].plane.DepthAlong(ray, min_ray_angle_rad, &depth1);
      if (!ok0 || !ok1) {
        // A plane seen edge-on: its depth along the ray is ill-defined.
        return PlaneLiftResult::kBackProjection;
      }
      // Depths are along the optical axis; the step is along the ray.
      const double step = (depth1 - depth0) * ray.norm();
      if (step > min_step_m) {
        ++num_side0_nearer;
      } else if (-step > min_step_m) {
        ++num_side1_nearer;
      } else {
        ++num_meeting;
      }
    }
    const double cos_angle =
        std::abs(sides[0].plane.normal.dot(sides[1].plane.normal));
    const double angle_deg = std::acos(std::min(1.0, cos_angle)) * 180.0 / kPi;
    if (num_meeting == 3) {
      if (angle_deg < options.min_crease_angle_deg) {
        return PlaneLiftResult::kTexture;
      }
      crease = true;
    } else if (num_side0_nearer == 3 || num_side1_nearer == 3) {
      near_side = num_side0_nearer == 3 ? 0 : 1;
    } else if (angle_deg >= options.min_crease_angle_deg && num_meeting >= 1) {
      // The faces meet along part of the stretch (a slightly tilted fit):
      // the intersection decides, through the reprojection check.
      crease = true;
    } else {
      return PlaneLiftResult::kReprojection;
    }
  } else {
    // One plane: an occluding edge when the other side's points lie
    // clearly behind it along their own rays.
    const int s = has_plane[0] ? 0 : 1;
    const SideBand& other = bands[1 - s];
    if (static_cast<int>(other.points.size()) < options.min_side_points) {
      // An (almost) empty side is open space (sky, or beyond the LIDAR's
      // range) when the LIDAR scanned its direction; outside the LIDAR's
      // vertical field nothing is known.
      const Eigen::Vector2d probe =
          0.5 * (segment.start + segment.end) +
          (s == 0 ? 1.0 : -1.0) * 0.5 * max_band_px * normal;
      if (candidates[1 - s].size() <= 2 && options.keep_occlusions &&
          probe.x() >= 0.0 && probe.y() >= 0.0 &&
          probe.x() < static_cast<double>(camera.width) &&
          probe.y() < static_cast<double>(camera.height) &&
          WithinLidarElevation(projected, Ray(camera, probe),
                               kOpenSpaceElevationMarginDeg * kPi / 180.0)) {
        near_side = s;
      } else {
        return PlaneLiftResult::kNoPlanes;
      }
    }
  }
  if (near_side < 0 && !(has_plane[0] && has_plane[1])) {
    const int s = has_plane[0] ? 0 : 1;
    const SideBand& other = bands[1 - s];
    std::vector<double> excess;
    excess.reserve(other.points.size());
    for (const Eigen::Vector3d& point : other.points) {
      double depth = 0.0;
      if (!sides[s].plane.DepthAlong(point / point.z(), min_ray_angle_rad,
                                     &depth)) {
        excess.push_back(1e9);  // the plane does not reach the ray: behind it
      } else {
        excess.push_back(point.z() - depth);
      }
    }
    std::nth_element(excess.begin(), excess.begin() + excess.size() / 4,
                     excess.end());
    // The lower quartile: most of the other side lies behind the plane.
    if (!(excess[excess.size() / 4] > min_step_m)) {
      return excess[excess.size() / 4] < -min_step_m
                 ? PlaneLiftResult::kNoPlanes
                 : PlaneLiftResult::kTexture;
    }
    near_side = s;
  }
  if (near_side >= 0) {
    if (!options.keep_occlusions) {
      return PlaneLiftResult::kNoPlanes;
    }
    lo = sides[near_side].lo;
    hi = sides[near_side].hi;
    // The far side must not continue the near plane (a texture line on the
    // near surface in front of a step a few pixels away).
    const SideBand& far = bands[1 - near_side];
    int num_on_near_plane = 0;
    for (const Eigen::Vector3d& point : far.points) {
      num_on_near_plane +=
          sides[near_side].plane.Distance(point) <= inlier_distance ? 1 : 0;
    }
    if (!far.points.empty() && num_on_near_plane * 5 > static_cast<int>(far.points.size())) {
      return PlaneLiftResult::kTexture;
    }
    // The step lies at the segment, not a few pixels beside it: next to the
    // segment (within boundary_band_fraction of max_band_px, past the gap),
    // the near plane must not continue on the far side and the far surface
    // must not show on the near side. Without this test a brick joint or a
    // shadow line a few pixels from a window recess's lip was lifted onto
    // the wall as if it were the lip (street_bent: 284 of 362 occluding
    // edges more than 5 cm from any crease).
    std::vector<std::pair<double, Eigen::Vector3d>> near_points;
    if (!LocalStepAtSegment(candidates, projected, sides[near_side].plane,
                            near_side, options.boundary_band_fraction *
                                           max_band_px,
                            inlier_distance, min_step_m, min_ray_angle_rad,
                            options.max_boundary_violations, &near_points)) {
      return PlaneLiftResult::kBoundary;
    }
    // The edge lies where the near surface meets the step, which is not
    // always on the band's plane: a window frame 10 cm proud of an oblique
    // wall is too narrow to hold a plane of its own, and the wall's plane
    // put the cut 10-20 cm behind it (street_bent). The near side's points
    // right next to the segment (within twice the band gap, the LIDAR's
    // last returns before the step) set the depth: the median ratio of
    // their depths to the plane's along their rays scales the cut.
    if (options.snap_to_near_points) {
      std::vector<double> ratios;
      for (const auto& [distance, point] : near_points) {
        if (distance > 2.0 * std::max(options.band_gap_px, 1.0)) break;
        double depth = 0.0;
        if (sides[near_side].plane.DepthAlong(point / point.z(),
                                              min_ray_angle_rad, &depth)) {
          ratios.push_back(point.z() / depth);
        }
      }
      if (ratios.size() >= 3) {
        std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2,
                         ratios.end());
        near_depth_scale = ratios[ratios.size() / 2];
      }
    }
  }
  if (hi - lo < options.min_coverage * length) {
    return PlaneLiftResult::kLowCoverage;
  }

  // 4. The 3D line and the endpoints of the supported stretch.
  ViewLineSegment result;
  result.segment2D.start = segment.start + lo * direction;
  result.segment2D.end = segment.start + hi * direction;
  if (crease) {
    const Eigen::Vector3d& n0 = sides[0].plane.normal;
    const Eigen::Vector3d& n1 = sides[1].plane.normal;
    Line3 line;
    line.direction = n0.cross(n1).normalized();
    Eigen::Matrix3d system;
    system.row(0) = n0.transpose();
    system.row(1) = n1.transpose();
    system.row(2) = line.direction.transpose();
    line.point = system.colPivHouseholderQr().solve(
        Eigen::Vector3d(-sides[0].plane.d, -sides[1].plane.d, 0.0));
    if (!BackProjectOntoLine(camera, result.segment2D.start, line,
                             min_ray_line_angle_deg, &result.start3D_in_cam) ||
        !BackProjectOntoLine(camera, result.segment2D.end, line,
                             min_ray_line_angle_deg, &result.end3D_in_cam)) {
      return PlaneLiftResult::kBackProjection;
    }
    // Reprojection of the intersection against the 2D segment.
    const Eigen::Vector2d first_px = camera.ImgFromCam(result.start3D_in_cam);
    const Eigen::Vector2d last_px = camera.ImgFromCam(result.end3D_in_cam);
    if ((last_px - first_px).norm() < 1.0) {
      return PlaneLiftResult::kReprojection;
    }
    const double cos_angle =
        std::abs((last_px - first_px).normalized().dot(direction));
    if (std::acos(std::min(1.0, cos_angle)) * 180.0 / kPi >
            max_reprojection_angle_deg ||
        DistanceToLine2D(first_px, last_px, result.segment2D.start) >
            max_reprojection_distance_px ||
        DistanceToLine2D(first_px, last_px, result.segment2D.end) >
            max_reprojection_distance_px) {
      return PlaneLiftResult::kReprojection;
    }
    // Then the endpoints on their rays (the image fixes the line's viewing
    // plane more precisely than the two fitted planes do), as the edge
    // points' line is fitted within that plane.
    for (const auto& [pixel, point] : EndpointsOf(&result)) {
      const Eigen::Vector3d ray = Ray(camera, pixel);
      *point = ray * (ray.dot(*point) / ray.squaredNorm());
    }
  } else {
    // The rays of the endpoints cut with the nearer plane.
    const Plane& plane = sides[near_side].plane;
    for (const auto& [pixel, point] : EndpointsOf(&result)) {
      const Eigen::Vector3d ray = Ray(camera, pixel);
      double depth = 0.0;
      if (!plane.DepthAlong(ray, min_ray_angle_rad, &depth)) {
        return PlaneLiftResult::kBackProjection;
      }
      *point = near_depth_scale * depth * ray;
    }
  }
  if ((result.end3D_in_cam - result.start3D_in_cam).norm() < 1e-3) {
    return PlaneLiftResult::kBackProjection;
  }
  *lifted = std::move(result);
  return crease ? PlaneLiftResult::kCrease : PlaneLiftResult::kOcclusion;
}

const char* PlaneLiftResultName(const PlaneLiftResult result) {
  switch (result) {
    case PlaneLiftResult::kCrease:
      return "crease";
    case PlaneLiftResult::kOcclusion:
      return "occlusion";
    case PlaneLiftResult::kNoPlanes:
      return "no_planes";
    case PlaneLiftResult::kTexture:
      return "texture";
    case PlaneLiftResult::kReprojection:
      return "reprojection";
    case PlaneLiftResult::kLowCoverage:
      return "low_coverage";
    case PlaneLiftResult::kBackProjection:
      return "back_projection";
    case PlaneLiftResult::kBoundary:
      return "boundary";
    case PlaneLiftResult::kOutOfRange:
      return "out_of_range";
    case PlaneLiftResult::kNotTried:
      return "not_tried";
  }
  return "unknown";
}

}  // namespace colmap_lidar
