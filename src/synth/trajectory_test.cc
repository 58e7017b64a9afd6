#include "src/synth/trajectory.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

TEST(Trajectory, CameraPoseFromYawPitchRoll) {
  // Looking along +x, level: camera z = world x, camera y (down) = -world z,
  // camera x (right) = -world y.
  const Rigid3d pose =
      CameraPoseFromYawPitchRoll({1, 2, 3}, 0.0, 0.0, 0.0);
  const Eigen::Matrix3d r = pose.rotation.toRotationMatrix();
  EXPECT_TRUE(r.col(2).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_TRUE(r.col(1).isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
  EXPECT_TRUE(r.col(0).isApprox(-Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  // Pitch up by 10 degrees raises the optical axis.
  const Rigid3d up = CameraPoseFromYawPitchRoll({0, 0, 0}, 0.3, 0.1745, 0.02);
  const Eigen::Vector3d axis = up.rotation * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(std::asin(axis.z()), 0.1745, 1e-9);
  EXPECT_NEAR(std::atan2(axis.y(), axis.x()), 0.3, 1e-9);
}

TEST(Trajectory, QuadLoopStaysOnThePath) {
  const SynthScene scene = BuildQuadScene();
  const std::vector<Rigid3d> poses = GenerateTrajectory(scene.path, 60, 3);
  ASSERT_EQ(poses.size(), 60u);
  double total_step = 0.0;
  for (size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Vector3d& c = poses[i].translation;
    EXPECT_NEAR(c.z(), 1.5, 0.1);
    // On the ellipse x^2/9.5^2 + y^2/5.5^2 = 1 up to the 3 cm jitter.
    const double r = std::hypot(c.x() / 9.5, c.y() / 5.5);
    EXPECT_NEAR(r, 1.0, 0.02);
    // The camera looks outwards (right of the counter-clockwise walk).
    const Eigen::Vector3d axis = poses[i].rotation * Eigen::Vector3d::UnitZ();
    const Eigen::Vector2d outward(c.x() / (9.5 * 9.5), c.y() / (5.5 * 5.5));
    EXPECT_GT(axis.head<2>().dot(outward.normalized()), 0.2) << i;
    if (i > 0) total_step += (c - poses[i - 1].translation).norm();
  }
  // About 48 m of ellipse in 60 steps.
  EXPECT_NEAR(total_step / 59.0, 0.8, 0.1);
}

TEST(Trajectory, DeterministicPerSeed) {
  const SynthScene scene = BuildStreetScene();
  const auto a = GenerateTrajectory(scene.path, 10, 7);
  const auto b = GenerateTrajectory(scene.path, 10, 7);
  const auto c = GenerateTrajectory(scene.path, 10, 8);
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].translation, b[i].translation);
    EXPECT_EQ(a[i].rotation.coeffs(), b[i].rotation.coeffs());
    EXPECT_NE(a[i].translation, c[i].translation);
  }
  // Open path: first and last frames at the two ends.
  EXPECT_NEAR(a.front().translation.x(), -25.0, 0.2);
  EXPECT_NEAR(a.back().translation.x(), 25.0, 0.2);
}

// The bent street's walk follows the bend in the right lane: it starts on
// leg 0 (along +x) and ends on leg 1 (28 deg to the left), keeps 0.9-2 m
// right of the road's centre line (the kerb is 3.5 m away) and steps
// evenly through the rounded bend.
TEST(Trajectory, StreetBentWalkFollowsTheBend) {
  const SynthScene scene = BuildScene("street_bent");
  const std::vector<Rigid3d> poses = GenerateTrajectory(scene.path, 30, 5);
  const double bend = 28.0 * M_PI / 180.0;
  const Eigen::Vector2d leg1(std::cos(bend), std::sin(bend));
  std::vector<double> steps;
  for (size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Vector2d c = poses[i].translation.head<2>();
    // Signed distance to the left of the centre line, from the leg the
    // point is closest to (leg 0 for x < 0 before the bisector).
    const bool on_leg1 = c.dot(Eigen::Vector2d(std::cos(0.5 * bend),
                                               std::sin(0.5 * bend))) > 0.0;
    const double left = on_leg1 ? leg1.x() * c.y() - leg1.y() * c.x() : c.y();
    EXPECT_LT(left, -0.9) << i;
    EXPECT_GT(left, -2.0) << i;
    if (i > 0) steps.push_back((c - poses[i - 1].translation.head<2>()).norm());
  }
  EXPECT_NEAR(poses.front().translation.x(), -35.0, 0.2);
  const Eigen::Vector2d end = poses.back().translation.head<2>();
  EXPECT_NEAR(end.dot(leg1), 35.0, 0.5);
  const auto [min_step, max_step] =
      std::minmax_element(steps.begin(), steps.end());
  EXPECT_GT(*min_step, 2.2);
  EXPECT_LT(*max_step, 2.6);
}

TEST(Trajectory, PriorNoiseStatistics) {
  const int n = 20000;
  const double sigma_t = 0.5;
  const double sigma_r_deg = 5.0;
  std::vector<Rigid3d> gt(n);
  for (int i = 0; i < n; ++i) {
    gt[i] = CameraPoseFromYawPitchRoll({0.001 * i, 1.0, 1.5}, 0.01 * i, 0.1,
                                       0.0);
  }
  const std::vector<Rigid3d> prior = PerturbPoses(gt, sigma_t, sigma_r_deg, 1);
  ASSERT_EQ(prior.size(), gt.size());
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d sum_sq = Eigen::Vector3d::Zero();
  double angle_sq = 0.0;
  Eigen::Vector3d axis_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_sq = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d e = prior[i].translation - gt[i].translation;
    sum += e;
    sum_sq += e.cwiseProduct(e);
    const Eigen::AngleAxisd delta(prior[i].rotation * gt[i].rotation.inverse());
    angle_sq += delta.angle() * delta.angle();
    axis_sum += delta.axis();
    axis_sq += delta.axis().cwiseProduct(delta.axis());
  }
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(sum(k) / n, 0.0, 0.02);
    EXPECT_NEAR(std::sqrt(sum_sq(k) / n), sigma_t, 0.02 * sigma_t);
    // A uniform axis: zero mean, 1/3 of the squared norm on each axis.
    EXPECT_NEAR(axis_sum(k) / n, 0.0, 0.03);
    EXPECT_NEAR(axis_sq(k) / n, 1.0 / 3.0, 0.02);
  }
  EXPECT_NEAR(std::sqrt(angle_sq / n) * 180.0 / M_PI, sigma_r_deg,
              0.02 * sigma_r_deg);
  // Zero sigmas reproduce the ground truth.
  const auto exact = PerturbPoses(gt, 0.0, 0.0, 1);
  EXPECT_TRUE(exact[5].translation.isApprox(gt[5].translation));
  EXPECT_NEAR(exact[5].rotation.angularDistance(gt[5].rotation), 0.0, 1e-12);
}

}  // namespace
}  // namespace colmap_lidar
