#include "src/pipeline/report.h"

#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "colmap_ext/scene/reconstruction.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/poses.h"
#include "src/eval/mesh_evaluator.h"
#include "src/eval/pose_evaluator.h"
#include "src/pipeline/stage_record.h"

namespace colmap_lidar {
namespace {

constexpr int kNumFrames = 12;

std::vector<FramePose> GroundTruth() {
  std::vector<FramePose> poses;
  for (int i = 0; i < kNumFrames; ++i) {
    FramePose pose;
    char frame[16];
    std::snprintf(frame, sizeof(frame), "%06d", i);
    pose.frame = frame;
    pose.world_from_cam = Rigid3d(
        Eigen::Quaterniond(
            Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitZ())),
        Eigen::Vector3d(0.5 * i, 0.1 * i * i, 1.5));
    poses.push_back(pose);
  }
  return poses;
}

// The ground truth with centre errors of 1 to 5 cm, as a model.
Reconstruction NoisyModel(const std::vector<FramePose>& ground_truth) {
  Reconstruction model;
  Camera camera =
      Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
  camera.camera_id = 1;
  model.cameras[1] = camera;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> error(0.01, 0.05);
  for (size_t i = 0; i < ground_truth.size(); ++i) {
    Image image;
    image.image_id = static_cast<image_t>(i + 1);
    image.name = ground_truth[i].frame + ".png";
    image.camera_id = 1;
    Rigid3d world_from_cam = ground_truth[i].world_from_cam;
    world_from_cam.translation += error(rng) * Eigen::Vector3d::UnitX();
    image.cam_from_world = world_from_cam.Inverse();
    model.images.push_back(image);
  }
  return model;
}

std::vector<Eigen::Vector3d> PlaneGrid(double noise_m, int seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_m);
  std::vector<Eigen::Vector3d> points;
  for (int x = 0; x < 60; ++x) {
    for (int y = 0; y < 60; ++y) {
      points.emplace_back(0.05 * x, 0.05 * y, noise_m > 0 ? noise(rng) : 0.0);
    }
  }
  return points;
}

// The smallest workspace with every input of a figure, written with the
// writers of the stages that produce them (stage records, pose and mesh
// evaluators); trajectories.csv in the layout of the evaluate stage
// (pipeline_evaluation.cc).
void WriteWorkspace(const std::string& workspace) {
  const std::string pipeline_dir = JoinPaths(workspace, "pipeline");
  const std::string eval_dir = JoinPaths(workspace, "eval");
  CreateDirIfNotExists(pipeline_dir);
  CreateDirIfNotExists(eval_dir);

  std::vector<StageRecord> records(2);
  records[0].stage = "import";
  records[0].wall_seconds = 1.5;
  records[0].cpu_seconds = 1.25;
  records[0].peak_memory_bytes = 50u << 20;
  records[0].finished_at = UtcTimestamp();
  records[0].note = "12 frames";
  records[1] = records[0];
  records[1].stage = "patch_match";
  records[1].note = "12 reference images";
  WriteStageRecordsJson(JoinPaths(pipeline_dir, "stages.json"), records);

  const std::vector<FramePose> ground_truth = GroundTruth();
  const Reconstruction model = NoisyModel(ground_truth);
  PoseEvaluationOptions pose_options;
  pose_options.alignment = "none";
  WritePoseEvaluationJson(JoinPaths(eval_dir, "poses_refined_none.json"),
                          EvaluatePoses(model, ground_truth, pose_options));
  WriteFileAtomically(
      JoinPaths(eval_dir, "trajectories.csv"),
      [&](std::ostream& stream) {
        stream << "frame,gt_x,gt_y,gt_z,prior_x,prior_y,prior_z,refined_x,"
                  "refined_y,refined_z\n";
        for (size_t i = 0; i < ground_truth.size(); ++i) {
          const Eigen::Vector3d gt = ground_truth[i].world_from_cam.translation;
          const Eigen::Vector3d refined = model.images[i].ProjectionCenter();
          stream << ground_truth[i].frame << "," << gt.x() << "," << gt.y()
                 << "," << gt.z() << ",,,," << refined.x() << ","
                 << refined.y() << "," << refined.z() << "\n";
        }
      },
      /*binary=*/false);

  const std::vector<Eigen::Vector3d> reference = PlaneGrid(0.0, 0);
  const MeshEvaluation mesh = EvaluateMesh(
      PlaneGrid(0.02, 9), {}, reference, reference, MeshEvaluationOptions());
  WriteMeshEvaluationJson(JoinPaths(eval_dir, "mesh_ours.json"), mesh);
  WritePrecisionColoredPly(JoinPaths(eval_dir, "mesh_ours_precision.ply"),
                           mesh);
  WriteRecallColoredPly(JoinPaths(eval_dir, "mesh_ours_recall.ply"), mesh);
}

