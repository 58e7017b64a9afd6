#include "src/lines/texture_rejection.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// One side of the viewing plane: the angles about the line and the
// distances from it of its points.
struct Side {
  std::vector<double> angles;
  std::vector<double> distances;

  int Size() const { return static_cast<int>(angles.size()); }
};

double Median(std::vector<double> values) {
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  return values[mid];
}

// The face: the median angle; *residual = median distance to the face,
// *extent = farthest point from the line.
double FaceAngle(const Side& side, double* residual, double* extent) {
  const double angle = Median(side.angles);
  std::vector<double> residuals(side.angles.size());
  *extent = 0.0;
  for (size_t i = 0; i < side.angles.size(); ++i) {
    residuals[i] =
        side.distances[i] * std::abs(std::sin(side.angles[i] - angle));
    *extent = std::max(*extent, side.distances[i]);
  }
  *residual = Median(std::move(residuals));
  return angle;
}

}  // namespace

bool TextureRejectionOptions::Check() const {
  if (!(radius > 0.0) || !(exclusion_distance >= 0.0) ||
      !(exclusion_distance < radius)) {
    LOG(ERROR) << "LineExtraction.texture_radius must be > "
                  "texture_exclusion_distance >= 0";
    return false;
  }
  if (!(exclusion_noise_sigmas >= 0.0) || !(range_noise_m >= 0.0)) {
    LOG(ERROR) << "LineExtraction.texture_exclusion_noise_sigmas and the "
                  "range noise must be >= 0";
    return false;
  }
  if (min_open_space_points < 0) {
    LOG(ERROR) << "LineExtraction.texture_min_open_space_points must be >= 0";
    return false;
  }
  if (min_side_points < 3) {
    LOG(ERROR) << "LineExtraction.texture_min_side_points must be >= 3";
    return false;
  }
  if (!(min_normal_change_deg >= 0.0 && min_normal_change_deg <= 90.0)) {
    LOG(ERROR) << "LineExtraction.texture_min_normal_change_deg must be in "
                  "[0, 90]";
    return false;
  }
  if (!(max_face_residual > 0.0) || !(min_face_extent >= 0.0)) {
    LOG(ERROR) << "LineExtraction.texture_max_face_residual must be > 0 and "
                  "texture_min_face_extent >= 0";
    return false;
  }
  return true;
}

const char* LineSurfaceTypeName(const LineSurfaceType type) {
  switch (type) {
    case LineSurfaceType::kCrease:
      return "crease";
    case LineSurfaceType::kOcclusion:
      return "occlusion";
    case LineSurfaceType::kSilhouette:
      return "silhouette";
    case LineSurfaceType::kTexture:
      return "texture";
    case LineSurfaceType::kUnknown:
      return "unknown";
  }
  return "unknown";
}

bool IsKeptSurfaceType(const LineSurfaceType type,
                       const TextureRejectionOptions& options) {
  switch (type) {
    case LineSurfaceType::kCrease:
      return true;
    case LineSurfaceType::kOcclusion:
      return options.keep_occlusions;
    case LineSurfaceType::kUnknown:
      return options.keep_unknown;
    case LineSurfaceType::kSilhouette:
    case LineSurfaceType::kTexture:
      return false;
  }
  return false;
}

