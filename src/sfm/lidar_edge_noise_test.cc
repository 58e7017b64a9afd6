#include "src/sfm/lidar_edge_noise.h"

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix<double, 6, 1> Floor() {
  Eigen::Matrix<double, 6, 1> floor;
  const double rotation = 0.02 * kPi / 180.0;
  floor << rotation, rotation, rotation, 0.005, 0.005, 0.005;
  return floor;
}

// Closures of a corridor-like graph: loops i -> i + 2, each closure the sum
// of three edge errors, N(0, sigma_x) along the sensor's x and small
// elsewhere.
std::vector<LidarLoopClosure> CorridorClosures(int num_closures,
                                               double sigma_x_m,
                                               double sigma_other_m) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<LidarLoopClosure> closures;
  for (int c = 0; c < num_closures; ++c) {
    LidarLoopClosure closure;
    closure.i = c;
    closure.j = c + 2;
    const double scale = std::sqrt(3.0);
    for (int k = 0; k < 3; ++k) {
      closure.delta[k] = scale * 1e-5 * normal(rng);
    }
    closure.delta[3] = scale * sigma_x_m * normal(rng);
    closure.delta[4] = scale * sigma_other_m * normal(rng);
    closure.delta[5] = scale * sigma_other_m * normal(rng);
    closures.push_back(closure);
  }
  return closures;
}

TEST(ClosureDelta, IsTheRightPerturbationFromChainToLoop) {
  const Rigid3d chained(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(0, 0, 1))),
      Eigen::Vector3d(6.8, 0.2, -0.1));
  const Eigen::Vector3d rotation_delta(0.001, -0.002, 0.0005);
  const Eigen::Vector3d translation_delta(0.12, -0.01, 0.004);
  const Rigid3d perturbation(
      Eigen::Quaterniond(Eigen::AngleAxisd(rotation_delta.norm(),
                                           rotation_delta.normalized())),
      translation_delta);
  const Eigen::Matrix<double, 6, 1> delta =
      ClosureDelta(chained, chained * perturbation);
  EXPECT_LT((delta.head<3>() - rotation_delta).norm(), 1e-12);
  EXPECT_LT((delta.tail<3>() - translation_delta).norm(), 1e-12);
  EXPECT_LT(ClosureDelta(chained, chained).norm(), 1e-12);
}

TEST(EstimateLidarEdgeNoise, MeasuresTheCorridorAxisAndInflatesOnlyIt) {
  const std::vector<LidarLoopClosure> closures =
      CorridorClosures(400, /*sigma_x_m=*/0.08, /*sigma_other_m=*/0.003);
  const LidarEdgeNoiseEstimate estimate =
      EstimateLidarEdgeNoise(closures, Floor(), LidarEdgeNoiseOptions());
  ASSERT_TRUE(estimate.estimated);
  EXPECT_EQ(estimate.num_closures, 400);
  // The scaled median absolute value of 400 draws: relative standard error
  // about 6 %.
  EXPECT_NEAR(estimate.sigma[3], 0.08, 0.15 * 0.08);
  EXPECT_NEAR(estimate.sigma[4], 0.003, 0.15 * 0.003);
  EXPECT_GT(estimate.added_variance[3], 0.0);
  EXPECT_NEAR(estimate.added_variance[3],
              estimate.sigma[3] * estimate.sigma[3] - 0.005 * 0.005, 1e-12);
  for (const int k : {0, 1, 2, 4, 5}) {
    EXPECT_EQ(estimate.added_variance[k], 0.0) << "axis " << k;
  }
  EXPECT_NE(estimate.Format().find("inflated beyond the floor: x"),
            std::string::npos)
      << estimate.Format();
}

TEST(EstimateLidarEdgeNoise, LongerClosuresCountTheirEdges) {
  // A closure over j - i = 5 consecutive edges sums 6 edge errors.
  std::vector<LidarLoopClosure> closures(9);
  for (size_t c = 0; c < closures.size(); ++c) {
    closures[c].i = 0;
    closures[c].j = 5;
    closures[c].delta[3] = std::sqrt(6.0) * 0.04 / 1.4826;
  }
  const LidarEdgeNoiseEstimate estimate =
      EstimateLidarEdgeNoise(closures, Floor(), LidarEdgeNoiseOptions());
  ASSERT_TRUE(estimate.estimated);
  EXPECT_NEAR(estimate.sigma[3], 0.04, 1e-12);
}

