#include "src/sfm/lidar_mapper.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_tracks_table.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/runner/colmap_runner.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/importer.h"
#include "src/dataset/poses.h"
#include "src/eval/pose_evaluator.h"
#include "src/eval/segment_io.h"
#include "src/sfm/mapper_iterations.h"
#include "src/sfm/model_alignment.h"
#include "src/synth/synthesize.h"
#include "src/synth/test_recordings.h"

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

// Synthesizes `num_frames` frames over `path_fraction` of the quad walk at
// 848 x 480 (no survey, no depth maps) into `dataset` and imports them into
// `workspace`.
void SynthesizeAndImportQuadWalk(int num_frames, double path_fraction,
                                 const std::string& dataset,
                                 const std::string& workspace) {
  SynthesizeDataset(QuickTestRecording(num_frames, path_fraction, 848, 480),
                    dataset);
  ImportDataset(dataset, workspace, JoinPaths(workspace, "database.db"),
                ImporterOptions());
}

// One small synthetic recording (quad, 30 frames, 848 x 480) imported once and
// run through the whole pipeline once; the tests inspect the result.
class LidarMapperTest : public ::testing::Test {
 protected:
  static constexpr int kNumFrames = 16;

  static void SetUpTestSuite() {
    root_ = new std::string(testing::CreateTestDir());
    dataset_ = new std::string(JoinPaths(*root_, "dataset"));
    workspace_ = new std::string(JoinPaths(*root_, "workspace"));
    // A 16% stretch of the quad walk in kNumFrames frames, spaced like the
    // default 60-frame scene (0.8 m): stock mapper initialises reliably.
    // (Spread over the whole walk, 30 frames overlap so little that stock
    // mapper mostly fails to build a model of 10 images.)
    SynthesizeAndImportQuadWalk(kNumFrames, 0.16, *dataset_, *workspace_);
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

  // Writes `initial` to <root>/<name>_init and runs lidar_mapper from it
  // (init_method "model") into <root>/<name>_out.
  static LidarMapperSummary RunFromInitialModel(const Reconstruction& initial,
                                                const std::string& name,
                                                int max_num_iterations) {
    const std::string initial_path = JoinPaths(*root_, name + "_init");
    WriteReconstruction(initial_path, initial, ModelFormat::kBinary);
    LidarMapperOptions options;
    options.num_threads = 2;
    options.max_num_iterations = max_num_iterations;
    options.init_method = "model";
    options.init_model_path = initial_path;
    LidarMapperPaths paths;
    paths.workspace_path = *workspace_;
    paths.output_path = OutputOf(name);
    const LidarMapperSummary summary = RunLidarMapper(paths, options);
    std::cout << summary.Format() << std::endl;
    return summary;
  }
  static std::string OutputOf(const std::string& name) {
    return JoinPaths(*root_, name + "_out");
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
  EXPECT_EQ(summary_->num_images, kNumFrames);
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
  // Stock mapper's relative poses, aligned to the priors, then refined. The
  // world frame is fixed only by the 24 noisy priors (0.5 m per axis), so the
  // error without alignment stays at a gauge of about 0.5 / sqrt(24) m per
  // axis; the accuracy target is checked by scripts/bench_lidar_mapper.sh on
  // the default 60-frame scene.
  EXPECT_NE(summary_->init_used, "priors (fallback)");
  EXPECT_LT(refined_error, 0.5 * prior_error);
  PoseEvaluationOptions sim3;
  sim3.alignment = "sim3";
  const PoseEvaluation aligned =
      EvaluatePoses(refined, ReadPoses(gt), sim3);
  std::cout << "after sim3: " << aligned.position_stats_m.mean << " m"
            << std::endl;
  EXPECT_LT(aligned.position_stats_m.mean, 0.05);
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
  EXPECT_EQ(converted.images.size(), static_cast<size_t>(kNumFrames));
  EXPECT_EQ(converted.points3D.size(),
            static_cast<size_t>(summary_->num_points));
}

// Mean reprojection error of the model's points over their observations,
// pixels.
double MeanPointErrorPx(const Reconstruction& model) {
  double sum = 0.0;
  int count = 0;
  for (const auto& [point3D_id, point3D] : model.points3D) {
    for (const TrackElement& element : point3D.track) {
      const Image& image = *model.FindImage(element.image_id);
      const Camera& camera = model.cameras.at(image.camera_id);
      sum += (camera.ImgFromCam(image.cam_from_world * point3D.xyz) -
              image.points2D.at(element.point2D_idx).xy)
                 .norm();
      ++count;
    }
  }
  return count > 0 ? sum / count : -1.0;
}

// When lidar_mapper keeps poses other than its adjustment's (the LIDAR
// graph's), the points and lines are rebuilt at them. Here every pose is
// moved by one rigid motion of the world, so the old structure misses by
// pixels and the rebuilt one fits.
TEST_F(LidarMapperTest, StructureIsRebuiltAtKeptPoses) {
  Reconstruction model =
      ReadReconstruction(JoinPaths(*workspace_, "sparse/refined"));
  const Rigid3d world_from_moved(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(0.3, -0.2, 0.1));
  for (Image& image : model.images) {
    image.cam_from_world = image.cam_from_world * world_from_moved;
  }
  ASSERT_GT(MeanPointErrorPx(model), 5.0);

  LidarMapperPaths paths;
  paths.workspace_path = *workspace_;
  paths.database_path = JoinPaths(*workspace_, "database.db");
  paths.image_path = JoinPaths(*workspace_, "images");
  LidarMapperOptions options;
  options.num_threads = 2;
  ColmapRunnerOptions runner_options;
  runner_options.log_path = JoinPaths(*root_, "rebuild_colmap.log");
  const std::string work_path = JoinPaths(*root_, "rebuild");
  CreateDirIfNotExists(work_path);
  const Database database(paths.database_path);
  RebuildStructureAtPoses(ColmapRunner(runner_options), paths, options,
                          work_path, {}, database, &model);
  EXPECT_GT(model.points3D.size(), 500u);
  EXPECT_LT(MeanPointErrorPx(model), 1.0);
  EXPECT_GT(model.lines3D.size(), 10u);
  for (const auto& [line3D_id, line3D] : model.lines3D) {
    EXPECT_GE(line3D.error, 0.0) << "line " << line3D_id;
    EXPECT_LE(line3D.error, options.max_line_error_px) << "line " << line3D_id;
  }
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
                    // lidar_mapper's per-axis sigma for 5 deg RMS priors.
                    " --LineBundleAdjustment.prior_rotation_sigma_deg 2.88675"
                    " --LineBundleAdjustment.gauge POSE_PRIORS"
                    " --LineBundleAdjustment.num_threads 2",
                log),
            0)
      << ReadText(log);
  const Reconstruction model = ReadReconstruction(output);
  EXPECT_EQ(model.images.size(), static_cast<size_t>(kNumFrames));
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

// A deliberately broken initial model (the ground truth mirrored: proper
// rotations, reflected centres, the mirror ambiguity of SfM) must be
// rejected by the robust alignment, with the run continuing from the priors.
TEST_F(LidarMapperTest, BrokenInitialModelFallsBackToPriors) {
  Reconstruction broken =
      ReadReconstruction(JoinPaths(*workspace_, "sparse/prior"));
  std::unordered_map<std::string, Rigid3d> truth;
  for (const FramePose& pose :
       ReadPoses(JoinPaths(*dataset_, "poses_gt.txt"))) {
    truth[pose.frame] = pose.world_from_cam;
  }
  const Eigen::Matrix3d mirror = Eigen::Vector3d(-1, 1, 1).asDiagonal();
  for (Image& image : broken.images) {
    const std::string frame = image.name.substr(0, image.name.rfind('.'));
    ASSERT_EQ(truth.count(frame), 1u) << image.name;
    const Rigid3d& world_from_cam = truth.at(frame);
    const Eigen::Quaterniond rotation(
        (mirror * world_from_cam.rotation.toRotationMatrix() * mirror)
            .transpose());
    image.cam_from_world = Rigid3d(
        rotation, -(rotation * (mirror * world_from_cam.translation)));
  }
  const LidarMapperSummary summary =
      RunFromInitialModel(broken, "broken", /*max_num_iterations=*/1);
  EXPECT_EQ(summary.init_used, "priors (fallback)");
  EXPECT_NE(summary.init_alignment.find("rejected"), std::string::npos);
  // From the priors a points-only round comes before the one round with
  // lines; the first was kept.
  ASSERT_EQ(summary.iterations.size(), 2u);
  EXPECT_EQ(summary.iterations[0].num_line_tracks, 0);
  EXPECT_FALSE(summary.iterations[0].rejected);
  const std::string gt = JoinPaths(*dataset_, "poses_gt.txt");
  const double prior_error = MeanPositionErrorNoAlignment(
      ReadReconstruction(JoinPaths(*workspace_, "sparse/prior")), gt);
  EXPECT_LT(MeanPositionErrorNoAlignment(
                ReadReconstruction(OutputOf("broken")), gt),
            1.05 * prior_error);

  // The same model unbroken is accepted.
  const Reconstruction prior =
      ReadReconstruction(JoinPaths(*workspace_, "sparse/prior"));
  Reconstruction intact = prior;
  for (Image& image : intact.images) {
    image.cam_from_world =
        truth.at(image.name.substr(0, image.name.rfind('.'))).Inverse();
  }
  std::unordered_map<image_t, Rigid3d> priors;
  for (const Image& image : prior.images) {
    priors[image.image_id] = image.cam_from_world;
  }
  EXPECT_TRUE(RobustAlignReconstructionToPriors(
                  priors, RobustPriorAlignmentOptions(), &intact)
                  .accepted);
}

// Images an initial model holds at wrong poses (outside the consensus with
// the priors) are pending: stock image_registrator places them against the
// points of an iteration, and they are refined with the others from then
// on.
TEST_F(LidarMapperTest, PendingImagesAreRegistered) {
  Reconstruction initial =
      ReadReconstruction(JoinPaths(*workspace_, "sparse/refined"));
  initial.points3D.clear();
  initial.point3D_file_order.clear();
  initial.lines3D.clear();
  std::vector<std::string> dropped;
  for (size_t i = 0; i < initial.images.size(); ++i) {
    Image& image = initial.images[i];
    image.points2D.clear();
    if (i >= 6 && i < 10) {
      // 4 m off and turned by 40 degrees: far outside the prior noise.
      dropped.push_back(image.name);
      const Eigen::Quaterniond turn(
          Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()));
      const Eigen::Vector3d centre =
          image.ProjectionCenter() + Eigen::Vector3d(4.0, 0.0, 0.0);
      const Eigen::Quaterniond rotation =
          (turn * image.cam_from_world.rotation).normalized();
      image.cam_from_world = Rigid3d(rotation, -(rotation * centre));
    }
  }
  const LidarMapperSummary summary =
      RunFromInitialModel(initial, "pending", /*max_num_iterations=*/2);
  EXPECT_EQ(summary.init_used, "model");
  EXPECT_EQ(summary.num_pending_images, 4);
  EXPECT_EQ(summary.num_registered_pending, 4);
  ASSERT_FALSE(summary.iterations.empty());
  EXPECT_EQ(summary.iterations[0].num_registered_images, 4);

