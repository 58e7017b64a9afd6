// The orthonormal representation of an infinite 3D line (Bartoli & Sturm
// 2005, see line_geometry.h) as a ceres::Manifold, used by the line bundle
// adjustment (paper section III-D: "We resort to the orthonormal
// representation for lines during the optimization process").
//
// Ambient space: 6 doubles [qx, qy, qz, qw, w1, w2] (U in SO(3) as a unit
// quaternion in Eigen's memory order, W in SO(2) as its first column
// (cos phi, sin phi)). Tangent space: 4 doubles [theta (3), phi].
//
//   Plus(x, delta)  = (q * Exp(theta), W * R(phi))      (right perturbation,
//                                                         U <- U R(theta))
//   Minus(y, x)     = (Log(q_x^-1 * q_y), atan2 of W_x^T W_y)
//
// Exp/Log are the unit-quaternion exponential map and its inverse (angle in
// [0, 2 pi) so that Plus(x, Minus(y, x)) reproduces y exactly, as Ceres'
// own quaternion manifolds do). Both parts stay exactly on SO(3) x SO(2),
// so the Pluecker vector (w2 u2, w1 u1) always satisfies the Klein
// constraint and the line has exactly 4 degrees of freedom.
#pragma once

#include <ceres/manifold.h>

namespace colmap_lidar {

class OrthonormalLineManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 6; }
  int TangentSize() const override { return 4; }

  bool Plus(const double* x, const double* delta,
            double* x_plus_delta) const override;
  // 6x4 row-major Jacobian of Plus(x, delta) w.r.t. delta at delta = 0.
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x,
             double* y_minus_x) const override;
  // 4x6 row-major Jacobian of Minus(y, x) w.r.t. y at y = x.
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace colmap_lidar
