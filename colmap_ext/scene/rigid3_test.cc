#include "colmap_ext/scene/rigid3.h"

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

Rigid3d TestTransform(double angle, const Eigen::Vector3d& axis,
                      const Eigen::Vector3d& translation) {
  return Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized())),
      translation);
}

TEST(Rigid3d, ApplyAndInverse) {
  // 90 degrees about z, then a shift: (1, 0, 0) -> (0, 1, 0) + t.
  const Rigid3d b_from_a = TestTransform(M_PI / 2, Eigen::Vector3d::UnitZ(),
                                         Eigen::Vector3d(1, 2, 3));
  const Eigen::Vector3d point_in_b = b_from_a * Eigen::Vector3d(1, 0, 0);
  EXPECT_TRUE(point_in_b.isApprox(Eigen::Vector3d(1, 3, 3), 1e-12));
  const Eigen::Vector3d point_in_a = b_from_a.Inverse() * point_in_b;
  EXPECT_TRUE(point_in_a.isApprox(Eigen::Vector3d(1, 0, 0), 1e-12));
}

TEST(Rigid3d, CompositionMatchesSequentialApplication) {
  const Rigid3d b_from_a =
      TestTransform(0.3, Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(-1, 0.5, 2));
  const Rigid3d c_from_b =
      TestTransform(-1.1, Eigen::Vector3d(0, 1, -1), Eigen::Vector3d(4, -2, 1));
  const Eigen::Vector3d point_in_a(0.7, -0.2, 5.0);
  const Eigen::Vector3d expected = c_from_b * (b_from_a * point_in_a);
  EXPECT_LT(((c_from_b * b_from_a) * point_in_a - expected).norm(), 1e-12);
  const Rigid3d identity = b_from_a * b_from_a.Inverse();
  EXPECT_LT(identity.translation.norm(), 1e-12);
  EXPECT_NEAR(std::abs(identity.rotation.w()), 1.0, 1e-12);
}

TEST(Rigid3d, MatrixRoundTrip) {
  const Rigid3d cam_from_world = TestTransform(
      2.0, Eigen::Vector3d(-1, 0.2, 0.4), Eigen::Vector3d(3, 2, 1));
  const Eigen::Matrix3x4d matrix = cam_from_world.ToMatrix();
  EXPECT_TRUE(matrix.leftCols<3>().isApprox(
      cam_from_world.rotation.toRotationMatrix(), 1e-14));
  EXPECT_EQ(Eigen::Vector3d(matrix.col(3)), cam_from_world.translation);
  const Rigid3d back = Rigid3d::FromMatrix(matrix);
  EXPECT_LT((back.ToMatrix() - matrix).norm(), 1e-12);
  // A slightly non-orthonormal R is projected back onto a rotation.
  Eigen::Matrix3x4d noisy = matrix;
  noisy(0, 0) += 1e-7;
  const Eigen::Matrix3d R =
      Rigid3d::FromMatrix(noisy).rotation.toRotationMatrix();
  EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

}  // namespace
}  // namespace colmap_lidar
