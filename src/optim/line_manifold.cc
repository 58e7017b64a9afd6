#include "src/optim/line_manifold.h"

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace colmap_lidar {
namespace {

// Unit quaternion of the rotation vector theta.
Eigen::Quaterniond QuaternionExp(const Eigen::Vector3d& theta) {
  const double angle = theta.norm();
  if (angle == 0.0) {
    return Eigen::Quaterniond::Identity();
  }
  const double half = 0.5 * angle;
  const Eigen::Vector3d axis = theta / angle;
  return Eigen::Quaterniond(std::cos(half), std::sin(half) * axis.x(),
                            std::sin(half) * axis.y(),
                            std::sin(half) * axis.z());
}

// Rotation vector of a unit quaternion, inverse of QuaternionExp for
// rotation angles in [0, 2 pi).
Eigen::Vector3d QuaternionLog(const Eigen::Quaterniond& q) {
  const Eigen::Vector3d v = q.vec();
  const double v_norm = v.norm();
  if (v_norm == 0.0) {
    return Eigen::Vector3d::Zero();
  }
  const double half = std::atan2(v_norm, q.w());
  return (2.0 * half / v_norm) * v;
}

}  // namespace

bool OrthonormalLineManifold::Plus(const double* x, const double* delta,
                                   double* x_plus_delta) const {
  const Eigen::Map<const Eigen::Quaterniond> q(x);
  const Eigen::Map<const Eigen::Vector3d> theta(delta);
  Eigen::Map<Eigen::Quaterniond> q_plus(x_plus_delta);
  q_plus = (q * QuaternionExp(theta)).normalized();
  const double c = std::cos(delta[3]);
  const double s = std::sin(delta[3]);
  // First column of W * R(phi).
  x_plus_delta[4] = x[4] * c - x[5] * s;
  x_plus_delta[5] = x[5] * c + x[4] * s;
  return true;
}

bool OrthonormalLineManifold::PlusJacobian(const double* x,
                                           double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 4, Eigen::RowMajor>> j(jacobian);
  j.setZero();
  // d(q * (theta / 2, 1)) / d theta = 0.5 [w I + [v]x ; -v^T].
  const Eigen::Vector3d v(x[0], x[1], x[2]);
  const double w = x[3];
  Eigen::Matrix3d v_cross;
  v_cross << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  j.block<3, 3>(0, 0) = 0.5 * (w * Eigen::Matrix3d::Identity() + v_cross);
  j.block<1, 3>(3, 0) = -0.5 * v.transpose();
  j(4, 3) = -x[5];
  j(5, 3) = x[4];
  return true;
}

bool OrthonormalLineManifold::Minus(const double* y, const double* x,
                                    double* y_minus_x) const {
  const Eigen::Map<const Eigen::Quaterniond> q_x(x);
  const Eigen::Map<const Eigen::Quaterniond> q_y(y);
  Eigen::Map<Eigen::Vector3d> theta(y_minus_x);
  theta = QuaternionLog(q_x.conjugate() * q_y);
  // Angle of W_x^T W_y.
  y_minus_x[3] = std::atan2(x[4] * y[5] - x[5] * y[4], x[4] * y[4] + x[5] * y[5]);
  return true;
}

bool OrthonormalLineManifold::MinusJacobian(const double* x,
                                            double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 4, 6, Eigen::RowMajor>> j(jacobian);
  j.setZero();
  // d(2 vec(q_x^* * q_y)) / d q_y at q_y = q_x: 2 [w I - [v]x, -v].
  const Eigen::Vector3d v(x[0], x[1], x[2]);
  const double w = x[3];
  Eigen::Matrix3d v_cross;
  v_cross << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  j.block<3, 3>(0, 0) = 2.0 * (w * Eigen::Matrix3d::Identity() - v_cross);
  j.block<3, 1>(0, 3) = -2.0 * v;
  j(3, 4) = -x[5];
  j(3, 5) = x[4];
  return true;
}

}  // namespace colmap_lidar
