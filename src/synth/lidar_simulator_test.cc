#include "src/synth/lidar_simulator.h"

#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "src/synth/scene_presets.h"
#include "src/synth/synthesize.h"
#include "src/synth/trajectory.h"

namespace colmap_lidar {
namespace {

struct LidarFixture {
  SynthScene scene = BuildQuadScene();
  RayTracer tracer{scene.mesh};
  std::vector<Rigid3d> poses = GenerateTrajectory(scene.path, 60, 0);
  Rigid3d WorldFromLidar(int frame) const {
    return poses[frame] * SynthCamFromLidar();
  }
};

TEST(LidarSimulator, NoiselessPointsLieOnTheSurfaces) {
  LidarFixture fixture;
  SynthesisOptions options;
  options.lidar_range_noise_m = 0.0;
  options.num_threads = 2;
  const Rigid3d world_from_lidar = fixture.WorldFromLidar(5);
  const LidarScan scan =
      SimulateLidarScan(fixture.tracer, world_from_lidar, options, 5);
  // Enclosed courtyard: only upper beams escape over the roofs.
  EXPECT_GT(scan.size(), 0.6 * 64 * 1024);
  ASSERT_EQ(scan.rings.size(), scan.size());
  ASSERT_EQ(scan.intensities.size(), scan.size());
  for (size_t i = 0; i < scan.size(); i += 97) {
    const Eigen::Vector3d point_in_world =
        world_from_lidar * scan.points[i].cast<double>();
    EXPECT_LT(fixture.tracer.DistanceToSurface(point_in_world), 1e-4) << i;
    // The beam's elevation identifies its ring.
    const Eigen::Vector3d direction = scan.points[i].cast<double>().normalized();
    const double elevation_deg = std::asin(direction.z()) * 180.0 / M_PI;
    const double expected_deg = -16.6 + 33.2 * scan.rings[i] / 63.0;
    EXPECT_NEAR(elevation_deg, expected_deg, 1e-3);
    EXPECT_GE(scan.intensities[i], 0.0f);
    EXPECT_LE(scan.intensities[i], 1.0f);
  }
  std::set<uint16_t> rings(scan.rings.begin(), scan.rings.end());
  EXPECT_EQ(rings.size(), 64u);
}

TEST(LidarSimulator, RangeNoiseHasTheConfiguredStd) {
  LidarFixture fixture;
  SynthesisOptions options;
  options.num_threads = 2;
  const Rigid3d world_from_lidar = fixture.WorldFromLidar(20);
  const LidarScan scan =
      SimulateLidarScan(fixture.tracer, world_from_lidar, options, 20);
  double sum = 0.0;
  double sum_sq = 0.0;
  int n = 0;
  for (size_t i = 0; i < scan.size(); ++i) {
    const Eigen::Vector3d point = scan.points[i].cast<double>();
    const Eigen::Vector3d direction_in_world =
        world_from_lidar.rotation * point.normalized();
    const RayHit hit = fixture.tracer.Intersect(
        world_from_lidar.translation, direction_in_world, 0.5, 100.0);
    ASSERT_TRUE(hit.Valid());
    const double residual = point.norm() - hit.distance;
    sum += residual;
    sum_sq += residual * residual;
    ++n;
    if (i % 211 == 0) {
      EXPECT_LT(fixture.tracer.DistanceToSurface(world_from_lidar * point),
                6 * 0.015);
    }
  }
  ASSERT_GT(n, 50000);
  EXPECT_NEAR(sum / n, 0.0, 1e-3);
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.015, 0.0005);
}

TEST(LidarSimulator, DeterministicPerSeedAndFrame) {
  LidarFixture fixture;
  SynthesisOptions options;
  options.lidar_rings = 16;
  options.lidar_columns = 256;
  const Rigid3d pose = fixture.WorldFromLidar(0);
  options.num_threads = 2;
  const LidarScan a = SimulateLidarScan(fixture.tracer, pose, options, 0);
  options.num_threads = 1;
  const LidarScan b = SimulateLidarScan(fixture.tracer, pose, options, 0);
  const LidarScan c = SimulateLidarScan(fixture.tracer, pose, options, 1);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), c.size());
  int num_different = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.points[i], b.points[i]);
    num_different += (a.points[i] != c.points[i]) ? 1 : 0;
  }
  EXPECT_GT(num_different, static_cast<int>(a.size()) / 2);
}

TEST(LidarSimulator, SurveySeesOnlyVisibleSurfacesAtVoxelSpacing) {
  LidarFixture fixture;
  SynthesisOptions options;
  options.survey_angular_step_deg = 0.5;
  options.survey_voxel_size_m = 0.1;
  options.survey_range_noise_m = 0.0;
  options.num_threads = 2;
  const std::vector<Eigen::Vector3d> stations = {{-8, -4, 1.5}, {8, 4, 1.5}};
  const std::vector<Eigen::Vector3f> points =
      SimulateSurvey(fixture.tracer, stations, options);
  ASSERT_GT(points.size(), 10000u);
  std::set<std::tuple<int, int, int>> voxels;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d p = points[i].cast<double>();
    voxels.insert({static_cast<int>(std::floor(p.x() / 0.1)),
                   static_cast<int>(std::floor(p.y() / 0.1)),
                   static_cast<int>(std::floor(p.z() / 0.1))});
    // Inside the courtyard walls or on them (recesses are at most 0.2 m
    // deep); beyond them only the side walls of taller buildings above the
    // lower roofs (8 m at least) are visible: no roofs, no building backs.
    if (std::abs(p.x()) > 15.21 || std::abs(p.y()) > 10.21) {
      EXPECT_GT(p.z(), 8.0) << p.transpose();
    }
    if (i % 53 == 0) {
      EXPECT_LT(fixture.tracer.DistanceToSurface(p), 1e-4);
    }
  }
  EXPECT_EQ(voxels.size(), points.size());
  options.survey_max_points = 5000;
  EXPECT_EQ(SimulateSurvey(fixture.tracer, stations, options).size(), 5000u);
}

}  // namespace
}  // namespace colmap_lidar
