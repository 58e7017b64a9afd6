#include "src/sfm/pose_prior_checks.h"

#include <cmath>

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

// cam_from_world of a camera at `centre` turned by angle_deg about z.
Rigid3d CameraAt(const Eigen::Vector3d& centre, double angle_deg) {
  const Eigen::Quaterniond rotation(
      Eigen::AngleAxisd(angle_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()));
  return Rigid3d(rotation, -(rotation * centre));
}

TEST(PriorOutlierLevel, CentreAgainstTheChiSquareQuantiles) {
  const Rigid3d prior = CameraAt(Eigen::Vector3d(1.0, 2.0, 3.0), 10.0);
  // Sigma 1 m: chi-square(3) 99.9 % at 16.27 (4.03 m), 1 - 1e-6 at 30.66
  // (5.54 m).
  EXPECT_EQ(PriorOutlierLevel(prior, prior, 1.0, 5.0), 0);
  EXPECT_EQ(PriorOutlierLevel(CameraAt(Eigen::Vector3d(1.0, 2.0, 6.9), 10.0),
                              prior, 1.0, 5.0),
            0);
  EXPECT_EQ(PriorOutlierLevel(CameraAt(Eigen::Vector3d(1.0, 2.0, 7.5), 10.0),
                              prior, 1.0, 5.0),
            1);
  EXPECT_EQ(PriorOutlierLevel(CameraAt(Eigen::Vector3d(1.0, 2.0, 9.0), 10.0),
                              prior, 1.0, 5.0),
            2);
}

TEST(PriorOutlierLevel, RotationAngleInRmsAngles) {
  const Rigid3d prior = CameraAt(Eigen::Vector3d::Zero(), 0.0);
  // RMS angle 1 deg: 3.29 and 4.89 deg.
  EXPECT_EQ(PriorOutlierLevel(CameraAt(Eigen::Vector3d::Zero(), 3.0), prior,
                              1.0, 1.0),
            0);
  EXPECT_EQ(PriorOutlierLevel(CameraAt(Eigen::Vector3d::Zero(), 4.0), prior,
                              1.0, 1.0),
            1);
  EXPECT_EQ(PriorOutlierLevel(CameraAt(Eigen::Vector3d::Zero(), 5.0), prior,
                              1.0, 1.0),
            2);
}

TEST(PerAxisRotationSigmaDeg, SplitsTheSquaredAngleOverThreeAxes) {
  const double per_axis = PerAxisRotationSigmaDeg(5.0);
  EXPECT_NEAR(3.0 * per_axis * per_axis, 25.0, 1e-12);
}

TEST(RotationAngleDeg, AngleBetweenRotations) {
  EXPECT_NEAR(RotationAngleDeg(CameraAt(Eigen::Vector3d::Zero(), 30.0).rotation,
                               CameraAt(Eigen::Vector3d::Zero(), -15.0).rotation),
              45.0, 1e-9);
}

}  // namespace
}  // namespace colmap_lidar
