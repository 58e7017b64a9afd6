#include "src/dataset/importer.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/calibration.h"
#include "src/dataset/dataset_test_util.h"
#include "src/dataset/poses.h"

namespace colmap_lidar {
namespace {
namespace fs = std::filesystem;

constexpr int kNumFrames = 4;

int RunColmap(const std::string& args, const std::string& dir) {
  return testing::RunCommand("colmap " + args, JoinPaths(dir, "colmap.log"));
}

std::string ColmapLog(const std::string& dir) {
  return ReadTextFile(JoinPaths(dir, "colmap.log"));
}

class ImporterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = testing::CreateTestDir();
    dataset_ = JoinPaths(root_, "dataset");
    workspace_ = JoinPaths(root_, "workspace");
    testing::MakeRigDatasetFromKitti(dataset_, kNumFrames);
  }
  std::string root_, dataset_, workspace_;
};

TEST_F(ImporterTest, ImportsARigRecording) {
  const ImportSummary summary =
      ImportDataset(dataset_, workspace_, "", ImporterOptions());
  EXPECT_EQ(summary.num_frames, kNumFrames);
  EXPECT_EQ(summary.num_new_images, kNumFrames);
  EXPECT_EQ(summary.num_matched_images, 0);
  EXPECT_EQ(summary.num_frames_with_prior, kNumFrames);
  EXPECT_GT(summary.num_lidar_points, 100000u * kNumFrames);
  EXPECT_EQ(summary.database_path, JoinPaths(workspace_, "database.db"));

  Database database(summary.database_path);
  ASSERT_EQ(database.ReadAllCameras().size(), 1u);
  const std::vector<DatabaseImage> images = database.ReadAllImages();
  ASSERT_EQ(images.size(), static_cast<size_t>(kNumFrames));
  const std::vector<FramePose> priors =
      ReadPoses(JoinPaths(dataset_, "poses_prior.txt"));
  for (const DatabaseImage& image : images) {
    const int index = std::stoi(image.name.substr(0, 6));
    EXPECT_EQ(image.name, priors[index].frame + ".png");
    // prior_t: camera position; prior_q: world-to-camera rotation.
    ASSERT_TRUE(image.prior_t.has_value() && image.prior_q.has_value());
    EXPECT_NEAR((*image.prior_t - priors[index].world_from_cam.translation).norm(), 0, 1e-12);
    EXPECT_NEAR(image.prior_q->angularDistance(
                    priors[index].world_from_cam.rotation.inverse()), 0, 1e-9);
    EXPECT_TRUE(ExistsFile(JoinPaths(workspace_, "images/" + image.name)));
    const std::optional<LidarScanRecord> scan = database.ReadLidarScan(image.image_id);
    ASSERT_TRUE(scan.has_value());
    EXPECT_EQ(scan->path, "lidar/" + priors[index].frame + ".ply");
    EXPECT_TRUE(ExistsFile(JoinPaths(workspace_, scan->path)));
    EXPECT_GT(scan->num_points, 100000u);
  }

  // The prior model: ids of the database, poses of the priors, no points.
  const Reconstruction model = ReadReconstruction(summary.prior_model_path);
  ASSERT_EQ(model.images.size(), static_cast<size_t>(kNumFrames));
  EXPECT_TRUE(model.points3D.empty());
  for (const Image& image : model.images) {
    const DatabaseImage db_image = *database.ReadImageWithName(image.name);
    EXPECT_EQ(db_image.image_id, image.image_id);
    EXPECT_NEAR((image.ProjectionCenter() - *db_image.prior_t).norm(), 0, 1e-9);
  }
  // No temporary files are left behind.
  for (const auto& entry : fs::recursive_directory_iterator(workspace_)) {
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos)
        << entry.path();
  }
}