TEST(EstimateLidarEdgeNoise, TooFewClosuresOrDisabledGiveNoEstimate) {
  const std::vector<LidarLoopClosure> closures = CorridorClosures(4, 0.08, 0.003);
  const LidarEdgeNoiseEstimate few =
      EstimateLidarEdgeNoise(closures, Floor(), LidarEdgeNoiseOptions());
  EXPECT_FALSE(few.estimated);
  EXPECT_EQ(few.num_closures, 4);
  EXPECT_EQ(few.added_variance, (Eigen::Matrix<double, 6, 1>::Zero()));
  EXPECT_EQ(few.cap_sigma, Floor());

  LidarEdgeNoiseOptions disabled;
  disabled.enabled = false;
  const LidarEdgeNoiseEstimate off = EstimateLidarEdgeNoise(
      CorridorClosures(40, 0.08, 0.003), Floor(), disabled);
  EXPECT_FALSE(off.estimated);
  EXPECT_EQ(off.added_variance, (Eigen::Matrix<double, 6, 1>::Zero()));
}

TEST(EstimateLidarEdgeNoise, NoiseAtTheFloorAddsNothing) {
  // Well-conditioned scans: closures at the floor sigma leave the
  // information as the registrations have it.
  const LidarEdgeNoiseEstimate estimate = EstimateLidarEdgeNoise(
      CorridorClosures(40, 0.005, 0.005), Floor(), LidarEdgeNoiseOptions());
  ASSERT_TRUE(estimate.estimated);
  EXPECT_EQ(estimate.added_variance, (Eigen::Matrix<double, 6, 1>::Zero()));
}

TEST(EstimateLidarEdgeNoise, CleanScansLowerTheCapDownToAFractionOfTheFloor) {
  // Closures of 1 mm along x (a fifth of the floor) and 0.1 mm elsewhere
  // (a fiftieth): the cap follows the measurement down to
  // min_cap_fraction x floor; rotations at the floor stay at the floor.
  std::vector<LidarLoopClosure> closures = CorridorClosures(400, 0.001, 0.0001);
  const double rotation_floor = Floor()[0];
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (LidarLoopClosure& closure : closures) {
    for (int k = 0; k < 3; ++k) {
      closure.delta[k] = std::sqrt(3.0) * rotation_floor * normal(rng);
    }
  }
  const LidarEdgeNoiseEstimate estimate =
      EstimateLidarEdgeNoise(closures, Floor(), LidarEdgeNoiseOptions());
  ASSERT_TRUE(estimate.estimated);
  EXPECT_EQ(estimate.added_variance, (Eigen::Matrix<double, 6, 1>::Zero()));
  EXPECT_NEAR(estimate.cap_sigma[3], 0.001, 0.15 * 0.001);
  EXPECT_EQ(estimate.cap_sigma[4], 0.1 * 0.005);
  EXPECT_EQ(estimate.cap_sigma[5], 0.1 * 0.005);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(estimate.cap_sigma[k], rotation_floor) << "axis " << k;
  }
  EXPECT_NE(estimate.Format().find("cap lowered below the floor: x, y, z"),
            std::string::npos)
      << estimate.Format();
}

