#include "src/mesh/lidar_denoising.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Voxel centroids every 5 cm on the plane z = 0 (x in [-1, 0]) and on the
// plane x = 0 (z in [0, 1]), which meet at a right-angled crease along y;
// Gaussian noise of `noise_std` (1 cm by default) along the plane normals.
struct CreaseCloud {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;
};
CreaseCloud MakeCreaseCloud(double noise_std = 0.01) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, noise_std);
  CreaseCloud cloud;
  for (int i = 0; i <= 20; ++i) {
    for (int j = 0; j <= 20; ++j) {
      const double u = -1.0 + 0.05 * i;
      const double y = -0.5 + 0.05 * j;
      cloud.positions.emplace_back(u, y, noise(rng));
      cloud.normals.emplace_back(0, 0, 1);
      if (i > 0) {
        cloud.positions.emplace_back(noise(rng), y, 1.0 + u);
        cloud.normals.emplace_back(1, 0, 0);
      }
    }
  }
  return cloud;
}

double DistanceToCrease(const CreaseCloud& cloud, size_t i,
                        const Eigen::Vector3d& p) {
  return std::abs(cloud.normals[i].dot(p));  // Both planes pass the origin.
}

TEST(LidarDenoising, ProjectsPlanarVoxelsAndKeepsTheCrease) {
  CreaseCloud cloud = MakeCreaseCloud();
  const std::vector<uint32_t> counts(cloud.positions.size(), 1);
  std::vector<Eigen::Vector3d> positions = cloud.positions;
  LidarDenoisingOptions options;
  options.radius_m = 0.15;
  const LidarDenoisingSummary summary =
      DenoiseLidarVoxels(options, counts, 2, &positions);
  double error_before = 0, error_after = 0;
  size_t num_far = 0, num_near_projected = 0, num_near = 0;
  for (size_t i = 0; i < positions.size(); ++i) {
    const double to_crease = std::hypot(cloud.positions[i].x(),
                                        cloud.positions[i].z());
    const bool moved = positions[i] != cloud.positions[i];
    if (to_crease > 0.2) {
      ++num_far;
      error_before += DistanceToCrease(cloud, i, cloud.positions[i]);
      error_after += DistanceToCrease(cloud, i, positions[i]);
      EXPECT_TRUE(moved);
    } else if (to_crease < 0.04) {
      ++num_near;
      num_near_projected += moved ? 1 : 0;
    }
  }
  ASSERT_GT(num_far, 0u);
  ASSERT_GT(num_near, 0u);
  // Averaging ~30 voxels divides the noise by several.
  EXPECT_LT(error_after, 0.4 * error_before);
  // Voxels at the crease see both planes: not planar, not moved.
  EXPECT_EQ(num_near_projected, 0u);
  EXPECT_GT(summary.num_projected, num_far);
  EXPECT_GT(summary.mean_displacement_m, 0.0);
}

// 3 cm of noise (a VLP-16): a fixed 2 cm planarity threshold leaves most of
// the planes noisy; the threshold from the measured median deviation
// projects them. At a 0.15 m radius the crease itself is then as "planar"
// as 3 cm noise (its neighbourhood deviates ~3 cm from the best plane), so
// it is flattened too; a radius twice as large keeps it.
TEST(LidarDenoising, ThresholdFollowsTheMeasuredNoise) {
  const CreaseCloud cloud = MakeCreaseCloud(0.03);
  const std::vector<uint32_t> counts(cloud.positions.size(), 1);
  struct Outcome {
    double far_moved_share = 0;
    double error_ratio = 0;  // Far voxels' distance after / before.
    size_t num_near_moved = 0;
    LidarDenoisingSummary summary;
  };
  auto run = [&](const LidarDenoisingOptions& options) {
    std::vector<Eigen::Vector3d> positions = cloud.positions;
    Outcome outcome;
    outcome.summary = DenoiseLidarVoxels(options, counts, 2, &positions);
    size_t num_far = 0, num_far_moved = 0;
    double error_before = 0, error_after = 0;
    for (size_t i = 0; i < positions.size(); ++i) {
      const double to_crease = std::hypot(cloud.positions[i].x(),
                                          cloud.positions[i].z());
      const bool moved = positions[i] != cloud.positions[i];
      if (to_crease > 0.35) {
        ++num_far;
        num_far_moved += moved;
        error_before += DistanceToCrease(cloud, i, cloud.positions[i]);
        error_after += DistanceToCrease(cloud, i, positions[i]);
      } else if (to_crease < 0.04) {
        outcome.num_near_moved += moved;
      }
    }
    outcome.far_moved_share = static_cast<double>(num_far_moved) / num_far;
    outcome.error_ratio = error_after / error_before;
    return outcome;
  };
  LidarDenoisingOptions options;
  options.plane_std_factor = 0;
  const Outcome fixed = run(options);
  EXPECT_DOUBLE_EQ(fixed.summary.plane_std_threshold_m,
                   options.max_plane_std_m);
  EXPECT_LT(fixed.far_moved_share, 0.5);
  EXPECT_EQ(fixed.num_near_moved, 0u);

  options = LidarDenoisingOptions();
  const Outcome adaptive = run(options);
  // The median deviation measures the noise (3 cm, less after the fit).
  EXPECT_GT(adaptive.summary.median_plane_std_m, 0.02);
  EXPECT_LT(adaptive.summary.median_plane_std_m, 0.035);
  EXPECT_NEAR(adaptive.summary.plane_std_threshold_m,
              1.5 * adaptive.summary.median_plane_std_m, 1e-12);
  EXPECT_GT(adaptive.far_moved_share, 0.95);
  EXPECT_LT(adaptive.error_ratio, 0.5);
  EXPECT_LT(adaptive.error_ratio, fixed.error_ratio);

  options.radius_m = 0.3;
  const Outcome wide = run(options);
  EXPECT_GT(wide.far_moved_share, 0.95);
  EXPECT_LT(wide.error_ratio, adaptive.error_ratio);
  EXPECT_EQ(wide.num_near_moved, 0u);

  options.plane_std_factor = -1;
  EXPECT_FALSE(options.Check());
}

TEST(LidarDenoising, RadiusZeroKeepsPositionsAndBadOptionsThrow) {
  CreaseCloud cloud = MakeCreaseCloud();
  const std::vector<uint32_t> counts(cloud.positions.size(), 1);
  std::vector<Eigen::Vector3d> positions = cloud.positions;
  LidarDenoisingOptions options;
  options.radius_m = 0;
  EXPECT_EQ(DenoiseLidarVoxels(options, counts, 1, &positions).num_projected,
            0u);
  EXPECT_EQ(positions, cloud.positions);
  options.radius_m = 0.1;
  options.min_neighbors = 2;
  EXPECT_THROW(DenoiseLidarVoxels(options, counts, 1, &positions), Error);
  options.min_neighbors = 8;
  const std::vector<uint32_t> short_counts(3, 1);
  EXPECT_THROW(DenoiseLidarVoxels(options, short_counts, 1, &positions),
               Error);
}

}  // namespace
}  // namespace colmap_lidar
