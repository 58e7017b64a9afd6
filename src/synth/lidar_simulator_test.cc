#include "src/synth/lidar_simulator.h"

#include <cmath>
#include <set>
#include <string>
#include <vector>

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

// A closed 40 x 40 x 20 m room around the sensor at the origin: every beam
// of every model hits a wall, the floor or the ceiling.
struct RoomFixture {
  SceneMesh mesh = [] {
    SceneBuilder builder;
    builder.AddBox({-20, -20, -10}, {20, 20, 10}, Material::kConcrete, 0,
                   false);
    return builder.mesh();
  }();
  RayTracer tracer{mesh};
};

// The sensor off the room's symmetry axes (no beam along a box edge, where
// Embree may miss between two triangles).
Rigid3d RoomPose(double z = 0.13) {
  Rigid3d pose;
  pose.translation = Eigen::Vector3d(0.37, -0.21, z);
  return pose;
}

double ElevationDeg(const Eigen::Vector3f& point) {
  const Eigen::Vector3d direction = point.cast<double>().normalized();
  return std::asin(direction.z()) * 180.0 / M_PI;
}

TEST(LidarSimulator, ModelsHaveTheirRingsElevationsAndColumns) {
  RoomFixture room;
  struct Expected {
    std::string model;
    int rings;
    double min_deg;
    double max_deg;
    int columns;
  };
  const std::vector<Expected> models = {
      {"VLP-16", 16, -15.0, 15.0, 1800},
      {"HDL-32E", 32, -30.67, 10.67, 2172},
      {"OS1-64", 64, -16.6, 16.6, 1024},
      {"HDL-64E", 64, -24.9, 2.0, 2048},
      {"OS1-128", 128, -22.5, 22.5, 1024},
      {"custom", 8, -5.0, 25.0, 100}};
  for (const Expected& expected : models) {
    SCOPED_TRACE(expected.model);
    SynthesisOptions options;
    options.lidar_model = expected.model;
    if (expected.model == "custom") {
      options.lidar_rings = 8;
      options.lidar_columns = 100;
      options.lidar_vertical_fov_min_deg = -5.0;
      options.lidar_vertical_fov_max_deg = 25.0;
    }
    options.lidar_range_noise_m = 0.0;
    options.num_threads = 2;
    ASSERT_TRUE(options.Check());
    const LidarGeometry geometry = SynthLidarGeometry(options);
    EXPECT_EQ(geometry.ring_elevations_deg.size(),
              static_cast<size_t>(expected.rings));
    EXPECT_EQ(geometry.columns, expected.columns);
    const LidarScan scan =
        SimulateLidarScan(room.tracer, RoomPose(), options, 0);
    // All beams return, ordered by column then ring.
    ASSERT_EQ(scan.size(),
              static_cast<size_t>(expected.rings) * expected.columns);
    std::vector<double> ring_min(expected.rings, 1e9);
    std::vector<double> ring_max(expected.rings, -1e9);
    std::set<long> azimuth_steps;
    for (size_t i = 0; i < scan.size(); ++i) {
      const int ring = scan.rings[i];
      ASSERT_LT(ring, expected.rings);
      EXPECT_EQ(ring, static_cast<int>(i % expected.rings));
      const double elevation = ElevationDeg(scan.points[i]);
      ring_min[ring] = std::min(ring_min[ring], elevation);
      ring_max[ring] = std::max(ring_max[ring], elevation);
      if (ring == 0) {
        const double azimuth =
            std::atan2(scan.points[i].y(), scan.points[i].x());
        azimuth_steps.insert(std::lround(
            (azimuth < 0 ? azimuth + 2 * M_PI : azimuth) / (2 * M_PI) *
            expected.columns) % expected.columns);
      }
    }
    EXPECT_EQ(azimuth_steps.size(), static_cast<size_t>(expected.columns));
    EXPECT_NEAR(ring_min.front(), expected.min_deg, 1e-3);
    EXPECT_NEAR(ring_max.back(), expected.max_deg, 1e-3);
    for (int ring = 0; ring < expected.rings; ++ring) {
      // One elevation per ring (float precision of the points).
      EXPECT_NEAR(ring_min[ring], ring_max[ring], 1e-3) << ring;
      EXPECT_NEAR(ring_min[ring], geometry.ring_elevations_deg[ring], 1e-3);
      if (ring > 0) {
        EXPECT_GT(ring_min[ring], ring_max[ring - 1]) << ring;
      }
    }
    if (expected.model == "HDL-64E") {
      // Two uniform blocks: 0.517 deg spacing below, 0.333 deg above.
      EXPECT_NEAR(ring_min[31], -8.87, 1e-3);
      EXPECT_NEAR(ring_min[32], -8.33, 1e-3);
      EXPECT_NEAR(ring_min[1] - ring_min[0], (24.9 - 8.87) / 31, 1e-3);
      EXPECT_NEAR(ring_min[63] - ring_min[62], (8.33 + 2.0) / 31, 1e-3);
    }
  }
}

