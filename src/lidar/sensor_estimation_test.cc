#include "src/lidar/sensor_estimation.h"

#include <cmath>
#include <random>

#include <glog/logging.h>
#include <gtest/gtest.h>

#include "colmap_ext/util/testing.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {

// A 32-ring scan (-15 .. +15 deg, 0.2 deg azimuth step) from the centre of
// a 20 x 16 m room with a floor 1.8 m below the sensor and a ceiling 4 m
// above, with Gaussian range noise of sigma metres along each beam.
LidarScan SimulateRoomScan(double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  LidarScan scan;
  for (int ring = 0; ring < 32; ++ring) {
    const double elevation = (-15.0 + ring * 30.0 / 31.0) * M_PI / 180.0;
    for (int k = 0; k < 1800; ++k) {
      const double azimuth = k * 0.2 * M_PI / 180.0;
      const Eigen::Vector3d dir(std::cos(elevation) * std::cos(azimuth),
                                std::cos(elevation) * std::sin(azimuth),
                                std::sin(elevation));
      double range = 1e9;
      const double bounds[3][2] = {{-10, 10}, {-8, 8}, {-1.8, 4}};
      for (int axis = 0; axis < 3; ++axis) {
        for (double b : bounds[axis]) {
          if (dir(axis) * b > 0) range = std::min(range, b / dir(axis));
        }
      }
      scan.points.push_back(((range + noise(rng)) * dir).cast<float>());
    }
  }
  return scan;
}

TEST(SensorEstimation, RangeNoiseWithin30PercentOfSimulated) {
  for (double sigma : {0.01, 0.02, 0.03}) {
    const RangeNoiseEstimate estimate =
        EstimateRangeNoise({SimulateRoomScan(sigma, 7)}, RangeNoiseOptions());
    EXPECT_GT(estimate.num_voxels, 20);
    EXPECT_NEAR(estimate.sigma_m, sigma, 0.3 * sigma) << "simulated " << sigma;
  }
}

TEST(SensorEstimation, RangeNoiseNoPlanes) {
  LidarScan scan;
  scan.points.push_back(Eigen::Vector3f(1, 2, 3));
  const RangeNoiseEstimate estimate =
      EstimateRangeNoise({scan}, RangeNoiseOptions());
  EXPECT_EQ(estimate.num_voxels, 0);
  EXPECT_EQ(estimate.sigma_m, 0.0);
}

TEST(SensorEstimation, RangeNoiseKitti) {
  // HDL-64E: about 2 cm range accuracy (datasheet); accept 0.5 .. 6 cm.
  const LidarScan scan =
      ReadLidarScan(testing::KittiSampleDir() +
                    "/2011_09_26/velodyne_points/data/0000000000.bin");
  const RangeNoiseEstimate estimate =
      EstimateRangeNoise({scan}, RangeNoiseOptions());
  EXPECT_GT(estimate.num_voxels, 30);
  LOG(INFO) << "KITTI range noise " << estimate.sigma_m << " m over "
            << estimate.num_voxels << " voxels";
  EXPECT_GT(estimate.sigma_m, 0.005);
  EXPECT_LT(estimate.sigma_m, 0.06);
}

TEST(SensorEstimation, SmoothnessThresholdRejectsNoisyFlatWall) {
  // One ring of a 32-ring sensor along a flat wall 5 m ahead (range grows
  // with the azimuth), 2 cm range noise, LeGO-LOAM window of 5 + 5.
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<double> ranges;
  for (double azimuth = -40; azimuth <= 40; azimuth += 0.2) {
    ranges.push_back(5.0 / std::cos(azimuth * M_PI / 180.0) + noise(rng));
  }
  const int k = 5;
  int above_fixed = 0, above_derived = 0, total = 0;
  for (int i = k; i + k < static_cast<int>(ranges.size()); ++i) {
    double sum = 0;
    for (int j = i - k; j <= i + k; ++j) sum += ranges[j] - ranges[i];
    const double c = std::abs(sum) / (2 * k * ranges[i]);
    above_fixed += c > 0.004;
    above_derived += c > SmoothnessThresholdForNoise(0.02, ranges[i], k);
    ++total;
  }
  // The OS1-64 value takes most flat-wall points as edges; the derived one
  // very few (3 sigma: 0.3 % expected).
  EXPECT_GT(above_fixed, total / 4);
  EXPECT_LT(above_derived, total / 100 + 1);
  // Low noise keeps the tuned floor.
  EXPECT_EQ(SmoothnessThresholdForNoise(0.002, 10.0, k), 0.004);
}

}  // namespace
}  // namespace colmap_lidar