LineSurfaceType ClassifyLineSurface(const Eigen::Vector3d& start,
                                    const Eigen::Vector3d& end,
                                    const std::vector<Eigen::Vector3d>& points,
                                    const TextureRejectionOptions& options) {
  const double length = (end - start).norm();
  Eigen::Vector3d plane_normal = start.cross(end);
  if (length < 1e-9 || plane_normal.norm() < 1e-12) {
    return LineSurfaceType::kUnknown;
  }
  const Eigen::Vector3d direction = (end - start) / length;
  plane_normal.normalize();
  // In the plane perpendicular to the line: `plane_normal` (across the
  // viewing plane) and `away` (within the viewing plane, pointing away from
  // the camera). Angle 0 is a face hidden behind the line along the viewing
  // rays, pi a face coming towards the camera.
  Eigen::Vector3d away = direction.cross(plane_normal);
  if (away.dot(start + end) < 0.0) {
    away = -away;
  }
  const double exclusion =
      std::max(options.exclusion_distance,
               std::min(options.exclusion_noise_sigmas * options.range_noise_m,
                        0.25 * options.radius));
  Side sides[2];
  // The points beyond the radius whose rays cross the band (the plane
  // through the line normal to `away`, within the radius) at the line.
  std::vector<Eigen::Vector3d> passing[2];
  const double line_depth = away.dot(start);  // the same for `end`
  for (const Eigen::Vector3d& point : points) {
    const Eigen::Vector3d offset = point - start;
    const double t = direction.dot(offset);
    const Eigen::Vector3d perpendicular = offset - t * direction;
    const double distance = perpendicular.norm();
    if (distance > options.radius) {
      const double point_depth = away.dot(point);
      if (line_depth > 0.0 && point_depth > line_depth) {
        const Eigen::Vector3d crossing = point * (line_depth / point_depth);
        const double crossing_t = direction.dot(crossing - start);
        const double across = plane_normal.dot(crossing);
        if (crossing_t >= 0.0 && crossing_t <= length &&
            std::abs(across) >= exclusion &&
            std::abs(across) <= options.radius) {
          passing[across > 0.0 ? 0 : 1].push_back(point);
        }
      }
      continue;
    }
    if (t < 0.0 || t > length || distance < exclusion) {
      continue;
    }
    const double across = plane_normal.dot(perpendicular);
    Side& side = sides[across > 0.0 ? 0 : 1];
    side.angles.push_back(std::atan2(across, away.dot(perpendicular)));
    side.distances.push_back(distance);
  }
  const bool has_face[2] = {sides[0].Size() >= options.min_side_points,
                            sides[1].Size() >= options.min_side_points};
  double residuals[2] = {0.0, 0.0};
  double extents[2] = {0.0, 0.0};
  double angles[2] = {0.0, 0.0};
  for (int side = 0; side < 2; ++side) {
    if (has_face[side]) {
      angles[side] = FaceAngle(sides[side], &residuals[side], &extents[side]);
    }
  }
  if (has_face[0] && has_face[1]) {
    // angles[0] in (0, pi), angles[1] in (-pi, 0): the faces are coplanar
    // when they differ by pi.
    const double between = angles[0] - angles[1];  // (0, 2 pi)
    const double normal_change_deg =
        std::abs(M_PI - between) * 180.0 / M_PI;
    return normal_change_deg >= options.min_normal_change_deg
               ? LineSurfaceType::kCrease
               : LineSurfaceType::kTexture;
  }
  if (has_face[0] != has_face[1]) {
    const int face = has_face[0] ? 0 : 1;
    if (residuals[face] > options.max_face_residual ||
        extents[face] < options.min_face_extent) {
      return LineSurfaceType::kSilhouette;
    }
    if (options.min_open_space_points == 0) {
      return LineSurfaceType::kOcclusion;
    }
    // The face's plane: through the line, towards angles[face] about it.
    const Eigen::Vector3d into_face =
        std::cos(angles[face]) * away + std::sin(angles[face]) * plane_normal;
    const Eigen::Vector3d face_normal = direction.cross(into_face).normalized();
    // The camera's side of the plane: negative offsets lie behind it.
    const double camera_sign = face_normal.dot(-start) >= 0.0 ? 1.0 : -1.0;
    // On the plane within the noise the face's points show, at least the
    // exclusion distance (the points nearer the line belong to no side).
    const double tolerance = std::max(3.0 * residuals[face], exclusion);
    int num_behind = 0;
    int num_on_face = 0;
    for (const Eigen::Vector3d& point : passing[1 - face]) {
      const double offset = camera_sign * face_normal.dot(point - start);
      if (offset < -tolerance) {
        ++num_behind;
      } else if (offset <= tolerance) {
        ++num_on_face;
      }
    }
    if (num_behind >= options.min_open_space_points &&
        num_behind >= num_on_face) {
      return LineSurfaceType::kOcclusion;
    }
    if (num_on_face >= options.min_open_space_points) {
      return LineSurfaceType::kTexture;
    }
    return LineSurfaceType::kUnknown;
  }
  return LineSurfaceType::kUnknown;
}

}  // namespace colmap_lidar
