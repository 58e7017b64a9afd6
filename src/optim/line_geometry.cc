#include "src/optim/line_geometry.h"

#include <cmath>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Any unit vector orthogonal to the unit vector v.
Eigen::Vector3d AnyOrthogonalUnitVector(const Eigen::Vector3d& v) {
  // Cross with the axis least aligned with v for a well-conditioned result.
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  int min_index = 0;
  v.cwiseAbs().minCoeff(&min_index);
  axis[min_index] = 1.0;
  return v.cross(axis).normalized();
}

// Focal lengths and principal point of any model (shared focal for the
// SIMPLE_* models).
void FocalAndPrincipalPoint(const Camera& camera, double* fx, double* fy,
                            double* cx, double* cy) {
  const std::vector<size_t> focal_idxs =
      CameraModelFocalLengthIdxs(camera.model_id);
  const std::vector<size_t> pp_idxs =
      CameraModelPrincipalPointIdxs(camera.model_id);
  THROW_CHECK(!focal_idxs.empty() && pp_idxs.size() == 2,
              "Camera " << camera.camera_id << " has an unknown model");
  *fx = camera.params.at(focal_idxs[0]);
  *fy = camera.params.at(focal_idxs.size() > 1 ? focal_idxs[1] : focal_idxs[0]);
  *cx = camera.params.at(pp_idxs[0]);
  *cy = camera.params.at(pp_idxs[1]);
}

}  // namespace

Vector6d PluckerFromPoints(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return PluckerFromPointAndDirection(a, b - a);
}

Vector6d PluckerFromPointAndDirection(const Eigen::Vector3d& point,
                                      const Eigen::Vector3d& direction) {
  Vector6d plucker;
  plucker << direction, point.cross(direction);
  return plucker;
}

Vector6d NormalizePlucker(const Vector6d& plucker) {
  const Eigen::Vector3d d = plucker.head<3>();
  const double norm = d.norm();
  THROW_CHECK(std::isfinite(norm) && norm > 0.0,
              "Pluecker vector with zero or invalid direction: "
                  << plucker.transpose());
  const Eigen::Vector3d unit_d = d / norm;
  Eigen::Vector3d m = plucker.tail<3>() / norm;
  m -= m.dot(unit_d) * unit_d;
  Vector6d normalized;
  normalized << unit_d, m;
  return normalized;
}

Vector6d PluckerToOrthonormal(const Vector6d& plucker) {
  const Vector6d normalized = NormalizePlucker(plucker);
  const Eigen::Vector3d u2 = normalized.head<3>();
  const Eigen::Vector3d m = normalized.tail<3>();
  const double distance = m.norm();
  // Below this the moment's direction is numerically meaningless.
  constexpr double kMinMomentNorm = 1e-12;
  const Eigen::Vector3d u1 =
      distance > kMinMomentNorm ? Eigen::Vector3d(m / distance)
                                : AnyOrthogonalUnitVector(u2);
  Eigen::Matrix3d u;
  u.col(0) = u1;
  u.col(1) = u2;
  u.col(2) = u1.cross(u2);
  const Eigen::Quaterniond rotation = Eigen::Quaterniond(u).normalized();
  // (w1, w2) ~ (|m|, |d|) with |d| = 1.
  const double scale = std::hypot(distance, 1.0);
  Vector6d orthonormal;
  orthonormal << rotation.coeffs(), distance / scale, 1.0 / scale;
  return orthonormal;
}

Vector6d OrthonormalToPlucker(const Vector6d& orthonormal) {
  Eigen::Vector3d d, m;
  const Eigen::Quaterniond rotation =
      Eigen::Quaterniond(orthonormal.data() + kLineQuaternionOffset)
          .normalized();
  Vector6d unit = orthonormal;
  unit.head<4>() = rotation.coeffs();
  OrthonormalToPluckerUnnormalized(unit.data(), d.data(), m.data());
  THROW_CHECK(std::abs(orthonormal[kLineWOffset + 1]) > 0.0,
              "Orthonormal line at infinity (w2 = 0): "
                  << orthonormal.transpose());
  Vector6d plucker;
  plucker << d, m;
  return NormalizePlucker(plucker);
}

Vector6d TransformPlucker(const Rigid3d& b_from_a,
                          const Vector6d& plucker_in_a) {
  const Eigen::Matrix3d rotation = b_from_a.rotation.toRotationMatrix();
  const Eigen::Vector3d d_in_b = rotation * plucker_in_a.head<3>();
  Vector6d plucker_in_b;
  plucker_in_b << d_in_b, rotation * plucker_in_a.tail<3>() +
                              b_from_a.translation.cross(d_in_b);
  return plucker_in_b;
}