TEST(EstimateLidarEdgeNoise, ASystematicClosureIsBiasNotNoise) {
  // Loops 8 cm longer per edge than their chains (KITTI's moving traffic):
  // the x axis is reported as biased and left as registered; the other
  // axes are estimated as usual.
  std::vector<LidarLoopClosure> closures = CorridorClosures(18, 0.02, 0.0001);
  for (LidarLoopClosure& closure : closures) {
    closure.delta[3] += std::sqrt(3.0) * 0.08;
  }
  const LidarEdgeNoiseEstimate estimate =
      EstimateLidarEdgeNoise(closures, Floor(), LidarEdgeNoiseOptions());
  ASSERT_TRUE(estimate.estimated);
  EXPECT_TRUE(estimate.biased[3]);
  EXPECT_GT(estimate.bias_t[3], 4.0);
  EXPECT_NEAR(estimate.mean[3], 0.08, 0.02);
  EXPECT_EQ(estimate.added_variance[3], 0.0);
  EXPECT_EQ(estimate.cap_sigma[3], Floor()[3]);
  EXPECT_FALSE(estimate.biased[4]);
  EXPECT_LT(estimate.cap_sigma[4], Floor()[4]);
  EXPECT_NE(estimate.Format().find("disagree systematically along x"),
            std::string::npos)
      << estimate.Format();

  // A significant but tiny offset (0.2 mm per edge, below half the 5 mm
  // floor) is no bias: the axis is estimated as usual.
  std::vector<LidarLoopClosure> tiny = CorridorClosures(18, 0.0001, 0.0001);
  for (LidarLoopClosure& closure : tiny) {
    closure.delta[5] += std::sqrt(3.0) * 0.0002;
  }
  const LidarEdgeNoiseEstimate small =
      EstimateLidarEdgeNoise(tiny, Floor(), LidarEdgeNoiseOptions());
  EXPECT_GT(std::abs(small.bias_t[5]), 4.0);
  EXPECT_FALSE(small.biased[5]);
  EXPECT_LT(small.cap_sigma[5], Floor()[5]);

  // The same spread without the offset: noise, inflated.
  const LidarEdgeNoiseEstimate unbiased = EstimateLidarEdgeNoise(
      CorridorClosures(18, 0.08, 0.0001), Floor(), LidarEdgeNoiseOptions());
  EXPECT_FALSE(unbiased.biased[3]);
  EXPECT_GT(unbiased.added_variance[3], 0.0);
}

TEST(LidarEdgeNoiseOptions, Check) {
  EXPECT_TRUE(LidarEdgeNoiseOptions().Check());
  LidarEdgeNoiseOptions options;
  options.min_num_closures = 0;
  EXPECT_FALSE(options.Check());
  options = LidarEdgeNoiseOptions();
  options.min_excess_ratio = 0.5;
  EXPECT_FALSE(options.Check());
  options = LidarEdgeNoiseOptions();
  options.min_cap_fraction = 0.0;
  EXPECT_FALSE(options.Check());
  options = LidarEdgeNoiseOptions();
  options.max_bias_t = 0.0;
  EXPECT_FALSE(options.Check());
}

TEST(InflateInformation, AddsTheVarianceAlongItsAxisOnly) {
  // A registration with 5 mm / 0.02 deg everywhere, correlated a little
  // between x and the yaw.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  const double rotation = 0.02 * kPi / 180.0;
  covariance.diagonal() << rotation * rotation, rotation * rotation,
      rotation * rotation, 2.5e-5, 2.5e-5, 2.5e-5;
  covariance(2, 3) = covariance(3, 2) = 0.5 * rotation * 0.005;
  const Eigen::Matrix<double, 6, 6> information = covariance.inverse();

  EXPECT_EQ(InflateInformation(information, Eigen::Matrix<double, 6, 1>::Zero()),
            information);

  Eigen::Matrix<double, 6, 1> added = Eigen::Matrix<double, 6, 1>::Zero();
  added[3] = 0.08 * 0.08;
  const Eigen::Matrix<double, 6, 6> inflated =
      InflateInformation(information, added);
  EXPECT_LT((inflated - inflated.transpose()).norm(), 1e-9 * inflated.norm());
  Eigen::Matrix<double, 6, 6> expected = covariance;
  expected(3, 3) += added[3];
  const Eigen::Matrix<double, 6, 6> inflated_covariance = inflated.inverse();
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) {
      EXPECT_NEAR(inflated_covariance(r, c), expected(r, c),
                  1e-9 * std::abs(expected(r, r)) + 1e-15)
          << r << ", " << c;
    }
  }
}

TEST(InflateInformation, ADirectionWithoutInformationKeepsNone) {
  // x unconstrained (a featureless corridor): no information there before
  // or after, the other axes inflated as asked.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  information.diagonal() << 1e7, 1e7, 1e7, 0.0, 4e4, 4e4;
  Eigen::Matrix<double, 6, 1> added = Eigen::Matrix<double, 6, 1>::Zero();
  added[3] = 0.01;
  added[4] = 0.0001;
  const Eigen::Matrix<double, 6, 6> inflated =
      InflateInformation(information, added);
  EXPECT_EQ(inflated.row(3).norm(), 0.0);
  EXPECT_NEAR(inflated(4, 4), 1.0 / (1.0 / 4e4 + 1e-4), 1e-6);
  EXPECT_NEAR(inflated(5, 5), 4e4, 1e-6);
  EXPECT_NEAR(inflated(0, 0), 1e7, 1e-3);
}

}  // namespace
}  // namespace colmap_lidar
