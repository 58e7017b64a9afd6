#include "src/lidar/lidar_prior_poses.h"

#include <filesystem>
#include <regex>

#include <gtest/gtest.h>
#include <glog/logging.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/importer.h"

namespace colmap_lidar {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;
constexpr size_t kNumKittiFrames = 20;
// The image that has a prior before the odometry runs (not the first, which
// would anchor the world frame).
constexpr size_t kImageWithPrior = 10;

double AngleDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b) * 180.0 / kPi;
}

Rigid3d FakePrior() {
  return Rigid3d(Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5),
                 Eigen::Vector3d(100, 200, 300));
}

void SetPrior(Database* database, const std::string& name,
              const Rigid3d& world_from_cam) {
  DatabaseImage image = *database->ReadImageWithName(name);
  image.prior_q = world_from_cam.rotation.inverse();
  image.prior_t = world_from_cam.translation;
  database->UpdateImage(image);
}

// The KITTI sample imported (without priors: the recording has none) and
// the odometry run once over it with the default options.
class LidarPriorPosesKittiTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = new std::string(testing::CreateTestDir());
    workspace_ = new std::string(JoinPaths(*root_, "workspace"));
    ImporterOptions import_options;
    import_options.copy_images = false;
    import_options.copy_scans = false;
    const ImportSummary import = ImportDataset(
        testing::KittiSampleDir(), *workspace_, "", import_options);
    ASSERT_EQ(import.num_frames, static_cast<int>(kNumKittiFrames));
    ASSERT_EQ(import.num_frames_with_prior, 0);
    database_path_ = new std::string(import.database_path);
    {
      Database database(*database_path_);
      std::vector<DatabaseImage> images = database.ReadAllImages();
      std::sort(images.begin(), images.end(),
                [](const auto& a, const auto& b) { return a.name < b.name; });
      SetPrior(&database, images.at(kImageWithPrior).name, FakePrior());
    }
    model_path_ = new std::string(JoinPaths(*workspace_, "sparse/odometry"));
    summary_ = new LidarPriorPosesSummary(RunLidarOdometryPriors(
        *database_path_, *model_path_, LidarOdometryOptions(),
        LidarPriorPosesOptions()));
    double max_seconds = 0;
    for (const LidarPriorPose& pose : summary_->poses) {
      max_seconds = std::max(max_seconds, pose.odometry.seconds);
    }
    LOG(INFO) << "KITTI odometry: " << summary_->poses.size() << " frames, "
              << summary_->trajectory_length_m << " m, "
              << summary_->seconds << " s in total, "
              << summary_->seconds / summary_->poses.size()
              << " s per frame (slowest registration " << max_seconds
              << " s)";
  }
  static void TearDownTestSuite() {
    delete summary_;
    delete model_path_;
    delete database_path_;
    delete workspace_;
    delete root_;
  }

  static std::string* root_;
  static std::string* workspace_;
  static std::string* database_path_;
  static std::string* model_path_;
  static LidarPriorPosesSummary* summary_;
};

std::string* LidarPriorPosesKittiTest::root_ = nullptr;
std::string* LidarPriorPosesKittiTest::workspace_ = nullptr;
std::string* LidarPriorPosesKittiTest::database_path_ = nullptr;
std::string* LidarPriorPosesKittiTest::model_path_ = nullptr;
LidarPriorPosesSummary* LidarPriorPosesKittiTest::summary_ = nullptr;

// The sample: the car creeps forward about 3 m in 20 frames on a straight
// road (README of the sample).
TEST_F(LidarPriorPosesKittiTest, TrajectoryIsSmoothAndForward) {
  ASSERT_EQ(summary_->poses.size(), kNumKittiFrames);
  EXPECT_EQ(summary_->num_failed_registrations, 0u);
  EXPECT_EQ(summary_->num_images_without_scan, 0u);
  const std::vector<LidarPriorPose>& poses = summary_->poses;
  // The first camera is the world.
  EXPECT_LT(poses[0].world_from_cam.translation.norm(), 1e-9);
  EXPECT_LT(AngleDeg(poses[0].world_from_cam.rotation,
                     Eigen::Quaterniond::Identity()),
            1e-6);
  for (size_t i = 1; i < poses.size(); ++i) {
    SCOPED_TRACE(poses[i].image_name);
    EXPECT_LT(poses[i - 1].image_name, poses[i].image_name);
    EXPECT_TRUE(poses[i].odometry.registered);
    EXPECT_GT(poses[i].odometry.overlap, 0.8);
    // The step in the previous camera's frame: z forward, y down.
    const Eigen::Vector3d step =
        poses[i - 1].world_from_cam.Inverse() *
        poses[i].world_from_cam.translation;
    EXPECT_GT(step.z(), 0.05);
    EXPECT_LT(step.z(), 0.3);
    EXPECT_LT(std::abs(step.x()), 0.05);
    EXPECT_LT(std::abs(step.y()), 0.05);
    EXPECT_LT(step.norm(), 0.5);
    EXPECT_LT(AngleDeg(poses[i - 1].world_from_cam.rotation,
                       poses[i].world_from_cam.rotation),
              1.0);
  }
  EXPECT_GT(summary_->trajectory_length_m, 2.0);
  EXPECT_LT(summary_->trajectory_length_m, 4.0);
  const Eigen::Vector3d last = poses.back().world_from_cam.translation;
  EXPECT_GT(last.z(), 2.0);
  EXPECT_LT(AngleDeg(poses.back().world_from_cam.rotation,
                     Eigen::Quaterniond::Identity()),
            5.0);
  // Keep the test well under a minute on two cores.
  EXPECT_LT(summary_->seconds, 40.0);
}