// Stock colmap works on what we wrote: feature extraction fills our images
// (no new camera, ids kept), matching, and point_triangulator on the prior
// model triangulates points with the prior poses kept fixed.
TEST_F(ImporterTest, StockColmapRunsOnTheImportedWorkspace) {
  const ImportSummary summary =
      ImportDataset(dataset_, workspace_, "", ImporterOptions());
  const std::string db = summary.database_path;
  ASSERT_EQ(RunColmap("feature_extractor --database_path " + db +
                          " --image_path " + summary.image_path +
                          " --SiftExtraction.use_gpu 0 --SiftExtraction.num_threads 2"
                          " --SiftExtraction.max_num_features 2048",
                      root_), 0) << ColmapLog(root_);
  ASSERT_EQ(RunColmap("exhaustive_matcher --database_path " + db +
                          " --SiftMatching.use_gpu 0",
                      root_), 0) << ColmapLog(root_);
  const std::string triangulated = JoinPaths(workspace_, "sparse/triangulated");
  CreateDirIfNotExists(triangulated);
  ASSERT_EQ(RunColmap("point_triangulator --database_path " + db +
                          " --image_path " + summary.image_path +
                          " --input_path " + summary.prior_model_path +
                          " --output_path " + triangulated,
                      root_), 0) << ColmapLog(root_);
  ASSERT_EQ(RunColmap("model_analyzer --path " + triangulated, root_), 0)
      << ColmapLog(root_);
  EXPECT_NE(ColmapLog(root_).find("Registered images: " + std::to_string(kNumFrames)),
            std::string::npos) << ColmapLog(root_);

  Database database(db);
  EXPECT_EQ(database.ReadAllCameras().size(), 1u);
  EXPECT_EQ(database.ReadAllImages().size(), static_cast<size_t>(kNumFrames));
  EXPECT_EQ(database.ReadAllLidarScans().size(), static_cast<size_t>(kNumFrames));
  const Reconstruction model = ReadReconstruction(triangulated);
  EXPECT_GT(model.points3D.size(), 200u);
  const Reconstruction prior = ReadReconstruction(summary.prior_model_path);
  for (const Image& image : prior.images) {
    const Image* refined = model.FindImage(image.image_id);
    ASSERT_NE(refined, nullptr);
    EXPECT_NEAR((refined->ProjectionCenter() - image.ProjectionCenter()).norm(), 0, 1e-9);
  }
}

// An existing COLMAP workspace: images and features came first (ids chosen by
// colmap); the import matches frames by name and only adds priors and scans.
TEST_F(ImporterTest, CompletesAnExistingColmapWorkspace) {
  const std::string image_dir = JoinPaths(workspace_, "images");
  CreateDirIfNotExists(image_dir);
  for (const auto& entry : fs::directory_iterator(JoinPaths(dataset_, "images"))) {
    fs::copy_file(entry.path(), JoinPaths(image_dir, entry.path().filename()));
  }
  const std::string db = JoinPaths(workspace_, "database.db");
  ASSERT_EQ(RunColmap("feature_extractor --database_path " + db + " --image_path " +
                          image_dir +
                          " --ImageReader.single_camera 1 --SiftExtraction.use_gpu 0"
                          " --SiftExtraction.max_num_features 512",
                      root_), 0) << ColmapLog(root_);
  std::map<std::string, image_t> ids_before;
  std::map<image_t, size_t> keypoints_before;
  {
    Database database(db);
    for (const DatabaseImage& image : database.ReadAllImages()) {
      ids_before[image.name] = image.image_id;
      keypoints_before[image.image_id] = database.NumKeypointsForImage(image.image_id);
      EXPECT_FALSE(image.prior_t.has_value());
    }
  }
  const ImportSummary summary = ImportDataset(dataset_, workspace_, "", ImporterOptions());
  EXPECT_EQ(summary.num_matched_images, kNumFrames);
  EXPECT_EQ(summary.num_new_images, 0);
  // Stock feature_extractor guessed a SIMPLE_RADIAL camera; the images now
  // use the calibrated one.
  EXPECT_EQ(summary.num_recalibrated_images, kNumFrames);
  const Camera calibrated =
      ReadCalibration(JoinPaths(dataset_, "calibration.yaml")).camera;
  Database database(db);
  const std::vector<DatabaseImage> images = database.ReadAllImages();
  ASSERT_EQ(images.size(), static_cast<size_t>(kNumFrames));
  for (const DatabaseImage& image : images) {
    EXPECT_EQ(ids_before.at(image.name), image.image_id);
    const std::optional<Camera> camera = database.ReadCamera(image.camera_id);
    ASSERT_TRUE(camera.has_value());
    EXPECT_EQ(camera->model_id, calibrated.model_id);
    EXPECT_EQ(camera->params, calibrated.params);
    EXPECT_EQ(database.NumKeypointsForImage(image.image_id),
              keypoints_before.at(image.image_id));
    EXPECT_TRUE(image.prior_t.has_value());
    EXPECT_TRUE(database.ExistsLidarScan(image.image_id));
  }
}

