#include "src/dataset/recording.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/dataset_test_util.h"

namespace colmap_lidar {
namespace {
namespace fs = std::filesystem;

class RecordingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dataset_ = JoinPaths(testing::CreateTestDir(), "rec");
    testing::MakeRigDatasetFromKitti(dataset_, 3);
  }
  std::string ExpectLoadError(const std::string& fragment) {
    try {
      LoadRecording(dataset_, "auto");
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos)
          << e.what();
      return e.what();
    }
    return "";
  }
  std::string dataset_;
};

TEST_F(RecordingTest, LoadsRigFormat) {
  EXPECT_EQ(DetectRecordingFormat(dataset_), "rig");
  const Recording recording = LoadRecording(dataset_, "auto");
  ASSERT_EQ(recording.frames.size(), 3u);
  EXPECT_EQ(recording.frames[1].name, "000001");
  ASSERT_TRUE(recording.frames[2].world_from_cam_prior.has_value());
  EXPECT_NEAR(recording.frames[2].world_from_cam_prior->translation.z(), 0.3,
              1e-12);
  EXPECT_TRUE(recording.ground_truth_poses_path.empty());
}

TEST_F(RecordingTest, DetectsKitti) {
  EXPECT_EQ(DetectRecordingFormat(testing::KittiSampleDir()), "kitti_raw");
  EXPECT_THROW(DetectRecordingFormat(testing::CreateTestDir()), Error);
  EXPECT_THROW(LoadRecording(dataset_, "colmap"), Error);
}

TEST_F(RecordingTest, ImageWithoutScan) {
  fs::remove(JoinPaths(dataset_, "lidar/000001.ply"));
  ExpectLoadError("000001");
}

TEST_F(RecordingTest, ScanWithoutImage) {
  fs::remove(JoinPaths(dataset_, "images/000002.png"));
  ExpectLoadError("has no image");
}

TEST_F(RecordingTest, TwoImagesForOneFrame) {
  fs::copy_file(JoinPaths(dataset_, "images/000000.png"),
                JoinPaths(dataset_, "images/000000.jpg"));
  ExpectLoadError("two image files");
}

TEST_F(RecordingTest, PoseWithoutFrameAndFrameWithoutPose) {
  std::ofstream(JoinPaths(dataset_, "poses_prior.txt"), std::ios::app)
      << "000009 0 0 0 0 0 0 1\n";
  ExpectLoadError("matches no frame");
  std::ofstream(JoinPaths(dataset_, "poses_prior.txt"))
      << "000000 0 0 0 0 0 0 1\n";
  ExpectLoadError("no pose for frame '000001'");
  fs::remove(JoinPaths(dataset_, "poses_prior.txt"));
  ExpectLoadError("poses_prior.txt");
}

// Timestamp-keyed trajectories match frames named by the same number.
TEST_F(RecordingTest, NumericPoseKeys) {
  std::ofstream(JoinPaths(dataset_, "poses_prior.txt"))
      << "0 0 0 0 0 0 0 1\n1.0 0 0 1 0 0 0 1\n2e0 0 0 2 0 0 0 1\n";
  const Recording recording = LoadRecording(dataset_, "rig");
  EXPECT_NEAR(recording.frames[2].world_from_cam_prior->translation.z(), 2,
              1e-12);
}

}  // namespace
}  // namespace colmap_lidar
