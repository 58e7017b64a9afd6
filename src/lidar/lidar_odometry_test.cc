#include "src/lidar/lidar_odometry.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"
#include "src/lidar/lidar_test_scene.h"

namespace colmap_lidar {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The street scene of lidar_test_scene.h at 30 points per square metre.
std::vector<Eigen::Vector3d> SampleScene(unsigned seed) {
  return SampleStreetScene(seed, 30.0);
}

// The scene as seen from `world_from_lidar` (LIDAR frame, all points).
LidarScan MakeScan(const std::vector<Eigen::Vector3d>& points_in_world,
                   const Rigid3d& world_from_lidar) {
  const Rigid3d lidar_from_world = world_from_lidar.Inverse();
  LidarScan scan;
  for (const Eigen::Vector3d& point : points_in_world) {
    scan.points.push_back((lidar_from_world * point).cast<float>());
  }
  return scan;
}

Rigid3d KnownMotion() {
  const Eigen::Quaterniond rotation =
      Eigen::AngleAxisd(3.0 * kPi / 180, Eigen::Vector3d::UnitZ()) *
      Eigen::AngleAxisd(0.5 * kPi / 180, Eigen::Vector3d::UnitX());
  return Rigid3d(rotation, Eigen::Vector3d(0.7, 0.25, 0.05));
}

LidarOdometryOptions SyntheticOptions() {
  LidarOdometryOptions options;
  options.voxel_size_m = 0.25;
  options.min_range_m = 1.0;
  return options;
}

TEST(LidarOdometryOptions, Check) {
  EXPECT_TRUE(LidarOdometryOptions().Check());
  LidarOdometryOptions options;
  options.method = "icp";
  EXPECT_FALSE(options.Check());
  options = LidarOdometryOptions();
  options.voxel_size_m = 0;
  EXPECT_FALSE(options.Check());
  options = LidarOdometryOptions();
  options.min_range_m = 90;
  EXPECT_FALSE(options.Check());
  options = LidarOdometryOptions();
  options.local_map_num_scans = 0;
  EXPECT_FALSE(options.Check());
  options = LidarOdometryOptions();
  options.min_overlap = 1.5;
  EXPECT_FALSE(options.Check());
  options = LidarOdometryOptions();
  options.gicp_num_neighbors = 2;
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(LidarOdometry odometry(options), Error);
}

TEST(LidarOdometry, GicpRecoversKnownMotion) {
  const Rigid3d world_from_first(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(10, -3, 1));
  const Rigid3d world_from_second = world_from_first * KnownMotion();
  const std::vector<LidarScan> scans = {
      MakeScan(SampleScene(1), world_from_first),
      MakeScan(SampleScene(2), world_from_second)};
  const std::vector<LidarOdometryFrame> frames =
      RunLidarOdometry(scans, {"a", "b"}, SyntheticOptions(), world_from_first);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_LT((frames[0].world_from_lidar.translation -
             world_from_first.translation)
                .norm(),
            1e-9);
  EXPECT_LT(RotationErrorDeg(frames[0].world_from_lidar, world_from_first),
            1e-6);
  EXPECT_TRUE(frames[1].registered);
  EXPECT_GT(frames[1].overlap, 0.9);
  // Point-to-point distance between independently sampled and
  // downsampled scans: about half a voxel.
  EXPECT_LT(frames[1].rmse_m, 0.2);
  EXPECT_GT(frames[1].num_points, 1000u);
  EXPECT_LT((frames[1].world_from_lidar.translation -
             world_from_second.translation)
                .norm(),
            0.01);
  EXPECT_LT(RotationErrorDeg(frames[1].world_from_lidar, world_from_second),
            0.1);
}

TEST(LidarOdometry, NdtRecoversKnownMotion) {
  const Rigid3d world_from_second = KnownMotion();
  const std::vector<LidarScan> scans = {
      MakeScan(SampleScene(3), Rigid3d()),
      MakeScan(SampleScene(4), world_from_second)};
  LidarOdometryOptions options = SyntheticOptions();
  options.method = "ndt";
  const std::vector<LidarOdometryFrame> frames =
      RunLidarOdometry(scans, {}, options);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_TRUE(frames[1].registered);
  EXPECT_LT((frames[1].world_from_lidar.translation -
             world_from_second.translation)
                .norm(),
            0.03);
  EXPECT_LT(RotationErrorDeg(frames[1].world_from_lidar, world_from_second),
            0.3);
}

// Constant motion of 1.2 m per frame, more than the correspondence
// distance: the later frames need the constant-velocity prediction.
TEST(LidarOdometry, TracksASequence) {
  const Rigid3d step(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(1.2, 0.0, 0.0));
  std::vector<Rigid3d> truth = {Rigid3d(Eigen::Quaterniond::Identity(),
                                        Eigen::Vector3d(-4, 0, 0))};
  truth.push_back(truth.back() * Rigid3d(step.rotation,
                                         Eigen::Vector3d(0.6, 0, 0)));
  for (int i = 0; i < 4; ++i) {
    truth.push_back(truth.back() * step);
  }
  std::vector<LidarScan> scans;
  for (size_t i = 0; i < truth.size(); ++i) {
    scans.push_back(MakeScan(SampleScene(10 + i), truth[i]));
  }
  LidarOdometryOptions options = SyntheticOptions();
  options.local_map_num_scans = 3;
  const std::vector<LidarOdometryFrame> frames =
      RunLidarOdometry(scans, {}, options, truth[0]);
  ASSERT_EQ(frames.size(), truth.size());
  for (size_t i = 0; i < truth.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_TRUE(frames[i].registered);
    EXPECT_LT(
        (frames[i].world_from_lidar.translation - truth[i].translation).norm(),
        0.02);
    EXPECT_LT(RotationErrorDeg(frames[i].world_from_lidar, truth[i]), 0.2);
  }
}

// A second scan of an unrelated place: no overlap with the map.
TEST(LidarOdometry, FailedRegistrationThrowsOrKeepsPrediction) {
  std::vector<LidarScan> scans = {MakeScan(SampleScene(5), Rigid3d())};
  LidarScan elsewhere;
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> coordinate(-5.0f, 5.0f);
  for (int i = 0; i < 20000; ++i) {
    elsewhere.points.emplace_back(40.0f + coordinate(rng), coordinate(rng),
                                  30.0f + coordinate(rng));
  }
  scans.push_back(elsewhere);
  LidarOdometryOptions options = SyntheticOptions();
  try {
    RunLidarOdometry(scans, {"first", "second_frame"}, options);
    ADD_FAILURE() << "expected an Error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("second_frame"),
              std::string::npos)
        << error.what();
  }
  options.abort_on_failure = false;
  const std::vector<LidarOdometryFrame> frames =
      RunLidarOdometry(scans, {}, options);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_FALSE(frames[1].registered);
  EXPECT_LT(frames[1].overlap, options.min_overlap);
  EXPECT_LT(frames[1].world_from_lidar.translation.norm(), 1e-9);
}

TEST(LidarOdometry, ThrowsOnEmptyScan) {
  LidarScan near;
  near.points.assign(100, Eigen::Vector3f(0.1f, 0.0f, 0.0f));
  LidarOdometry odometry(SyntheticOptions());
  try {
    odometry.AddScan(near, "tiny.bin");
    ADD_FAILURE() << "expected an Error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("tiny.bin"), std::string::npos);
  }
}

}  // namespace
}  // namespace colmap_lidar
