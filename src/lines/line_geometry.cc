#include "src/lines/line_geometry.h"

#include <cmath>

#include <Eigen/Eigenvalues>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

Line3 FitLineLeastSquares(const std::vector<Eigen::Vector3d>& points,
                          const std::vector<int>& idxs) {
  const size_t count = idxs.empty() ? points.size() : idxs.size();
  THROW_CHECK(count >= 2, "FitLineLeastSquares: need at least two points");
  auto at = [&](size_t i) -> const Eigen::Vector3d& {
    return idxs.empty() ? points[i] : points[idxs[i]];
  };
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < count; ++i) {
    mean += at(i);
  }
  mean /= static_cast<double>(count);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d q = at(i) - mean;
    covariance += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  THROW_CHECK(solver.eigenvalues()(2) > 0.0,
              "FitLineLeastSquares: all points coincide");
  Line3 line;
  line.point = mean;
  line.direction = solver.eigenvectors().col(2).normalized();
  return line;
}

double DistanceToLine(const Line3& line, const Eigen::Vector3d& point) {
  return line.direction.cross(point - line.point).norm();
}

Eigen::Vector3d ViewingPlaneNormal(const Camera& camera,
                                   const Eigen::Vector2d& start,
                                   const Eigen::Vector2d& end) {
  const Eigen::Vector2d a = camera.CamFromImg(start);
  const Eigen::Vector2d b = camera.CamFromImg(end);
  return Eigen::Vector3d(a.x(), a.y(), 1.0)
      .cross(Eigen::Vector3d(b.x(), b.y(), 1.0))
      .normalized();
}

Line3 FitLineInPlane(const std::vector<Eigen::Vector3d>& points,
                     const std::vector<int>& idxs,
                     const Eigen::Vector3d& plane_normal) {
  std::vector<Eigen::Vector3d> projected;
  projected.reserve(idxs.size());
  for (const int idx : idxs) {
    projected.push_back(points[idx] -
                        plane_normal.dot(points[idx]) * plane_normal);
  }
  return FitLineLeastSquares(projected);
}

bool BackProjectOntoLine(const Camera& camera, const Eigen::Vector2d& pixel,
                         const Line3& line, const double min_angle_deg,
                         Eigen::Vector3d* point_in_cam) {
  const Eigen::Vector2d normalized = camera.CamFromImg(pixel);
  const Eigen::Vector3d ray =
      Eigen::Vector3d(normalized.x(), normalized.y(), 1.0).normalized();
  // Minimise |line.point + t d - s ray| over (t, s); both directions unit.
  const Eigen::Vector3d& d = line.direction;
  const double b = d.dot(ray);
  const double denominator = 1.0 - b * b;  // sin^2 of the angle
  const double min_sin = std::sin(min_angle_deg * M_PI / 180.0);
  if (denominator < min_sin * min_sin) {
    return false;
  }
  const Eigen::Vector3d& w0 = line.point;
  const double dd = d.dot(w0);
  const double e = ray.dot(w0);
  const double t = (b * e - dd) / denominator;
  *point_in_cam = line.point + t * d;
  return point_in_cam->z() > 0.0;
}

double DistanceToLine2D(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                        const Eigen::Vector2d& pixel) {
  const Eigen::Vector2d direction = (b - a).normalized();
  const Eigen::Vector2d offset = pixel - a;
  return std::abs(direction.x() * offset.y() - direction.y() * offset.x());
}

}  // namespace colmap_lidar
