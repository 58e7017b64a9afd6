#include "src/lines/texture_rejection.h"

#include <cmath>

#include <Eigen/Eigenvalues>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Accumulates points for a PCA plane fit.
struct PlaneAccumulator {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum2 = Eigen::Matrix3d::Zero();
  int count = 0;

  void Add(const Eigen::Vector3d& point) {
    sum += point;
    sum2 += point * point.transpose();
    ++count;
  }

  // False when the points are (nearly) collinear, i.e. no plane.
  bool Normal(Eigen::Vector3d* normal) const {
    const Eigen::Vector3d mean = sum / count;
    const Eigen::Matrix3d covariance =
        sum2 / count - mean * mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
    const Eigen::Vector3d eigenvalues = solver.eigenvalues();
    // The second spread must be at least 1 cm for a plane to be defined.
    if (eigenvalues(1) < 1e-4) {
      return false;
    }
    *normal = solver.eigenvectors().col(0);
    return true;
  }
};

}  // namespace

bool TextureRejectionOptions::Check() const {
  if (!(radius > 0.0) || !(exclusion_distance >= 0.0) ||
      !(exclusion_distance < radius)) {
    LOG(ERROR) << "LineExtraction.texture_radius must be > "
                  "texture_exclusion_distance >= 0";
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
  return true;
}

LineSurfaceType ClassifyLineSurface(const Eigen::Vector3d& start,
                                    const Eigen::Vector3d& end,
                                    const std::vector<Eigen::Vector3d>& points,
                                    const TextureRejectionOptions& options) {
  const Eigen::Vector3d direction = (end - start).normalized();
  const double length = (end - start).norm();
  Eigen::Vector3d plane_normal = start.cross(end);
  if (plane_normal.norm() < 1e-12) {
    return LineSurfaceType::kUnknown;
  }
  plane_normal.normalize();
  PlaneAccumulator sides[2];
  const double radius2 = options.radius * options.radius;
  const double exclusion2 =
      options.exclusion_distance * options.exclusion_distance;
  for (const Eigen::Vector3d& point : points) {
    const Eigen::Vector3d offset = point - start;
    const double t = direction.dot(offset);
    if (t < 0.0 || t > length) {
      continue;
    }
    const double distance2 = (offset - t * direction).squaredNorm();
    if (distance2 > radius2 || distance2 < exclusion2) {
      continue;
    }
    sides[plane_normal.dot(offset) > 0.0 ? 0 : 1].Add(point);
  }
  Eigen::Vector3d normals[2];
  bool has_plane[2];
  for (int side = 0; side < 2; ++side) {
    has_plane[side] = sides[side].count >= options.min_side_points &&
                      sides[side].Normal(&normals[side]);
  }
  if (has_plane[0] && has_plane[1]) {
    const double cos_angle = std::min(1.0, std::abs(normals[0].dot(normals[1])));
    const double angle_deg = std::acos(cos_angle) * 180.0 / M_PI;
    return angle_deg >= options.min_normal_change_deg
               ? LineSurfaceType::kCrease
               : LineSurfaceType::kTexture;
  }
  if (has_plane[0] != has_plane[1]) {
    const int empty_side = has_plane[0] ? 1 : 0;
    if (sides[empty_side].count < options.min_side_points) {
      return LineSurfaceType::kOcclusion;
    }
  }
  return LineSurfaceType::kUnknown;
}

}  // namespace colmap_lidar
