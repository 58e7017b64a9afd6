#include "src/lidar/free_space_filter.h"

#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"
#include "src/lidar/lidar_fusion.h"

namespace colmap_lidar {
namespace {

struct Box {
  Eigen::Vector3d min;
  Eigen::Vector3d max;
};

// Distance along the unit ray origin + t dir to the nearest of the ground
// plane z = 0 and the boxes (slab test), or nothing within max_range.
std::optional<double> CastRay(const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& dir,
                              const std::vector<Box>& boxes,
                              double max_range) {
  double best = std::numeric_limits<double>::infinity();
  if (dir.z() < -1e-9) {
    best = -origin.z() / dir.z();
  }
  for (const Box& box : boxes) {
    double t_near = 0.0;
    double t_far = std::numeric_limits<double>::infinity();
    bool hit = true;
    for (int k = 0; k < 3 && hit; ++k) {
      if (std::abs(dir[k]) < 1e-12) {
        hit = origin[k] >= box.min[k] && origin[k] <= box.max[k];
        continue;
      }
      double t0 = (box.min[k] - origin[k]) / dir[k];
      double t1 = (box.max[k] - origin[k]) / dir[k];
      if (t0 > t1) std::swap(t0, t1);
      t_near = std::max(t_near, t0);
      t_far = std::min(t_far, t1);
      hit = t_near <= t_far;
    }
    if (hit && t_near > 0) {
      best = std::min(best, t_near);
    }
  }
  if (!(best <= max_range)) {
    return std::nullopt;
  }
  return best;
}

// A spinning LIDAR at `origin` (world axes): num_rings beams equally
// spaced over [-15, 15] deg, one return every 0.2 deg of azimuth.
LidarScan RingScan(const Eigen::Vector3d& origin, const std::vector<Box>& boxes,
                   int num_rings = 16) {
  LidarScan scan;
  for (int ring = 0; ring < num_rings; ++ring) {
    const double elevation =
        (-15.0 + 30.0 * ring / (num_rings - 1)) * M_PI / 180.0;
    for (int step = 0; step < 1800; ++step) {
      const double azimuth = step * 0.2 * M_PI / 180.0;
      const Eigen::Vector3d dir(std::cos(elevation) * std::cos(azimuth),
                                std::cos(elevation) * std::sin(azimuth),
                                std::sin(elevation));
      const std::optional<double> range = CastRay(origin, dir, boxes, 80.0);
      if (range) {
        scan.points.push_back((*range * dir).cast<float>());
        scan.rings.push_back(static_cast<uint16_t>(ring));
      }
    }
  }
  return scan;
}

Rigid3d At(const Eigen::Vector3d& origin) {
  Rigid3d world_from_lidar;
  world_from_lidar.translation = origin;
  return world_from_lidar;
}

const Box kWall{{20, -30, 0}, {21, 30, 10}};
const Box kParkedCar{{6, -6, 0}, {10, -4, 1.5}};
const Box kPassingCar{{6, -1, 0}, {10, 1, 1.5}};

TEST(FreeSpaceFilter, RingGapIsTheBeamSpacing) {
  const LidarScan scan = RingScan({0, 0, 1.7}, {kWall}, 16);
  EXPECT_NEAR(EstimateRingGapDeg(scan), 2.0, 0.01);
  const LidarScan dense = RingScan({0, 0, 1.7}, {kWall}, 61);
  EXPECT_NEAR(EstimateRingGapDeg(dense), 0.5, 0.01);
  EXPECT_EQ(EstimateRingGapDeg(LidarScan()), 0.0);
}

TEST(FreeSpaceFilter, RangeImageGivesTheNearestReturnAround) {
  const LidarScan scan = RingScan({0, 0, 1.7}, {kWall}, 16);
  // Cells of 1 deg, the min filter over +-3 cells (1.5 ring gaps).
  const SphericalRangeImage image(scan, 0.5, 80.0, 1.0, 3);
  // Straight ahead at the sensor's height: the wall at 20 m (the rings at
  // +-1 deg hit it at 20.0x m).
  EXPECT_NEAR(image.NearestRangeAround({15, 0, 0}), 20.0, 0.01);
  // Above the highest ring: no evidence.
  EXPECT_LT(image.NearestRangeAround({1, 0, 1}), 0.0);
  // Between two rings, along the ground at 10 m (about -9.8 deg, rings at
  // -9 and -11): the nearer neighbour counts, not the farther one.
  const double ground_10m =
      image.NearestRangeAround({10, 0, -1.7});
  EXPECT_GT(ground_10m, 0.0);
  EXPECT_LT(ground_10m, std::hypot(10.0, 1.7));
}

// Three scans along x; the passing car is in the first scan only, the
// parked car in all three.
struct Scene {
  std::vector<LidarScan> scans;
  std::vector<Eigen::Vector3d> origins = {{0, 0, 1.7}, {1, 0, 1.7},
                                          {2, 0, 1.7}};
  Scene() {
    scans.push_back(RingScan(origins[0], {kWall, kParkedCar, kPassingCar}));
    scans.push_back(RingScan(origins[1], {kWall, kParkedCar}));
    scans.push_back(RingScan(origins[2], {kWall, kParkedCar}));
  }
  std::vector<LidarFusionInput> Inputs() const {
    std::vector<LidarFusionInput> inputs(scans.size());
    for (size_t i = 0; i < scans.size(); ++i) {
      inputs[i].image_idx = static_cast<uint32_t>(i);
      inputs[i].scan = &scans[i];
      inputs[i].world_from_lidar = At(origins[i]);
    }
    return inputs;
  }
};

bool Inside(const Eigen::Vector3f& p, const Box& box, double pad) {
  const Eigen::Vector3d q = p.cast<double>();
  return (q.array() >= box.min.array() - pad).all() &&
         (q.array() <= box.max.array() + pad).all();
}

struct Census {
  // The passing car above 0.6 m, and below: within 1.5 ring gaps of the
  // ground at its distance (+-3 deg at 6-9 m is +-0.3-0.5 m), where the
  // ground's nearer returns hide what lies behind it.
  int passing = 0;
  int passing_low = 0;
  int parked = 0;
  int wall = 0;
  int ground = 0;
};

Census Count(const FusedLidarCloud& cloud) {
  Census census;
  for (const Eigen::Vector3f& p : cloud.points) {
    if (Inside(p, kPassingCar, 0.05) && p.z() > 0.6) {
      ++census.passing;
    } else if (Inside(p, kPassingCar, 0.05) && p.z() > 0.1) {
      ++census.passing_low;
    } else if (Inside(p, kParkedCar, 0.05) && p.z() > 0.1) {
      ++census.parked;
    } else if (Inside(p, kWall, 0.05)) {
      ++census.wall;
    } else if (std::abs(p.z()) < 0.05) {
      ++census.ground;
    }
  }
  return census;
}

TEST(FreeSpaceFilter, FusionDropsTheCarThatLeftAndKeepsTheStaticScene) {
  const Scene scene;
  LidarFusionOptions options;
  options.free_space.enabled = false;
  const Census all = Count(FuseLidarScans(scene.Inputs(), options));
  ASSERT_GT(all.passing, 100);
  ASSERT_GT(all.passing_low, 20);
  ASSERT_GT(all.parked, 100);
  ASSERT_GT(all.wall, 1000);
  ASSERT_GT(all.ground, 1000);

  options.free_space.enabled = true;
  const Census kept = Count(FuseLidarScans(scene.Inputs(), options));
  // The passing car's body is seen through by both later scans (their
  // rays reach the ground and the wall behind it). Its lower part stays
  // in part: the ground's returns lie within the margin there.
  EXPECT_LT(kept.passing, all.passing / 20);
  EXPECT_LE(kept.passing_low, all.passing_low);
  // Nothing static is lost: not the parked car, not the wall, not the
  // ground the passing car hid in the first scan (hidden is not seen
  // through), not the ground at grazing angles between two rings.
  EXPECT_EQ(kept.parked, all.parked);
  EXPECT_EQ(kept.wall, all.wall);
  EXPECT_EQ(kept.ground, all.ground);
}

TEST(FreeSpaceFilter, OneScanOrDisabledDropsNothing) {
  const Scene scene;
  const std::vector<Eigen::Vector3d> centroids = {{8, 0, 1.5}};
  const std::vector<std::vector<uint32_t>> hits = {{0}};
  std::vector<FreeSpaceScan> scans = {{&scene.scans[0], At(scene.origins[0])},
                                      {&scene.scans[1], At(scene.origins[1])},
                                      {&scene.scans[2], At(scene.origins[2])}};
  FreeSpaceFilterOptions options;
  EXPECT_TRUE(FindMovingVoxels(centroids, hits, scans, 0.05, 0.5, 80.0,
                               options)[0]);
  // Two scans see through it and one hits it; three are needed.
  options.min_see_through_frames = 3;
  EXPECT_FALSE(FindMovingVoxels(centroids, hits, scans, 0.05, 0.5, 80.0,
                                options)[0]);
  options = FreeSpaceFilterOptions();
  options.enabled = false;
  EXPECT_FALSE(FindMovingVoxels(centroids, hits, scans, 0.05, 0.5, 80.0,
                                options)[0]);
  scans.resize(1);
  EXPECT_FALSE(FindMovingVoxels(centroids, hits, scans, 0.05, 0.5, 80.0,
                                FreeSpaceFilterOptions())[0]);
}

// A scan that returns from a sphere of `radius` around its origin (every
// direction of 16 rings over [-15, 15] deg, one return every 0.2 deg).
LidarScan SphereScan(double radius) {
  LidarScan scan;
  for (int ring = 0; ring < 16; ++ring) {
    const double elevation = (-15.0 + 2.0 * ring) * M_PI / 180.0;
    for (int step = 0; step < 1800; ++step) {
      const double azimuth = step * 0.2 * M_PI / 180.0;
      scan.points.push_back(
          (radius * Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
                                    std::cos(elevation) * std::sin(azimuth),
                                    std::sin(elevation)))
              .cast<float>());
      scan.rings.push_back(static_cast<uint16_t>(ring));
    }
  }
  return scan;
}

TEST(FreeSpaceFilter, EveryScanWithinRangeDecidesOnALongRecording) {
  // 60 scans over a 400 m x 80 m area, 2000 empty voxels among them: a scan
  // sees through a voxel exactly when the voxel lies within [min_range,
  // max_range] of it and more than the margin before its sphere. The filter
  // only tests the scans whose origin is near the voxel (a grid of 21 m
  // cells here); none that decides may be left out, wherever the voxel lies
  // in its cell.
  const double radius = 19.9;
  const double min_range = 0.5;
  const double max_range = 20.0;
  const double voxel_size = 0.05;
  const double margin = FreeSpaceFilterOptions().margin_voxels * voxel_size;
  const LidarScan sphere = SphereScan(radius);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(-200.0, 200.0);
  std::uniform_real_distribution<double> y(-40.0, 40.0);
  std::vector<Eigen::Vector3d> origins;
  std::vector<FreeSpaceScan> scans;
  for (int k = 0; k < 60; ++k) {
    origins.emplace_back(x(rng), y(rng), 0.0);
  }
  for (const Eigen::Vector3d& origin : origins) {
    scans.push_back({&sphere, At(origin)});
  }
  std::vector<Eigen::Vector3d> centroids;
  std::vector<int> expected_counts;
  while (centroids.size() < 2000) {
    const Eigen::Vector3d c(x(rng), y(rng), 0.0);
    int count = 0;
    bool borderline = false;
    for (const Eigen::Vector3d& origin : origins) {
      const double d = (c - origin).norm();
      borderline |= std::abs(d - min_range) < 0.01 ||
                    std::abs(d - (radius - margin)) < 0.01;
      count += d >= min_range && d < radius - margin;
    }
    if (borderline) continue;
    centroids.push_back(c);
    expected_counts.push_back(count);
  }
  const std::vector<std::vector<uint32_t>> hits(centroids.size());
  for (const int min_frames : {1, 2, 3}) {
    FreeSpaceFilterOptions options;
    options.min_see_through_frames = min_frames;
    const std::vector<bool> moving = FindMovingVoxels(
        centroids, hits, scans, voxel_size, min_range, max_range, options);
    int num_moving = 0;
    for (size_t v = 0; v < centroids.size(); ++v) {
      EXPECT_EQ(moving[v], expected_counts[v] >= min_frames)
          << "voxel " << centroids[v].transpose() << ", " << expected_counts[v]
          << " scans within range, min " << min_frames;
      num_moving += moving[v];
    }
    // Neither all nor none: the counts straddle the thresholds.
    EXPECT_GT(num_moving, 100);
    EXPECT_LT(num_moving, 1900);
  }
}

TEST(FreeSpaceFilter, BadOptionsAndInputsThrow) {
  FreeSpaceFilterOptions options;
  EXPECT_TRUE(options.Check());
  options.margin_voxels = 0;
  EXPECT_FALSE(options.Check());
  options = FreeSpaceFilterOptions();
  options.neighborhood_ring_gaps = -1;
  EXPECT_FALSE(options.Check());
  options = FreeSpaceFilterOptions();
  options.min_see_through_frames = 0;
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(FindMovingVoxels({{0, 0, 0}}, {}, {}, 0.05, 0.5, 80.0,
                                FreeSpaceFilterOptions()),
               Error);
  LidarFusionOptions fusion;
  fusion.free_space.margin_voxels = -1;
  EXPECT_FALSE(fusion.Check());
}

}  // namespace
}  // namespace colmap_lidar
