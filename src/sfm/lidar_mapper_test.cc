#include "src/sfm/lidar_mapper.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_tracks_table.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/importer.h"
#include "src/dataset/poses.h"
#include "src/eval/pose_evaluator.h"
#include "src/eval/segment_io.h"
#include "src/synth/synthesize.h"

namespace colmap_lidar {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

double MeanPositionErrorNoAlignment(const Reconstruction& model,
                                    const std::string& gt_path) {
  PoseEvaluationOptions options;
  options.alignment = "none";
  return EvaluatePoses(model, ReadPoses(gt_path), options)
      .position_stats_m.mean;
}

// One small synthetic recording (quad, 30 frames, 848 x 480) imported once and
// run through the whole pipeline once; the tests inspect the result.
class LidarMapperTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = new std::string(testing::CreateTestDir());
    dataset_ = new std::string(JoinPaths(*root_, "dataset"));
    workspace_ = new std::string(JoinPaths(*root_, "workspace"));
    SynthesisOptions synthesis;
    // The trajectory is the whole walk split into num_frames: with 10
    // frames neighbours barely overlap and stock mapper fails; 30 frames
    // of the quad loop reconstruct.
    synthesis.num_frames = 30;
    synthesis.image_width = 848;
    synthesis.image_height = 480;
    synthesis.supersampling = 1;
    synthesis.survey_num_stations = 0;
    synthesis.write_depth_maps = false;
    synthesis.num_threads = 2;
    SynthesizeDataset(synthesis, *dataset_);
    ImportDataset(*dataset_, *workspace_,
                  JoinPaths(*workspace_, "database.db"), ImporterOptions());
    LidarMapperOptions options;
    options.num_threads = 2;
    options.max_num_iterations = 3;
    LidarMapperPaths paths;
    paths.workspace_path = *workspace_;
    summary_ = new LidarMapperSummary(RunLidarMapper(paths, options));
  }
  static void TearDownTestSuite() {
    delete summary_;
    delete workspace_;
    delete dataset_;
    delete root_;
  }

  static std::string Binary() {
    return JoinPaths(testing::BinaryDir(), "colmap-lidar");
  }

  static std::string* root_;
  static std::string* dataset_;
  static std::string* workspace_;
  static LidarMapperSummary* summary_;
};

std::string* LidarMapperTest::root_ = nullptr;
std::string* LidarMapperTest::dataset_ = nullptr;
std::string* LidarMapperTest::workspace_ = nullptr;
LidarMapperSummary* LidarMapperTest::summary_ = nullptr;

TEST_F(LidarMapperTest, ReducesThePriorPoseErrorWithoutAlignment) {
  std::cout << summary_->Format() << std::endl;
  EXPECT_EQ(summary_->num_images, 30);
  ASSERT_FALSE(summary_->iterations.empty());
  const std::string gt = JoinPaths(*dataset_, "poses_gt.txt");
  const double prior_error = MeanPositionErrorNoAlignment(
      ReadReconstruction(JoinPaths(*workspace_, "sparse/prior")), gt);
  const Reconstruction refined =
      ReadReconstruction(JoinPaths(*workspace_, "sparse/refined"));
  const double refined_error = MeanPositionErrorNoAlignment(refined, gt);
  std::cout << "mean position error (no alignment): prior " << prior_error
            << " m, refined " << refined_error << " m" << std::endl;
  EXPECT_GT(prior_error, 0.3);
  // On this short 30-frame walk stock mapper cannot initialise (neighbours
  // overlap little), so the run takes the prior-initialised route, which
  // only partly corrects 0.5 m priors (measured 0.80 -> 0.56 m). The
  // accuracy target is checked by scripts/bench_lidar_mapper.sh on the
  // default 60-frame scene (0.79 -> 0.061 m, 0.0083 m after sim3); here the
  // pipeline must run end to end and move every pose towards the truth.
  EXPECT_LT(refined_error, 0.85 * prior_error);
  PoseEvaluationOptions sim3;
  sim3.alignment = "sim3";
  const PoseEvaluation aligned =
      EvaluatePoses(refined, ReadPoses(gt), sim3);
  std::cout << "after sim3: " << aligned.position_stats_m.mean << " m"
            << std::endl;
  EXPECT_GT(summary_->num_lines, 10);
  EXPECT_GT(summary_->num_points, 100);
  EXPECT_EQ(refined.lines3D.size(), static_cast<size_t>(summary_->num_lines));
}

TEST_F(LidarMapperTest, OutputIsReadableByStockColmapAndHasSegments) {
  const std::string refined = JoinPaths(*workspace_, "sparse/refined");
  EXPECT_TRUE(ExistsFile(JoinPaths(refined, "lines3D.bin")));
  const std::vector<Segment3D> segments =
      ReadSegments(JoinPaths(refined, "lines3D.ply"));
  EXPECT_EQ(segments.size(), static_cast<size_t>(summary_->num_lines));
  const std::string text = JoinPaths(*root_, "refined_txt");
  CreateDirIfNotExists(text);
  ASSERT_EQ(testing::RunCommand("colmap model_converter --input_path '" +
                                    refined + "' --output_path '" + text +
                                    "' --output_type TXT",
                                JoinPaths(*root_, "converter.log")),
            0);
  const Reconstruction converted = ReadReconstruction(text);
  EXPECT_EQ(converted.images.size(), 30u);
  EXPECT_EQ(converted.points3D.size(),
            static_cast<size_t>(summary_->num_points));
}

