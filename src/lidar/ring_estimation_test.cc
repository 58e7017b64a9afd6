#include "src/lidar/ring_estimation.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {

constexpr int kNumRings = 64;

LidarScan ReadKittiScan(const std::string& name) {
  return ReadLidarScan(testing::KittiSampleDir() +
                       "/2011_09_26/velodyne_points/data/" + name + ".bin");
}

Eigen::Vector3f PointAt(double azimuth_deg, double elevation_deg,
                        double range) {
  const double azimuth = azimuth_deg * M_PI / 180.0;
  const double elevation = elevation_deg * M_PI / 180.0;
  return Eigen::Vector3f(range * std::cos(elevation) * std::cos(azimuth),
                         range * std::cos(elevation) * std::sin(azimuth),
                         range * std::sin(elevation));
}

TEST(RingEstimation, ElevationDeg) {
  EXPECT_NEAR(ElevationDeg(Eigen::Vector3f(1, 0, 1)), 45.0, 1e-9);
  EXPECT_NEAR(ElevationDeg(Eigen::Vector3f(0, -2, 0)), 0.0, 1e-9);
  EXPECT_NEAR(ElevationDeg(PointAt(123, -24.9, 30)), -24.9, 1e-5);
}

TEST(RingEstimation, FromElevationSynthetic) {
  // One point per beam centre, plus points outside the field of view.
  LidarScan scan;
  const double step = (2.0 + 24.9) / (kNumRings - 1);
  for (int ring = 0; ring < kNumRings; ++ring) {
    scan.points.push_back(
        PointAt(10.0 * ring, -24.9 + step * ring + 0.4 * step, 5.0 + ring));
  }
  scan.points.push_back(PointAt(0, -40, 3));
  scan.points.push_back(PointAt(0, 15, 3));
  const std::vector<uint16_t> rings =
      EstimateRingsFromElevation(scan, kNumRings, -24.9, 2.0);
  ASSERT_EQ(rings.size(), scan.size());
  for (int ring = 0; ring < kNumRings; ++ring) {
    EXPECT_EQ(rings[ring], ring);
  }
  EXPECT_EQ(rings[kNumRings], 0);
  EXPECT_EQ(rings[kNumRings + 1], kNumRings - 1);

  EXPECT_THROW(EstimateRingsFromElevation(scan, 0, -24.9, 2.0), Error);
  EXPECT_THROW(EstimateRingsFromElevation(scan, 64, 2.0, -24.9), Error);
}

TEST(RingEstimation, FromElevationOnKitti) {
  const LidarScan scan = ReadKittiScan("0000000000");
  const std::vector<uint16_t> rings =
      EstimateRingsFromElevation(scan, kNumRings, -24.9, 2.0);
  ASSERT_EQ(rings.size(), scan.size());
  std::vector<int> counts(kNumRings, 0);
  std::vector<double> elevation_sums(kNumRings, 0.0);
  for (size_t i = 0; i < scan.size(); ++i) {
    ASSERT_LT(rings[i], kNumRings);
    ++counts[rings[i]];
    elevation_sums[rings[i]] += ElevationDeg(scan.points[i]);
  }
  // Mean elevation increases with the ring; nearly every ring is used. The
  // nominal field of view is narrower than KITTI's data (laser offsets
  // spread near points up to +6 deg), so the top ring collects the excess.
  double previous = -90.0;
  int num_used = 0;
  for (int ring = 0; ring < kNumRings; ++ring) {
    if (counts[ring] == 0) {
      continue;
    }
    ++num_used;
    const double mean = elevation_sums[ring] / counts[ring];
    EXPECT_GT(mean, previous) << "ring " << ring;
    previous = mean;
  }
  EXPECT_GE(num_used, 58);
  std::vector<int> sorted = counts;
  std::sort(sorted.begin(), sorted.end());
  const int median = sorted[kNumRings / 2];
  EXPECT_GT(median, 1200);
  EXPECT_LT(median, 2500);
}

