#include "src/sfm/lidar_mapper_workspace.h"

#include <gtest/gtest.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"
#include "src/synth/synthesize.h"
#include "src/synth/test_recordings.h"

namespace colmap_lidar {
namespace {

constexpr int kNumFrames = 3;

// One tiny synthetic recording (3 frames, 160 x 120, VLP-16), made once.
class LidarMapperWorkspaceTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = new std::string(testing::CreateTestDir());
    dataset_ = new std::string(JoinPaths(*root_, "dataset"));
    SynthesisOptions synthesis =
        QuickTestRecording(kNumFrames, 0.05, 160, 120);
    synthesis.lidar_model = "VLP-16";
    SynthesizeDataset(synthesis, *dataset_);
  }
  static void TearDownTestSuite() {
    delete dataset_;
    delete root_;
  }

  // A new, empty workspace folder.
  static std::string NewWorkspace(const std::string& name) {
    const std::string workspace = JoinPaths(*root_, name);
    CreateDirIfNotExists(workspace);
    return workspace;
  }

  static std::string* root_;
  static std::string* dataset_;
};

std::string* LidarMapperWorkspaceTest::root_ = nullptr;
std::string* LidarMapperWorkspaceTest::dataset_ = nullptr;

TEST_F(LidarMapperWorkspaceTest, ImportsIntoAWorkspaceWithoutDatabase) {
  LidarMapperPaths paths;
  paths.workspace_path = NewWorkspace("imported");
  const LidarMapperWorkspace workspace =
      PrepareLidarMapperWorkspace(paths, *dataset_);
  ASSERT_EQ(workspace.error, "");
  ASSERT_TRUE(workspace.imported);
  EXPECT_EQ(workspace.import.num_frames, kNumFrames);
  EXPECT_EQ(workspace.import.num_new_images, kNumFrames);
  EXPECT_EQ(workspace.import.num_frames_with_prior, kNumFrames);
  const std::string database_path =
      JoinPaths(paths.workspace_path, "database.db");
  EXPECT_EQ(workspace.import.database_path, database_path);
  ASSERT_TRUE(ExistsFile(database_path));
  EXPECT_EQ(Database(database_path).NumImages(),
            static_cast<size_t>(kNumFrames));
  // The mapper gets the imported images; the other paths stay defaults.
  EXPECT_EQ(workspace.paths.image_path, workspace.import.image_path);
  EXPECT_TRUE(ExistsDir(workspace.paths.image_path));
  EXPECT_EQ(workspace.paths.workspace_path, paths.workspace_path);
  EXPECT_EQ(workspace.paths.database_path, "");
  EXPECT_EQ(workspace.paths.output_path, "");

  // Once the database exists nothing is imported again.
  const LidarMapperWorkspace again =
      PrepareLidarMapperWorkspace(paths, *dataset_);
  EXPECT_EQ(again.error, "");
  EXPECT_FALSE(again.imported);
  EXPECT_EQ(again.paths.image_path, "");
  EXPECT_EQ(Database(database_path).NumImages(),
            static_cast<size_t>(kNumFrames));
}

TEST_F(LidarMapperWorkspaceTest, KeepsGivenDatabaseAndImagePaths) {
  LidarMapperPaths paths;
  paths.workspace_path = NewWorkspace("given_paths");
  paths.database_path = JoinPaths(paths.workspace_path, "other.db");
  paths.image_path = "/some/images";
  const LidarMapperWorkspace workspace =
      PrepareLidarMapperWorkspace(paths, *dataset_);
  ASSERT_EQ(workspace.error, "");
  ASSERT_TRUE(workspace.imported);
  EXPECT_TRUE(ExistsFile(paths.database_path));
  EXPECT_FALSE(ExistsFile(JoinPaths(paths.workspace_path, "database.db")));
  EXPECT_EQ(workspace.paths.database_path, paths.database_path);
  EXPECT_EQ(workspace.paths.image_path, "/some/images");
}

TEST_F(LidarMapperWorkspaceTest, RefusesWithoutDatabaseOrDataset) {
  LidarMapperPaths paths;
  paths.workspace_path = NewWorkspace("no_dataset");
  const LidarMapperWorkspace workspace =
      PrepareLidarMapperWorkspace(paths, /*dataset_path=*/"");
  const std::string database_path =
      JoinPaths(paths.workspace_path, "database.db");
  EXPECT_EQ(workspace.error, "No database " + database_path +
                                 ": run lidar_importer or give --dataset_path");
  EXPECT_FALSE(workspace.imported);
  EXPECT_FALSE(ExistsFile(database_path));
}

TEST_F(LidarMapperWorkspaceTest, FailedImportThrowsAndWritesNoDatabase) {
  LidarMapperPaths paths;
  paths.workspace_path = NewWorkspace("bad_dataset");
  EXPECT_THROW(PrepareLidarMapperWorkspace(
                   paths, JoinPaths(*root_, "no_such_dataset")),
               Error);
  EXPECT_FALSE(ExistsFile(JoinPaths(paths.workspace_path, "database.db")));
}

}  // namespace
}  // namespace colmap_lidar