TEST_F(LidarMapperTest, LineBundleAdjusterCommandRefinesTheOutput) {
  const std::string output = JoinPaths(*root_, "line_ba");
  const std::string log = JoinPaths(*root_, "line_ba.log");
  ASSERT_EQ(testing::RunCommand(
                Binary() + " line_bundle_adjuster --database_path '" +
                    JoinPaths(*workspace_, "database.db") +
                    "' --input_path '" +
                    JoinPaths(*workspace_, "sparse/refined") +
                    "' --output_path '" + output +
                    "' --LineBundleAdjustment.prior_position_sigma_m 0.5"
                    " --LineBundleAdjustment.prior_rotation_sigma_deg 5"
                    " --LineBundleAdjustment.gauge POSE_PRIORS"
                    " --LineBundleAdjustment.num_threads 2",
                log),
            0)
      << ReadText(log);
  const Reconstruction model = ReadReconstruction(output);
  EXPECT_EQ(model.images.size(), 30u);
  EXPECT_GT(model.lines3D.size(), 10u);
  EXPECT_TRUE(ExistsFile(JoinPaths(output, "lines3D.ply")));
  // Starting from the converged model, the poses barely move.
  const double error = MeanPositionErrorNoAlignment(
      model, JoinPaths(*dataset_, "poses_gt.txt"));
  const double before = MeanPositionErrorNoAlignment(
      ReadReconstruction(JoinPaths(*workspace_, "sparse/refined")),
      JoinPaths(*dataset_, "poses_gt.txt"));
  EXPECT_NEAR(error, before, 0.02);
}

TEST_F(LidarMapperTest, BadInputsGiveClearErrors) {
  const std::string log = JoinPaths(*root_, "bad.log");
  // Missing model.
  EXPECT_NE(testing::RunCommand(
                Binary() + " line_bundle_adjuster --database_path '" +
                    JoinPaths(*workspace_, "database.db") +
                    "' --input_path '" + JoinPaths(*root_, "nope") +
                    "' --output_path '" + JoinPaths(*root_, "out") + "'",
                log),
            0);
  EXPECT_NE(ReadText(log).find("holds no sparse model"), std::string::npos)
      << ReadText(log);
  // A database without line tracks.
  const std::string copy = JoinPaths(*root_, "no_tracks.db");
  ASSERT_EQ(testing::RunCommand("cp '" +
                                JoinPaths(*workspace_, "database.db") +
                                "' '" + copy + "'"),
            0);
  {
    Database database(copy);
    ClearLineTracks(&database);
  }
  EXPECT_NE(testing::RunCommand(
                Binary() + " line_bundle_adjuster --database_path '" + copy +
                    "' --input_path '" +
                    JoinPaths(*workspace_, "sparse/refined") +
                    "' --output_path '" + JoinPaths(*root_, "out") + "'",
                log),
            0);
  EXPECT_NE(ReadText(log).find("no line tracks"), std::string::npos)
      << ReadText(log);
  // lidar_mapper on a folder without a database.
  EXPECT_NE(testing::RunCommand(Binary() + " lidar_mapper --workspace_path '" +
                                    JoinPaths(*root_, "empty") + "'",
                                log),
            0);
  EXPECT_NE(ReadText(log).find("No database"), std::string::npos)
      << ReadText(log);
}

TEST(FilterPoints, RemovesLargeErrorsAndReferences) {
  Reconstruction model;
  Image image;
  image.image_id = 1;
  image.points2D.resize(3);
  image.points2D[0].point3D_id = 10;
  image.points2D[1].point3D_id = 11;
  model.images.push_back(image);
  image.image_id = 2;
  model.images.push_back(image);
  Point3D good;
  good.error = 1.0;
  good.track = {{1, 0}, {2, 0}};
  Point3D bad = good;
  bad.error = 9.0;
  bad.track = {{1, 1}, {2, 1}};
  model.points3D[10] = good;
  model.points3D[11] = bad;
  EXPECT_EQ(FilterPoints(4.0, &model), 1);
  EXPECT_EQ(model.points3D.count(10), 1u);
  EXPECT_EQ(model.points3D.count(11), 0u);
  EXPECT_EQ(model.images[0].points2D[1].point3D_id, kInvalidPoint3DId);
  EXPECT_EQ(model.images[1].points2D[1].point3D_id, kInvalidPoint3DId);
  EXPECT_EQ(model.images[1].points2D[0].point3D_id, 10u);
}

}  // namespace
}  // namespace colmap_lidar
