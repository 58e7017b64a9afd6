// End to end: the whole pipeline on a small synthetic scene with the real
// colmap binary, checked against bounds; resumption; bad input.
#include "src/pipeline/automatic_reconstructor.h"

#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/poses.h"
#include "src/eval/pose_evaluator.h"
#include "src/synth/synthesize.h"

namespace colmap_lidar {
namespace {

constexpr int kNumFrames = 16;

// A small, quick scene: 16 frames over the first 16% of the courtyard walk
// (about 12 m, spaced like the default scene), full-size images (at half
// size stock mapper's model of 12 frames was rejected or broken one run in
// two), a lighter LIDAR and survey.
AutomaticReconstructorOptions SmallSceneOptions() {
  AutomaticReconstructorOptions options;
  options.num_threads = 2;
  options.synthesis.num_frames = kNumFrames;
  options.synthesis.path_fraction = 0.16;
  options.synthesis.image_width = 848;
  options.synthesis.image_height = 480;
  options.synthesis.supersampling = 1;
  options.synthesis.lidar_columns = 512;
  options.synthesis.survey_angular_step_deg = 0.2;
  options.synthesis.survey_max_points = 500000;
  options.synthesis.write_depth_maps = false;
  return options;
}

TEST(AutomaticReconstructor, SmallSceneEndToEnd) {
  const std::string workspace =
      JoinPaths(testing::CreateTestDir(), "workspace");
  const AutomaticReconstructorOptions options = SmallSceneOptions();
  const AutomaticReconstructorSummary summary =
      RunAutomaticReconstructor(workspace, options);

  // Every stage ran but the odometry (the synthetic scene has priors).
  EXPECT_EQ(summary.ran.size(), static_cast<size_t>(kNumPipelineStages - 1));
  EXPECT_EQ(summary.not_applicable,
            std::vector<std::string>({"odometry"}));
  const PipelinePaths paths(workspace);
  EXPECT_EQ(summary.mesh_path, paths.mesh);
  EXPECT_EQ(summary.report_path, JoinPaths(paths.report, "index.html"));
  for (const StageRecord& record : summary.ran) {
    EXPECT_GT(record.wall_seconds, 0.0) << record.stage;
    EXPECT_GT(record.peak_memory_bytes, 0u) << record.stage;
  }

  // Poses: the adjustment removes most of the 0.5 m / 5 deg prior noise.
  const Json prior_none =
      ReadJsonFile(JoinPaths(paths.eval, "poses_prior_none.json"));
  const Json refined_none =
      ReadJsonFile(JoinPaths(paths.eval, "poses_refined_none.json"));
  const Json refined_sim3 =
      ReadJsonFile(JoinPaths(paths.eval, "poses_refined_sim3.json"));
  const double prior_error =
      prior_none.at("position_error_m").at("mean").get<double>();
  const double refined_error =
      refined_none.at("position_error_m").at("mean").get<double>();
  const double refined_sim3_error =
      refined_sim3.at("position_error_m").at("mean").get<double>();
  LOG(INFO) << "poses: prior " << prior_error << " m, refined "
            << refined_error << " m (none), " << refined_sim3_error
            << " m (sim3)";
  EXPECT_GT(prior_error, 0.3);
  EXPECT_LT(refined_error, 0.5 * prior_error);
  EXPECT_LT(refined_sim3_error, 0.05);
  EXPECT_EQ(refined_none.at("num_matched").get<int>(), kNumFrames);

  // Mesh: thresholds 0.02 0.05 0.1 0.2 0.5 m.
  const Json mesh_json =
      ReadJsonFile(JoinPaths(paths.eval, "mesh_ours.json"));
  const std::vector<double> thresholds =
      mesh_json.at("thresholds_m").get<std::vector<double>>();
  const std::vector<double> fscores =
      mesh_json.at("fscore").get<std::vector<double>>();
  ASSERT_EQ(thresholds.size(), 5u);
  ASSERT_EQ(fscores.size(), 5u);
  LOG(INFO) << "mesh F: " << fscores[0] << " " << fscores[1] << " "
            << fscores[2] << " " << fscores[3] << " " << fscores[4];
  EXPECT_GT(fscores[4], 0.8);
  EXPECT_GT(fscores[2], 0.5);
  // The synthetic recording's true surface judges precision.
  EXPECT_TRUE(mesh_json.at("precision_to_surface").get<bool>());
  EXPECT_TRUE(ExistsFile(JoinPaths(paths.eval, "mesh_lidar_poisson.json")));
  EXPECT_TRUE(ExistsFile(JoinPaths(paths.eval, "trajectories.csv")));

  // Report: a page with its figures embedded.
  const std::string html = ReadTextFile(summary.report_path);
  EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
  EXPECT_NE(html.find("Ours, refined (sim3 alignment)"), std::string::npos);
  // The stock mapper's row exists only when lidar_mapper ran it
  // (init_method mapper; the default lidar_graph does not).
  EXPECT_EQ(html.find("Stock COLMAP mapper") != std::string::npos,
            ExistsDir(JoinPaths(workspace, "sparse/lidar_mapper/mapper/0")));
  for (const char* png : {"trajectories.png", "pose_error_histogram.png",
                          "mesh_precision_recall.png", "mesh_ours.png",
                          "line_overlays.png"}) {
    EXPECT_TRUE(ExistsFile(JoinPaths(paths.report, png))) << png;
  }

  // Fusion leaves out the pixels that only one view and the LIDAR confirmed
  // (the masks PatchMatch wrote).
  ASSERT_TRUE(ExistsDir(JoinPaths(paths.dense, "stereo/fusion_masks")));
  EXPECT_NE(ReadTextFile(JoinPaths(paths.pipeline, "colmap.log"))
                .find("--StereoFusion.mask_path " +
                      JoinPaths(paths.dense, "stereo/fusion_masks")),
            std::string::npos);

  // A second run resumes: everything is marked done.
  const AutomaticReconstructorSummary again =
      RunAutomaticReconstructor(workspace, options);
  EXPECT_TRUE(again.ran.empty());
  EXPECT_EQ(again.skipped.size(), summary.ran.size());

  // Re-running one stage drops the marks of the later ones.
  AutomaticReconstructorOptions mesh_only = options;
  mesh_only.stages = "mesh";
  mesh_only.overwrite = true;
  const AutomaticReconstructorSummary remeshed =
      RunAutomaticReconstructor(workspace, mesh_only);
  ASSERT_EQ(remeshed.ran.size(), 1u);
  EXPECT_FALSE(ExistsFile(paths.StageMark(PipelineStage::kEvaluate)));
  EXPECT_FALSE(ExistsFile(paths.StageMark(PipelineStage::kReport)));
  EXPECT_TRUE(ExistsFile(paths.StageMark(PipelineStage::kFusion)));
}

// A workspace made by stock COLMAP (images, features, matches) plus a
// recording with the LIDAR and the calibration: the pipeline adds what is
// missing and keeps the stock features.
TEST(AutomaticReconstructor, CompletesAStockColmapWorkspace) {
  const std::string dir = testing::CreateTestDir();
  AutomaticReconstructorOptions options = SmallSceneOptions();
  options.dataset_path = JoinPaths(dir, "dataset");
  SynthesizeDataset(options.synthesis, options.dataset_path);
  const std::string workspace = JoinPaths(dir, "workspace");
  const std::string images = JoinPaths(workspace, "images");
  CreateDirIfNotExists(workspace);
  std::filesystem::copy(JoinPaths(options.dataset_path, "images"), images);
  const std::string database_path = JoinPaths(workspace, "database.db");
  const std::string log = JoinPaths(dir, "colmap.log");
  ASSERT_EQ(testing::RunCommand(
                "colmap feature_extractor --database_path '" + database_path +
                    "' --image_path '" + images +
                    "' --SiftExtraction.use_gpu 0 --SiftExtraction.num_threads 2",
                log),
            0)
      << ReadTextFile(log);
  ASSERT_EQ(testing::RunCommand("colmap sequential_matcher --database_path '" +
                                    database_path +
                                    "' --SiftMatching.use_gpu 0 "
                                    "--SiftMatching.num_threads 2",
                                log),
            0)
      << ReadTextFile(log);
  std::map<image_t, size_t> keypoints_before;
  {
    Database database(database_path);
    for (const DatabaseImage& image : database.ReadAllImages()) {
      keypoints_before[image.image_id] =
          database.NumKeypointsForImage(image.image_id);
    }
  }
  ASSERT_EQ(keypoints_before.size(), static_cast<size_t>(kNumFrames));

  options.stages = "import:sfm";
  const AutomaticReconstructorSummary summary =
      RunAutomaticReconstructor(workspace, options);
  ASSERT_EQ(summary.ran.size(), 2u);
  EXPECT_EQ(summary.ran[0].stage, "import");
  EXPECT_EQ(summary.ran[1].stage, "sfm");
  {
    Database database(database_path);
    const std::vector<DatabaseImage> database_images = database.ReadAllImages();
    ASSERT_EQ(database_images.size(), static_cast<size_t>(kNumFrames));
    for (const DatabaseImage& image : database_images) {
      EXPECT_EQ(database.NumKeypointsForImage(image.image_id),
                keypoints_before.at(image.image_id))
          << image.name;
      EXPECT_TRUE(image.prior_t.has_value()) << image.name;
    }
  }
  PoseEvaluationOptions sim3;
  sim3.alignment = "sim3";
  const PoseEvaluation evaluation = EvaluatePoses(
      ReadReconstruction(PipelinePaths(workspace).refined_model),
      ReadPoses(JoinPaths(options.dataset_path, "poses_gt.txt")), sim3);
  EXPECT_EQ(evaluation.num_matched, static_cast<size_t>(kNumFrames));
  EXPECT_LT(evaluation.position_stats_m.mean, 0.05);
}

TEST(AutomaticReconstructor, BadInputIsReportedAndLeavesNoMark) {
  const std::string dir = testing::CreateTestDir();
  AutomaticReconstructorOptions options = SmallSceneOptions();
  options.dataset_path = JoinPaths(dir, "no_such_dataset");
  const std::string workspace = JoinPaths(dir, "workspace");
  try {
    RunAutomaticReconstructor(workspace, options);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("import"), std::string::npos) << message;
    EXPECT_NE(message.find("no_such_dataset"), std::string::npos) << message;
  }
  EXPECT_FALSE(ExistsFile(
      PipelinePaths(workspace).StageMark(PipelineStage::kImport)));

  options.stages = "mesh:import";
  EXPECT_FALSE(options.Check());
  options.stages = "all";
  options.dense_image_step = 0;
  EXPECT_FALSE(options.Check());
}

}  // namespace
}  // namespace colmap_lidar
