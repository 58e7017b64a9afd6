// A rigid transform target_from_source: x_target = rotation * x_source +
// translation. Names follow COLMAP 3.9 (cam_from_world, cam_from_lidar).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "colmap_ext/util/types.h"

namespace colmap_lidar {

struct Rigid3d {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Rigid3d() = default;
  Rigid3d(const Eigen::Quaterniond& rotation, const Eigen::Vector3d& translation)
      : rotation(rotation), translation(translation) {}

  // From a 3x4 [R|t] or the top rows of a 4x4 matrix. R is re-orthonormalised
  // through the quaternion.
  static Rigid3d FromMatrix(const Eigen::Matrix3x4d& matrix) {
    return Rigid3d(Eigen::Quaterniond(matrix.leftCols<3>()).normalized(),
                   matrix.col(3));
  }

  Eigen::Matrix3x4d ToMatrix() const {
    Eigen::Matrix3x4d matrix;
    matrix.leftCols<3>() = rotation.toRotationMatrix();
    matrix.col(3) = translation;
    return matrix;
  }

  Rigid3d Inverse() const {
    const Eigen::Quaterniond inverse_rotation = rotation.inverse();
    return Rigid3d(inverse_rotation, inverse_rotation * -translation);
  }

  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const {
    return rotation * point + translation;
  }
};

// c_from_a = c_from_b * b_from_a.
inline Rigid3d operator*(const Rigid3d& c_from_b, const Rigid3d& b_from_a) {
  return Rigid3d((c_from_b.rotation * b_from_a.rotation).normalized(),
                 c_from_b.translation + c_from_b.rotation * b_from_a.translation);
}

}  // namespace colmap_lidar