TEST(RingEstimation, FromScanOrderOnKitti) {
  for (const std::string name : {"0000000000", "0000000010", "0000000019"}) {
    SCOPED_TRACE(name);
    const LidarScan scan = ReadKittiScan(name);
    const std::vector<uint16_t> rings =
        EstimateRingsFromScanOrder(scan, kNumRings);
    ASSERT_EQ(rings.size(), scan.size());

    std::vector<std::vector<double>> elevations(kNumRings);
    // Far points: the per-laser offsets are negligible there, so one laser
    // has one elevation.
    std::vector<double> far_sum(kNumRings, 0.0);
    std::vector<double> far_sum_sq(kNumRings, 0.0);
    std::vector<int> far_count(kNumRings, 0);
    for (size_t i = 0; i < scan.size(); ++i) {
      const double elevation = ElevationDeg(scan.points[i]);
      elevations[rings[i]].push_back(elevation);
      if (scan.points[i].norm() > 10.0) {
        far_sum[rings[i]] += elevation;
        far_sum_sq[rings[i]] += elevation * elevation;
        ++far_count[rings[i]];
      }
    }
    // Roughly equal counts (the lowest rings hit the ground close by, the
    // highest lose points to the sky).
    size_t min_count = scan.size();
    size_t max_count = 0;
    std::vector<double> medians;
    for (std::vector<double>& values : elevations) {
      min_count = std::min(min_count, values.size());
      max_count = std::max(max_count, values.size());
      std::sort(values.begin(), values.end());
      medians.push_back(values.empty() ? 0.0 : values[values.size() / 2]);
    }
    EXPECT_GT(min_count, 900u);
    EXPECT_LT(max_count, 2300u);
    // Monotone elevation with laser-sized steps over the HDL-64E's range.
    EXPECT_LT(medians.front(), -22.0);
    EXPECT_GT(medians.back(), 2.0);
    for (int ring = 1; ring < kNumRings; ++ring) {
      EXPECT_GT(medians[ring], medians[ring - 1]) << "ring " << ring;
      EXPECT_LT(medians[ring] - medians[ring - 1], 1.5) << "ring " << ring;
    }
    // Each recovered ring is one laser: far points have one elevation.
    int num_checked = 0;
    for (int ring = 0; ring < kNumRings; ++ring) {
      if (far_count[ring] < 20) {
        continue;
      }
      ++num_checked;
      const double mean = far_sum[ring] / far_count[ring];
      const double std_dev =
          std::sqrt(std::max(0.0, far_sum_sq[ring] / far_count[ring] -
                                      mean * mean));
      EXPECT_LT(std_dev, 0.4) << "ring " << ring;
    }
    EXPECT_GE(num_checked, 30);
  }
}

TEST(RingEstimation, FromScanOrderRejectsOtherOrders) {
  LidarScan scan = ReadKittiScan("0000000000");
  // Firing order (all lasers at one azimuth, then the next azimuth) is one
  // turn in total.
  std::stable_sort(scan.points.begin(), scan.points.end(),
                   [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
                     return std::atan2(a.y(), a.x()) < std::atan2(b.y(), b.x());
                   });
  EXPECT_TRUE(EstimateRingsFromScanOrder(scan, kNumRings).empty());
  // The right order but the wrong ring count.
  EXPECT_TRUE(
      EstimateRingsFromScanOrder(ReadKittiScan("0000000000"), 32).empty());
  EXPECT_THROW(EstimateRingsFromScanOrder(scan, 0), Error);
}

TEST(RingEstimation, FromScanOrderSyntheticBothDirections) {
  // 4 rings written top first, each one turn with a 200 deg gap in ring 2;
  // each ring starts a little later in azimuth than the one before.
  for (const double direction : {1.0, -1.0}) {
    LidarScan scan;
    std::vector<uint16_t> expected;
    const double elevations[4] = {3.0, 1.0, -1.0, -3.0};
    for (int turn = 0; turn < 4; ++turn) {
      for (int k = 0; k < 360; ++k) {
        if (turn == 2 && k > 50 && k < 250) {
          continue;
        }
        // Small backward jitter must not start a new turn.
        const double jitter = (k % 7 == 3) ? -1.5 : 0.0;
        scan.points.push_back(PointAt(
            direction * (20.0 + 0.3 * turn + k + jitter), elevations[turn], 10.0));
        expected.push_back(static_cast<uint16_t>(3 - turn));
      }
    }
    EXPECT_EQ(EstimateRingsFromScanOrder(scan, 4), expected)
        << "direction " << direction;
  }
}

}  // namespace
}  // namespace colmap_lidar