TEST_F(LidarPriorPosesKittiTest, WritesPriorsOnlyWhereMissing) {
  EXPECT_EQ(summary_->num_priors_written, kNumKittiFrames - 1);
  EXPECT_EQ(summary_->num_priors_kept, 1u);
  Database database(*database_path_);
  for (size_t i = 0; i < summary_->poses.size(); ++i) {
    const LidarPriorPose& pose = summary_->poses[i];
    SCOPED_TRACE(pose.image_name);
    const std::optional<DatabaseImage> image = database.ReadImage(pose.image_id);
    ASSERT_TRUE(image.has_value());
    ASSERT_TRUE(image->prior_q.has_value());
    ASSERT_TRUE(image->prior_t.has_value());
    const Rigid3d expected = i == kImageWithPrior ? FakePrior()
                                                  : pose.world_from_cam;
    EXPECT_LT(AngleDeg(*image->prior_q, expected.rotation.inverse()), 1e-6);
    EXPECT_LT((*image->prior_t - expected.translation).norm(), 1e-9);
  }
}

TEST_F(LidarPriorPosesKittiTest, WritesAModelThatColmapReads) {
  const Reconstruction model = ReadReconstruction(*model_path_);
  EXPECT_EQ(model.cameras.size(), 1u);
  EXPECT_TRUE(model.points3D.empty());
  ASSERT_EQ(model.images.size(), kNumKittiFrames);
  for (size_t i = 0; i < model.images.size(); ++i) {
    const LidarPriorPose& pose = summary_->poses[i];
    EXPECT_EQ(model.images[i].image_id, pose.image_id);
    EXPECT_EQ(model.images[i].name, pose.image_name);
    EXPECT_EQ(model.images[i].camera_id, pose.camera_id);
    // The model holds the odometry's pose even where a prior was kept.
    EXPECT_LT((model.images[i].ProjectionCenter() -
               pose.world_from_cam.translation)
                  .norm(),
              1e-9);
  }

  const std::string log_path = JoinPaths(*root_, "model_analyzer.log");
  ASSERT_EQ(testing::RunCommand("colmap model_analyzer --path " + *model_path_,
                                log_path),
            0)
      << ReadTextFile(log_path);
  const std::string log = ReadTextFile(log_path);
  std::smatch match;
  ASSERT_TRUE(std::regex_search(log, match,
                                std::regex("Registered images: ([0-9]+)")))
      << log;
  EXPECT_EQ(std::stoi(match[1]), static_cast<int>(kNumKittiFrames));
  ASSERT_TRUE(std::regex_search(log, match, std::regex("Points: ([0-9]+)")))
      << log;
  EXPECT_EQ(std::stoi(match[1]), 0);
}

// A copy of the database with scans for the first three images only; the
// first has a prior, which anchors the world, and all priors are replaced.
TEST_F(LidarPriorPosesKittiTest, OverwritesAndAnchorsOnTheFirstPrior) {
  const std::string dir = testing::CreateTestDir();
  const std::string database_path = JoinPaths(dir, "database.db");
  fs::copy_file(*database_path_, database_path);
  std::vector<DatabaseImage> images;
  const Rigid3d world_from_first(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())),
      Eigen::Vector3d(5, -1, 2));
  {
    Database database(database_path);
    images = database.ReadAllImages();
    std::sort(images.begin(), images.end(),
              [](const auto& a, const auto& b) { return a.name < b.name; });
    for (size_t i = 3; i < images.size(); ++i) {
      database.DeleteLidarScan(images[i].image_id);
    }
    SetPrior(&database, images[0].name, world_from_first);
    SetPrior(&database, images[1].name, FakePrior());
  }
  LidarPriorPosesOptions options;
  options.overwrite_priors = true;
  const LidarPriorPosesSummary summary = RunLidarOdometryPriors(
      database_path, JoinPaths(dir, "model"), LidarOdometryOptions(), options);
  ASSERT_EQ(summary.poses.size(), 3u);
  EXPECT_EQ(summary.num_images_without_scan, kNumKittiFrames - 3);
  EXPECT_EQ(summary.num_priors_written, 3u);
  EXPECT_EQ(summary.num_priors_kept, 0u);
  EXPECT_LT((summary.poses[0].world_from_cam.translation -
             world_from_first.translation)
                .norm(),
            1e-9);
  // The relative motion is about the one of the full run. Not exactly: the
  // street constrains the forward motion weakly, and PCL's GICP stops a few
  // centimetres apart when the world frame is rotated.
  const Rigid3d relative = summary.poses[0].world_from_cam.Inverse() *
                           summary.poses[2].world_from_cam;
  const Rigid3d full_relative = summary_->poses[0].world_from_cam.Inverse() *
                                summary_->poses[2].world_from_cam;
  EXPECT_LT((relative.translation - full_relative.translation).norm(), 0.05);

  Database database(database_path);
  const DatabaseImage second = *database.ReadImage(images[1].image_id);
  EXPECT_LT((*second.prior_t - summary.poses[1].world_from_cam.translation)
                .norm(),
            1e-9);
  // Images without a scan keep the prior of the full run.
  EXPECT_LT((*database.ReadImage(images[5].image_id)->prior_t -
             summary_->poses[5].world_from_cam.translation)
                .norm(),
            1e-9);
}

TEST_F(LidarPriorPosesKittiTest, RefusesToReplaceAFolderThatIsNoModel) {
  EXPECT_THROW(RunLidarOdometryPriors(*database_path_, *workspace_,
                                      LidarOdometryOptions(),
                                      LidarPriorPosesOptions()),
               Error);
  EXPECT_TRUE(ExistsFile(*database_path_));
}

}  // namespace
}  // namespace colmap_lidar