  PoseEvaluationOptions sim3;
  sim3.alignment = "sim3";
  const PoseEvaluation evaluation =
      EvaluatePoses(ReadReconstruction(OutputOf("pending")),
                    ReadPoses(JoinPaths(*dataset_, "poses_gt.txt")), sim3);
  EXPECT_EQ(evaluation.num_matched, static_cast<size_t>(kNumFrames));
  EXPECT_LT(evaluation.position_stats_m.mean, 0.05);
  for (const ImagePoseError& error : evaluation.errors) {
    if (std::find(dropped.begin(), dropped.end(), error.image_name) !=
        dropped.end()) {
      EXPECT_LT(error.position_error_m, 0.1) << error.image_name;
      EXPECT_LT(error.rotation_error_deg, 2.0) << error.image_name;
    }
  }
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

// Issue 16: a frame whose image has no features (night, blur, a blank wall)
// still gets a pose, from the LIDAR graph (its edges to the neighbouring
// scans) and its prior: as good as its neighbours' and far better than the
// prior (0.5 m / 5 deg of noise); the summary and the log name it. A scene
// of its own (10 frames of the quad walk, spaced like the fixture above,
// the middle one's image replaced by uniform grey) so that the tests above
// keep a complete image set.
TEST(LidarMapperFeaturelessFrame, IsPosedByTheLidarGraph) {
  constexpr char kFeaturelessImage[] = "000005.png";
  const std::string root = testing::CreateTestDir();
  const std::string dataset = JoinPaths(root, "dataset");
  const std::string workspace = JoinPaths(root, "workspace");
  SynthesizeAndImportQuadWalk(10, 0.1, dataset, workspace);
  const std::string blank_path =
      JoinPaths(JoinPaths(workspace, "images"), kFeaturelessImage);
  const cv::Mat original = cv::imread(blank_path, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(original.empty()) << blank_path;
  ASSERT_TRUE(cv::imwrite(blank_path, cv::Mat(original.size(), original.type(),
                                              cv::Scalar::all(128))));

  LidarMapperOptions options;
  options.num_threads = 2;
  options.max_num_iterations = 3;
  LidarMapperPaths paths;
  paths.workspace_path = workspace;
  const LidarMapperSummary summary = RunLidarMapper(paths, options);
  std::cout << summary.Format() << std::endl;
  EXPECT_EQ(summary.images_without_points,
            std::vector<std::string>({kFeaturelessImage}));
  EXPECT_NE(summary.Format().find("observe no 3D point"), std::string::npos)
      << summary.Format();
  // The pipeline's stage record (and so the report) says it too.
  EXPECT_NE(summary.Outcome().find(std::string("images observe no 3D point, "
                                               "posed by the LIDAR graph and "
                                               "their priors alone: ") +
                                   kFeaturelessImage),
            std::string::npos)
      << summary.Outcome();

  const Reconstruction refined =
      ReadReconstruction(JoinPaths(workspace, "sparse/refined"));
  ASSERT_NE(refined.FindImageByName(kFeaturelessImage), nullptr);
  PoseEvaluationOptions sim3;
  sim3.alignment = "sim3";
  const PoseEvaluation aligned = EvaluatePoses(
      refined, ReadPoses(JoinPaths(dataset, "poses_gt.txt")), sim3);
  EXPECT_EQ(aligned.num_matched, 10u);
  double position_error_m = -1.0;
  double rotation_error_deg = -1.0;
  for (const ImagePoseError& error : aligned.errors) {
    if (error.image_name == kFeaturelessImage) {
      position_error_m = error.position_error_m;
      rotation_error_deg = error.rotation_error_deg;
    }
  }
  std::cout << kFeaturelessImage << " after sim3: " << position_error_m
            << " m, " << rotation_error_deg << " deg (all images: mean "
            << aligned.position_stats_m.mean << " m, max "
            << aligned.position_stats_m.max << " m)" << std::endl;
  ASSERT_GE(position_error_m, 0.0);
  EXPECT_LT(position_error_m, 0.05);
  EXPECT_LT(rotation_error_deg, 0.5);
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
