#include "src/lidar/scan_registration.h"

#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"
#include "src/lidar/lidar_test_scene.h"

namespace colmap_lidar {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<Eigen::Vector3d> SampleStreet(unsigned seed) {
  return SampleStreetScene(seed, 20.0);
}

// A corridor along x: ground and two walls only, nothing fixes x.
std::vector<Eigen::Vector3d> SampleCorridor(unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Eigen::Vector3d> points;
  SampleRectangle({-40, -4, -1.7}, {80, 0, 0}, {0, 8, 0}, 20.0, &rng, &points);
  SampleRectangle({-40, -4, -1.7}, {80, 0, 0}, {0, 0, 5}, 20.0, &rng, &points);
  SampleRectangle({-40, 4, -1.7}, {80, 0, 0}, {0, 0, 5}, 20.0, &rng, &points);
  return points;
}

LidarScan MakeScan(const std::vector<Eigen::Vector3d>& points_in_world,
                   const Rigid3d& world_from_lidar, double noise_m,
                   unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_m);
  const Rigid3d lidar_from_world = world_from_lidar.Inverse();
  LidarScan scan;
  for (const Eigen::Vector3d& point : points_in_world) {
    const Eigen::Vector3d p = lidar_from_world * point;
    scan.points.push_back(
        (p + noise(rng) * p.normalized()).cast<float>());
  }
  return scan;
}

TEST(ScanRegistration, RecoversAMotionFromAPriorLevelGuess) {
  const Rigid3d world_from_target = PoseFromYawRoll(10, 0, {0, 0, 0});
  const Rigid3d world_from_source = PoseFromYawRoll(17, 1, {2.5, 0.8, 0.05});
  const LidarScan target =
      MakeScan(SampleStreet(1), world_from_target, 0.015, 11);
  const LidarScan source =
      MakeScan(SampleStreet(2), world_from_source, 0.015, 12);
  const Rigid3d truth = world_from_target.Inverse() * world_from_source;
  // A guess as far off as two frames with 0.5 m / 5 deg priors can be.
  const Rigid3d guess = truth * PoseFromYawRoll(-7, 2, {0.6, -0.5, 0.2});
  ScanRegistrationOptions options;
  options.num_threads = 2;
  const ScanRegistrationResult result =
      RegisterScans(source, target, guess, options);
  EXPECT_TRUE(result.converged);
  EXPECT_GT(result.fitness, 0.8);
  EXPECT_LT(result.rmse_m, 0.05);
  EXPECT_LT((result.target_from_source.translation - truth.translation).norm(),
            0.02);
  EXPECT_LT(RotationErrorDeg(result.target_from_source, truth), 0.1);
  EXPECT_GT(result.voxel_size_m, 0.09);
  EXPECT_LE(result.voxel_size_m, 0.5);
  // Information: positive definite, capped at the floor sigmas.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> solver(
      result.information);
  EXPECT_GT(solver.eigenvalues().minCoeff(), 0.0);
  EXPECT_LE(result.information(3, 3),
            1.0 / (options.min_translation_sigma_m *
                   options.min_translation_sigma_m) * 1.0001);
}

TEST(ScanRegistration, InformationIsSmallAlongACorridor) {
  const Rigid3d world_from_target;
  const Rigid3d world_from_source = PoseFromYawRoll(0, 0, {1.0, 0.1, 0});
  const LidarScan target =
      MakeScan(SampleCorridor(3), world_from_target, 0.015, 13);
  const LidarScan source =
      MakeScan(SampleCorridor(4), world_from_source, 0.015, 14);
  const Rigid3d truth = world_from_target.Inverse() * world_from_source;
  ScanRegistrationOptions options;
  options.num_threads = 2;
  const ScanRegistrationResult result =
      RegisterScans(source, target, truth, options);
  EXPECT_GT(result.fitness, 0.8);
  // Translation along the corridor (x) is unconstrained, across (y) it is
  // pinned by the walls.
  EXPECT_LT(result.information(3, 3), 0.25 * result.information(4, 4))
      << result.information << "\n" << result.target_from_source.translation.transpose();
}