TEST(LidarSimulator, NamedModelsRejectCustomLayoutOptions) {
  SynthesisOptions options;
  options.lidar_model = "VLP-16";
  EXPECT_TRUE(options.Check());
  options.lidar_rings = 32;
  EXPECT_FALSE(options.Check());
  options.lidar_model = "custom";
  EXPECT_TRUE(options.Check());
  options.lidar_model = "HDL-128";
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(SynthLidarGeometry(options), Error);
  options = SynthesisOptions();
  options.lidar_dropout_probability = 1.0;
  EXPECT_FALSE(options.Check());
  options.lidar_dropout_probability = -0.1;
  EXPECT_FALSE(options.Check());
  options = SynthesisOptions();
  options.lidar_grazing_dropout = 1.5;
  EXPECT_FALSE(options.Check());
}

// |cos| of the angle between the beam from the sensor and the normal of the
// room face that the world point lies on.
double CosIncidence(const Eigen::Vector3f& point_in_world,
                    const Rigid3d& world_from_lidar) {
  const Eigen::Vector3d p = point_in_world.cast<double>();
  const Eigen::Vector3d scaled(std::abs(p.x()) / 20.0, std::abs(p.y()) / 20.0,
                               std::abs(p.z()) / 10.0);
  int axis = 0;
  scaled.maxCoeff(&axis);
  const Eigen::Vector3d beam = p - world_from_lidar.translation;
  return std::abs(beam(axis)) / beam.norm();
}

TEST(LidarSimulator, DropoutRemovesTheRequestedShareDeterministically) {
  RoomFixture room;
  SynthesisOptions options;
  options.lidar_model = "VLP-16";
  options.num_threads = 2;
  const size_t num_beams = 16 * 1800;
  const LidarScan full = SimulateLidarScan(room.tracer, RoomPose(), options, 3);
  ASSERT_EQ(full.size(), num_beams);
  for (const double probability : {0.05, 0.2, 0.5}) {
    options.lidar_dropout_probability = probability;
    const LidarScan a = SimulateLidarScan(room.tracer, RoomPose(), options, 3);
    const LidarScan b = SimulateLidarScan(room.tracer, RoomPose(), options, 3);
    const LidarScan c = SimulateLidarScan(room.tracer, RoomPose(), options, 4);
    // Binomial std of the share is <= 0.003 for 28800 beams.
    EXPECT_NEAR(1.0 - static_cast<double>(a.size()) / num_beams, probability,
                0.012);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a.points[i], b.points[i]);
    EXPECT_NE(a.size(), c.size());
  }
  // Grazing dropout: returns at a low |cos incidence| are lost more often.
  // The sensor 0.5 m above the floor sees it at grazing angles.
  const Rigid3d near_floor = RoomPose(-9.5);
  options.lidar_dropout_probability = 0.0;
  const LidarScan full_near_floor =
      SimulateLidarScan(room.tracer, near_floor, options, 3);
  options.lidar_grazing_dropout = 1.0;
  const LidarScan grazing =
      SimulateLidarScan(room.tracer, near_floor, options, 3);
  const auto count_by_cos = [&](const LidarScan& scan, double lo, double hi) {
    int count = 0;
    for (const Eigen::Vector3f& point : scan.points) {
      const double cosine = CosIncidence(
          (near_floor * point.cast<double>()).cast<float>(), near_floor);
      count += (cosine >= lo && cosine < hi) ? 1 : 0;
    }
    return count;
  };
  ASSERT_GT(count_by_cos(full_near_floor, 0.0, 0.3), 1000);
  ASSERT_GT(count_by_cos(full_near_floor, 0.9, 1.01), 1000);
  const double kept_low = static_cast<double>(count_by_cos(grazing, 0.0, 0.3)) /
                          count_by_cos(full_near_floor, 0.0, 0.3);
  const double kept_high =
      static_cast<double>(count_by_cos(grazing, 0.9, 1.01)) /
      count_by_cos(full_near_floor, 0.9, 1.01);
  EXPECT_LT(kept_low, 0.4);
  EXPECT_GT(kept_high, 0.88);
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
