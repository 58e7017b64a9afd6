#include "src/sfm/lidar_point_planes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace colmap_lidar {
namespace {

constexpr double kRangeNoiseM = 0.01;

// The synthesizer's rig: LIDAR x forward, y left, z up; camera x right, y
// down, z forward; the LIDAR 0.1 m above and 0.04 m behind the camera.
Rigid3d CamFromLidar() {
  Eigen::Matrix3d rotation;
  rotation << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  return Rigid3d(Eigen::Quaterniond(rotation), Eigen::Vector3d(0, -0.1, -0.04));
}

// A 16-ring scanner (-15 .. 15 deg, 0.2 deg in azimuth over +-60 deg) in
// front of a wall at x = 6 m over a floor at z = -1 m (its lowest three
// rings land on it), with 1 cm range noise, and a bush (points at random in
// a 1 m cube around (4, -2, -0.3)).
LidarScan MakeScan() {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, kRangeNoiseM);
  std::uniform_real_distribution<double> uniform(-0.5, 0.5);
  LidarScan scan;
  for (int ring = 0; ring < 16; ++ring) {
    const double elevation = (-15.0 + 2.0 * ring) * M_PI / 180.0;
    for (double azimuth_deg = -60.0; azimuth_deg <= 60.0; azimuth_deg += 0.2) {
      const double azimuth = azimuth_deg * M_PI / 180.0;
      const Eigen::Vector3d direction(std::cos(elevation) * std::cos(azimuth),
                                      std::cos(elevation) * std::sin(azimuth),
                                      std::sin(elevation));
      double range = 6.0 / direction.x();
      if (direction.z() < 0.0) {
        range = std::min(range, -1.0 / direction.z());
      }
      scan.points.push_back(((range + noise(rng)) * direction).cast<float>());
    }
  }
  for (int k = 0; k < 3000; ++k) {
    scan.points.push_back(Eigen::Vector3f(
        4.0 + uniform(rng), -2.0 + uniform(rng), -0.3 + uniform(rng)));
  }
  return scan;
}

// One image at the world origin (world = camera frame) observing the given
// points (LIDAR frame), each a one-element track.
Reconstruction MakeModel(const std::vector<Eigen::Vector3d>& points_in_lidar) {
  Reconstruction model;
  Camera camera =
      Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
  camera.camera_id = 1;
  model.cameras[1] = camera;
  Image image;
  image.image_id = 1;
  image.camera_id = 1;
  image.name = "000000.png";
  for (size_t k = 0; k < points_in_lidar.size(); ++k) {
    Point3D point3D;
    point3D.xyz = CamFromLidar() * points_in_lidar[k];
    point3D.track.push_back({1, static_cast<point2D_t>(k)});
    Point2D point2D;
    point2D.xy = camera.ImgFromCam(point3D.xyz);
    point2D.point3D_id = k + 1;
    image.points2D.push_back(point2D);
    model.points3D[k + 1] = point3D;
  }
  model.images.push_back(image);
  return model;
}

LidarPlaneScans MakeScans() {
  std::vector<LidarPlaneScanInput> scans(1);
  scans[0].image_id = 1;
  scans[0].scan = MakeScan();
  scans[0].cam_from_lidar = CamFromLidar();
  return LidarPlaneScans(std::move(scans));
}

TEST(LidarPointPlanes, OptionsCheck) {
  EXPECT_TRUE(LidarPointPlaneOptions().Check());
  LidarPointPlaneOptions options;
  options.min_neighbors = 2;
  EXPECT_FALSE(options.Check());
  options = LidarPointPlaneOptions();
  options.min_spread_fraction = 1.0;
  EXPECT_FALSE(options.Check());
  options = LidarPointPlaneOptions();
  options.num_threads = 0;
  EXPECT_FALSE(options.Check());
}

TEST(LidarPointPlanes, WallPointGetsTheWallPlane) {
  const LidarPlaneScans scans = MakeScans();
  EXPECT_EQ(scans.NumScans(), 1);
  // The range noise is measured, not assumed.
  EXPECT_NEAR(scans.RangeSigma(), kRangeNoiseM, 0.4 * kRangeNoiseM);

  // Points on the wall between rings (the nearest neighbours lie on one
  // ring: the radius must grow to the next), and on the floor.
  const Reconstruction model =
      MakeModel({{6.0, 0.5, 0.3}, {6.0, -1.2, -0.9}, {4.0, 0.5, -1.0}});
  LidarPointPlaneSummary summary;
  const std::vector<PointPlaneObservation> planes =
      scans.Associate(model, 1, LidarPointPlaneOptions(), &summary);
  ASSERT_EQ(planes.size(), 3u);
  EXPECT_EQ(summary.num_observations, 3);
  EXPECT_EQ(summary.num_planes, 3);
  const Eigen::Vector3d wall_normal_in_cam =
      CamFromLidar().rotation * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d floor_normal_in_cam =
      CamFromLidar().rotation * Eigen::Vector3d::UnitZ();
  for (const PointPlaneObservation& plane : planes) {
    const Eigen::Vector3d& point = model.points3D.at(plane.point3D_id).xyz;
    const Eigen::Vector3d& expected =
        plane.point3D_id == 3 ? floor_normal_in_cam : wall_normal_in_cam;
    EXPECT_GT(std::abs(plane.normal_in_cam.dot(expected)), 0.995)
        << "point " << plane.point3D_id;
    EXPECT_NEAR(plane.normal_in_cam.norm(), 1.0, 1e-9);
    // The point lies on the true surface: its residual is the fit's error.
    EXPECT_LT(std::abs(plane.normal_in_cam.dot(point) - plane.offset_m), 0.01)
        << "point " << plane.point3D_id;
    EXPECT_GE(plane.sigma_m, scans.RangeSigma());
    EXPECT_LT(plane.sigma_m, 3.0 * kRangeNoiseM);
    EXPECT_EQ(plane.image_id, 1u);
  }
  EXPECT_GT(summary.median_plane_sigma_m, 0.0);
}

TEST(LidarPointPlanes, NoPlaneOffTheSurfaceInClutterOrBeyondTheScan) {
  const LidarPlaneScans scans = MakeScans();
  const Reconstruction model = MakeModel({
      {5.85, 0.5, 0.3},   // 15 noise sigmas in front of the wall
      {4.0, -2.0, -0.3},  // inside the bush: not flat
      {6.0, 0.5, 3.0},    // on the wall above the top ring (15 deg)
  });
  LidarPointPlaneSummary summary;
  EXPECT_TRUE(
      scans.Associate(model, 1, LidarPointPlaneOptions(), &summary).empty());
  EXPECT_EQ(summary.num_observations, 3);
  EXPECT_EQ(summary.num_planes, 0);

  // A wall point farther than max_range_m, and points seen fewer times than
  // the track length asked for, get none either.
  const Reconstruction wall = MakeModel({{6.0, 0.5, 0.3}});
  LidarPointPlaneOptions options;
  options.max_range_m = 5.0;
  EXPECT_TRUE(scans.Associate(wall, 1, options, nullptr).empty());
  EXPECT_TRUE(
      scans.Associate(wall, 2, LidarPointPlaneOptions(), nullptr).empty());
  // A wider distance gate lets the point in front of the wall in.
  options = LidarPointPlaneOptions();
  options.max_distance_sigmas = 100.0;
  EXPECT_EQ(scans.Associate(MakeModel({{5.85, 0.5, 0.3}}), 1, options, nullptr)
                .size(),
            1u);
}

}  // namespace
}  // namespace colmap_lidar