TEST(WriteReport, WritesThePageWithEveryFigureOfTheWorkspace) {
  const std::string root = testing::CreateTestDir();
  const std::string workspace = JoinPaths(root, "workspace");
  const std::string output = JoinPaths(root, "report");
  WriteWorkspace(workspace);
  const ReportSummary summary =
      WriteReport(workspace, JoinPaths(root, "dataset"), output,
                  ReportOptions());
  EXPECT_EQ(summary.html_path, JoinPaths(output, "index.html"));
  ASSERT_TRUE(ExistsFile(summary.html_path));
  const std::string html = ReadTextFile(summary.html_path);
  EXPECT_EQ(summary.num_figures, 4);
  for (const char* figure : {"trajectories", "pose_error_histogram",
                             "mesh_precision_recall", "mesh_ours"}) {
    const std::string png = std::string(figure) + ".png";
    EXPECT_TRUE(ExistsFile(JoinPaths(output, png))) << png;
    EXPECT_NE(html.find("(" + png + ")</figcaption>"), std::string::npos)
        << png;
  }
  // The sections of the inputs, the stage table, the pose row.
  for (const char* text :
       {"<h2>Stages</h2>", "<h2>Camera poses</h2>", "<h2>Mesh</h2>",
        "<td>patch_match</td>", "12 reference images",
        "Ours, refined (no alignment)", "<td>12 / 12</td>",
        "Ours: LIDAR-MVS + lines, refined poses"}) {
    EXPECT_NE(html.find(text), std::string::npos) << text;
  }
  // Sections without inputs say so; no lines section without a database.
  EXPECT_EQ(html.find("Stock COLMAP mapper"), std::string::npos);
  EXPECT_EQ(html.find("<h2>Lines</h2>"), std::string::npos);
  EXPECT_TRUE(ExistsFile(JoinPaths(output, "report.py")));
  EXPECT_TRUE(ExistsFile(JoinPaths(output, "report.log")));
}

TEST(WriteReport, PerfectPosesStillGetTheirHistogram) {
  // Every centre error exactly 0 (the ground truth against itself): the
  // log-scale histogram had no positive value to start from.
  const std::string root = testing::CreateTestDir();
  const std::string workspace = JoinPaths(root, "workspace");
  WriteWorkspace(workspace);
  const std::vector<FramePose> ground_truth = GroundTruth();
  Reconstruction model = NoisyModel(ground_truth);
  for (size_t i = 0; i < ground_truth.size(); ++i) {
    model.images[i].cam_from_world = ground_truth[i].world_from_cam.Inverse();
  }
  PoseEvaluationOptions pose_options;
  pose_options.alignment = "none";
  PoseEvaluation perfect = EvaluatePoses(model, ground_truth, pose_options);
  ASSERT_LT(perfect.position_stats_m.max, 1e-9);
  // Exactly 0, whatever the rounding of the pose inversions.
  for (ImagePoseError& error : perfect.errors) {
    error.position_error_m = 0.0;
  }
  WritePoseEvaluationJson(
      JoinPaths(workspace, "eval/poses_refined_none.json"), perfect);
  const std::string output = JoinPaths(root, "report");
  const ReportSummary summary =
      WriteReport(workspace, JoinPaths(root, "dataset"), output,
                  ReportOptions());
  EXPECT_EQ(summary.num_figures, 4);
  EXPECT_TRUE(ExistsFile(JoinPaths(output, "pose_error_histogram.png")));
}

TEST(WriteReport, EmptyWorkspaceGivesAPageThatSaysWhatIsMissing) {
  const std::string root = testing::CreateTestDir();
  const std::string workspace = JoinPaths(root, "workspace");
  CreateDirIfNotExists(workspace);
  const std::string output = JoinPaths(root, "report");
  const ReportSummary summary =
      WriteReport(workspace, workspace, output, ReportOptions());
  EXPECT_EQ(summary.num_figures, 0);
  const std::string html = ReadTextFile(summary.html_path);
  EXPECT_NE(html.find("No stage has finished yet."), std::string::npos);
  EXPECT_NE(html.find("No pose evaluation"), std::string::npos);
  EXPECT_NE(html.find("No mesh evaluation"), std::string::npos);
  EXPECT_EQ(html.find("<img"), std::string::npos);
}

TEST(WriteReport, MissingWorkspaceOrInterpreterFailsClearly) {
  const std::string root = testing::CreateTestDir();
  const std::string missing = JoinPaths(root, "no_workspace");
  const std::string output = JoinPaths(root, "report");
  try {
    WriteReport(missing, missing, output, ReportOptions());
    ADD_FAILURE() << "no exception for a missing workspace";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(missing), std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(ExistsDir(output));

  const std::string workspace = JoinPaths(root, "workspace");
  CreateDirIfNotExists(workspace);
  ReportOptions options;
  options.python_binary = JoinPaths(root, "no_python3");
  try {
    WriteReport(workspace, workspace, output, options);
    ADD_FAILURE() << "no exception for a missing interpreter";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(options.python_binary),
              std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(ExistsFile(JoinPaths(output, "index.html")));

  options.python_binary = "";
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(WriteReport(workspace, workspace, output, options), Error);
}

}  // namespace
}  // namespace colmap_lidar