// The corridor with a few shallow jambs (0.15 m deep, 1 m wide) on its
// walls: the only surfaces that face along the axis.
std::vector<Eigen::Vector3d> SampleCorridorWithJambs(unsigned seed) {
  std::vector<Eigen::Vector3d> points = SampleCorridor(seed);
  std::mt19937 rng(seed + 100);
  for (const double x : {-13.0, -6.5, 2.0, 7.5, 15.0}) {
    SampleBox({x, -4.0, -1.7}, {1.0, 0.15, 4.0}, 20.0, &rng, &points);
    SampleBox({x + 1.7, 3.85, -1.7}, {1.0, 0.15, 4.0}, 20.0, &rng, &points);
  }
  return points;
}

TEST(ScanRegistration, SlidesAlongACorridorToItsJambs) {
  const Rigid3d world_from_target = PoseFromYawRoll(0, 0, {0, 0, 0});
  const Rigid3d world_from_source = PoseFromYawRoll(2, 0, {2.2, 0.1, 0.02});
  const LidarScan target =
      MakeScan(SampleCorridorWithJambs(7), world_from_target, 0.02, 17);
  const LidarScan source =
      MakeScan(SampleCorridorWithJambs(8), world_from_source, 0.02, 18);
  const Rigid3d truth = world_from_target.Inverse() * world_from_source;
  ScanRegistrationOptions options;
  options.num_threads = 2;
  for (const double offset_m : {-0.6, 0.6}) {
    // A guess as far off along the axis as 0.5 m priors can put it. GICP
    // alone ends where it starts (0.6 m off, measured); the point-to-plane
    // steps bring it within 0.05-0.11 m on these sparse, noisy jambs.
    Rigid3d guess = truth;
    guess.translation.x() += offset_m;
    const ScanRegistrationResult result =
        RegisterScans(source, target, guess, options);
    EXPECT_LT(std::abs(result.target_from_source.translation.x() -
                       truth.translation.x()),
              0.15)
        << "from an offset of " << offset_m << " m";
    EXPECT_LT(RotationErrorDeg(result.target_from_source, truth), 0.2);
  }
}

TEST(ScanRegistration, DisjointScansHaveLowFitness) {
  const LidarScan target = MakeScan(SampleStreet(5), Rigid3d(), 0.015, 15);
  // The source sees the street from 300 m away: nothing within range.
  LidarScan source = MakeScan(SampleCorridor(6), Rigid3d(), 0.015, 16);
  ScanRegistrationOptions options;
  options.num_threads = 2;
  const ScanRegistrationResult result = RegisterScans(
      source, target, PoseFromYawRoll(0, 0, {0, 60, 30}), options);
  EXPECT_LT(result.fitness, 0.3);
}

TEST(ScanRegistration, RejectsBadOptionsAndTinyScans) {
  ScanRegistrationOptions options;
  EXPECT_TRUE(options.Check());
  options.max_range_m = options.min_range_m;
  EXPECT_FALSE(options.Check());
  options = ScanRegistrationOptions();
  options.coarse_voxel_factor = 0.5;
  EXPECT_FALSE(options.Check());
  options = ScanRegistrationOptions();
  LidarScan tiny;
  tiny.points.emplace_back(5, 0, 0);
  EXPECT_THROW(PreparedScan(tiny, options), Error);
}

TEST(ScanRegistration, VoxelFollowsTheScanRange) {
  ScanRegistrationOptions options;
  LidarScan near_scan, far_scan;
  for (int k = 0; k < 100; ++k) {
    near_scan.points.emplace_back(5.0f, 0.01f * k, 0.0f);
    far_scan.points.emplace_back(15.0f, 0.01f * k, 0.0f);
  }
  EXPECT_NEAR(VoxelSizeForScan(near_scan, options), 5.0 * 1.5 * kPi / 180,
              1e-3);
  EXPECT_NEAR(VoxelSizeForScan(far_scan, options), 15.0 * 1.5 * kPi / 180,
              1e-3);
  options.voxel_size_m = 0.3;
  EXPECT_EQ(VoxelSizeForScan(far_scan, options), 0.3);
}

}  // namespace
}  // namespace colmap_lidar