Eigen::Vector3d PluckerClosestPointToOrigin(const Vector6d& plucker) {
  const Eigen::Vector3d d = plucker.head<3>();
  return d.cross(plucker.tail<3>()) / d.squaredNorm();
}

double PluckerLineCoordinate(const Vector6d& plucker,
                             const Eigen::Vector3d& point) {
  const Eigen::Vector3d d = plucker.head<3>();
  return (point - PluckerClosestPointToOrigin(plucker)).dot(d) / d.norm();
}

Eigen::Vector3d PluckerPointAt(const Vector6d& plucker, double coordinate) {
  return PluckerClosestPointToOrigin(plucker) +
         coordinate * plucker.head<3>().normalized();
}

double PointToPluckerLineDistance(const Vector6d& plucker,
                                  const Eigen::Vector3d& point) {
  const Eigen::Vector3d d = plucker.head<3>();
  return (point.cross(d) - plucker.tail<3>()).norm() / d.norm();
}

bool ClosestLineCoordinateToRay(const Vector6d& plucker,
                                const Eigen::Vector3d& ray_origin,
                                const Eigen::Vector3d& ray_direction,
                                double* coordinate) {
  const Eigen::Vector3d d = plucker.head<3>().normalized();
  const Eigen::Vector3d r = ray_direction.normalized();
  const Eigen::Vector3d p0 = PluckerClosestPointToOrigin(plucker);
  // Minimise |p0 + t d - (o + s r)|^2 over t, s.
  const Eigen::Vector3d w0 = p0 - ray_origin;
  const double b = d.dot(r);
  const double denom = 1.0 - b * b;
  // sin^2 of ~0.1 deg.
  constexpr double kMinSinSquared = 3e-6;
  if (denom < kMinSinSquared) {
    return false;
  }
  const double dw = d.dot(w0);
  const double rw = r.dot(w0);
  const double t = (b * rw - dw) / denom;
  const double s = (rw - b * dw) / denom;
  if (s <= 0.0) {
    return false;
  }
  *coordinate = t;
  return true;
}

Eigen::Vector3d ProjectPluckerToImageLine(const Camera& camera,
                                          const Vector6d& plucker_in_cam) {
  double fx, fy, cx, cy;
  FocalAndPrincipalPoint(camera, &fx, &fy, &cx, &cy);
  const Eigen::Vector3d m = plucker_in_cam.tail<3>();
  // m . (u, v, 1) = 0 with u = (x - cx) / fx, v = (y - cy) / fy, times
  // fx * fy.
  return Eigen::Vector3d(fy * m[0], fx * m[1],
                         fx * fy * m[2] - fy * cx * m[0] - fx * cy * m[1]);
}

Eigen::Vector2d UndistortPixel(const Camera& camera,
                               const Eigen::Vector2d& pixel) {
  double fx, fy, cx, cy;
  FocalAndPrincipalPoint(camera, &fx, &fy, &cx, &cy);
  const Eigen::Vector2d normalized = camera.CamFromImg(pixel);
  return Eigen::Vector2d(fx * normalized.x() + cx, fy * normalized.y() + cy);
}

double ImageLinePointDistance(const Eigen::Vector3d& line,
                              const Eigen::Vector2d& point) {
  return line.dot(point.homogeneous()) / line.head<2>().norm();
}

Eigen::Vector4d ViewingPlaneInWorld(const Camera& camera,
                                    const Rigid3d& cam_from_world,
                                    const Eigen::Vector2d& start2D,
                                    const Eigen::Vector2d& end2D) {
  const Eigen::Vector3d start_ray = camera.CamFromImg(start2D).homogeneous();
  const Eigen::Vector3d end_ray = camera.CamFromImg(end2D).homogeneous();
  const Eigen::Vector3d normal_in_cam = start_ray.cross(end_ray).normalized();
  const Eigen::Vector3d normal_in_world =
      cam_from_world.rotation.inverse() * normal_in_cam;
  const Eigen::Vector3d center = cam_from_world.Inverse().translation;
  Eigen::Vector4d plane;
  plane << normal_in_world, -normal_in_world.dot(center);
  return plane;
}

Vector6d IntersectPlanes(const Eigen::Vector4d& plane1,
                         const Eigen::Vector4d& plane2) {
  const Eigen::Vector3d n1 = plane1.head<3>();
  const Eigen::Vector3d n2 = plane2.head<3>();
  Vector6d plucker;
  // For p on both planes: p x (n1 x n2) = n1 (p . n2) - n2 (p . n1)
  // = -c2 n1 + c1 n2.
  plucker << n1.cross(n2), plane1[3] * n2 - plane2[3] * n1;
  return plucker;
}

}  // namespace colmap_lidar