// Any error leaves the workspace as it was: no new rows, no new files.
TEST_F(ImporterTest, BadInputLeavesTheWorkspaceUnchanged) {
  ImportDataset(dataset_, workspace_, "", ImporterOptions());
  const std::string db = JoinPaths(workspace_, "database.db");

  // A second recording with one more frame whose scan has a NaN point.
  const std::string bad = JoinPaths(root_, "bad");
  testing::MakeRigDatasetFromKitti(bad, kNumFrames + 1);
  {
    std::ofstream scan(JoinPaths(bad, "lidar/000004.ply"), std::ios::trunc);
    scan << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
            "property float y\nproperty float z\nend_header\n1 2 3\nnan 0 1\n";
  }
  ImporterOptions overwrite;
  overwrite.overwrite = true;
  try {
    ImportDataset(bad, workspace_, "", overwrite);
    FAIL() << "no error for a NaN point";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("000004.ply"), std::string::npos) << e.what();
  }
  {
    Database database(db);
    EXPECT_EQ(database.ReadAllImages().size(), static_cast<size_t>(kNumFrames));
  }
  EXPECT_FALSE(ExistsFile(JoinPaths(workspace_, "images/000004.png")));
  EXPECT_FALSE(ExistsFile(JoinPaths(workspace_, "lidar/000004.ply")));

  // Importing the same frames twice needs --LidarImport.overwrite.
  EXPECT_THROW(ImportDataset(dataset_, workspace_, "", ImporterOptions()), Error);
  EXPECT_NO_THROW(ImportDataset(dataset_, workspace_, "", overwrite));
  Database database(db);
  EXPECT_EQ(database.ReadAllImages().size(), static_cast<size_t>(kNumFrames));
  EXPECT_EQ(database.ReadAllLidarScans().size(), static_cast<size_t>(kNumFrames));

  // A failed import into a new folder does not create it.
  fs::remove(JoinPaths(dataset_, "lidar/000001.ply"));
  const std::string fresh = JoinPaths(root_, "fresh");
  EXPECT_THROW(ImportDataset(dataset_, fresh, "", ImporterOptions()), Error);
  EXPECT_FALSE(fs::exists(fresh));
}

TEST_F(ImporterTest, ImportsKittiRawWithoutPriors) {
  ImporterOptions options;
  options.copy_images = false;
  options.copy_scans = false;
  const ImportSummary summary =
      ImportDataset(testing::KittiSampleDir(), workspace_, "", options);
  EXPECT_EQ(summary.dataset_format, "kitti_raw");
  EXPECT_EQ(summary.num_frames, 20);
  EXPECT_EQ(summary.num_frames_with_prior, 0);
  EXPECT_TRUE(summary.prior_model_path.empty());
  EXPECT_FALSE(fs::exists(JoinPaths(workspace_, "images")));
  Database database(summary.database_path);
  const std::vector<LidarScanRecord> scans = database.ReadAllLidarScans();
  ASSERT_EQ(scans.size(), 20u);
  EXPECT_TRUE(ExistsFile(scans[0].path));  // absolute, not copied
  EXPECT_TRUE(fs::path(scans[0].path).is_absolute());
}

TEST(ImporterOptionsTest, Check) {
  ImporterOptions options;
  EXPECT_TRUE(options.Check());
  options.input_format = "ply";
  EXPECT_FALSE(options.Check());
  options = ImporterOptions();
  options.kitti_camera = 4;
  EXPECT_FALSE(options.Check());
}

}  // namespace
}  // namespace colmap_lidar
