#include "src/eval/pose_evaluator.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

Eigen::Quaterniond Rotation(double angle_deg, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(
      Eigen::AngleAxisd(angle_deg * M_PI / 180.0, axis.normalized()));
}

// Six ground-truth frames with centres spanning 3D (centroid (1, 2, 3)) and
// varied orientations.
std::vector<FramePose> GroundTruth() {
  const std::vector<Eigen::Vector3d> offsets = {
      {1, 0, 0}, {-1, 0, 0}, {0, 2, 0}, {0, -2, 0}, {0, 0, 3}, {0, 0, -3}};
  std::vector<FramePose> poses;
  for (size_t i = 0; i < offsets.size(); ++i) {
    FramePose pose;
    pose.frame = "00000" + std::to_string(i);
    pose.world_from_cam.translation = Eigen::Vector3d(1, 2, 3) + offsets[i];
    pose.world_from_cam.rotation =
        Rotation(20.0 * i, Eigen::Vector3d(1, i, 2));
    poses.push_back(pose);
  }
  return poses;
}

// A model whose images have exactly the given world_from_cam poses.
Reconstruction ModelFromPoses(const std::vector<FramePose>& poses) {
  Reconstruction model;
  for (size_t i = 0; i < poses.size(); ++i) {
    Image image;
    image.image_id = i + 1;
    image.camera_id = 1;
    image.name = poses[i].frame + ".png";
    image.cam_from_world = poses[i].world_from_cam.Inverse();
    model.images.push_back(image);
  }
  return model;
}

PoseEvaluationOptions Options(const std::string& alignment) {
  PoseEvaluationOptions options;
  options.alignment = alignment;
  return options;
}

TEST(PoseEvaluator, IdenticalPosesHaveZeroError) {
  const std::vector<FramePose> gt = GroundTruth();
  for (const std::string alignment : {"none", "se3", "sim3"}) {
    const PoseEvaluation evaluation =
        EvaluatePoses(ModelFromPoses(gt), gt, Options(alignment));
    EXPECT_EQ(evaluation.num_matched, 6u);
    EXPECT_EQ(evaluation.num_missing, 0u);
    EXPECT_NEAR(evaluation.position_stats_m.max, 0.0, 1e-9) << alignment;
    EXPECT_NEAR(evaluation.rotation_stats_deg.max, 0.0, 1e-6) << alignment;
    EXPECT_NEAR(evaluation.scale, 1.0, 1e-12);
    for (const double recall : evaluation.position_recalls) {
      EXPECT_DOUBLE_EQ(recall, 1.0);
    }
    for (const double recall : evaluation.pose_recalls) {
      EXPECT_DOUBLE_EQ(recall, 1.0);
    }
  }
}

TEST(PoseEvaluator, Sim3AlignmentRemovesASimilarity) {
  const std::vector<FramePose> gt = GroundTruth();
  // The estimate lives in a frame est_from_gt = (s, R, t).
  const double s = 0.37;
  const Eigen::Quaterniond rotation = Rotation(73.0, Eigen::Vector3d(1, -2, 5));
  const Eigen::Vector3d t(10.0, -4.0, 2.5);
  std::vector<FramePose> estimated = gt;
  for (FramePose& pose : estimated) {
    pose.world_from_cam.translation =
        s * (rotation * pose.world_from_cam.translation) + t;
    pose.world_from_cam.rotation = rotation * pose.world_from_cam.rotation;
  }
  const PoseEvaluation sim3 =
      EvaluatePoses(ModelFromPoses(estimated), gt, Options("sim3"));
  EXPECT_NEAR(sim3.position_stats_m.max, 0.0, 1e-9);
  EXPECT_NEAR(sim3.rotation_stats_deg.max, 0.0, 1e-6);
  EXPECT_NEAR(sim3.scale, 1.0 / s, 1e-9);
  EXPECT_TRUE(sim3.rotation.isApprox(
      rotation.conjugate().toRotationMatrix(), 1e-9));
  // The steps are exact once scaled; their rotations need no alignment.
  EXPECT_EQ(sim3.step_translation_stats_m.count, 5u);
  EXPECT_NEAR(sim3.step_translation_stats_m.max, 0.0, 1e-9);
  EXPECT_NEAR(sim3.step_rotation_stats_deg.max, 0.0, 1e-6);
  // Without alignment the errors are large; the steps keep their exact
  // rotations but are s times too long.
  const PoseEvaluation none =
      EvaluatePoses(ModelFromPoses(estimated), gt, Options("none"));
  EXPECT_GT(none.position_stats_m.mean, 1.0);
  EXPECT_GT(none.rotation_stats_deg.mean, 10.0);
  EXPECT_NEAR(none.step_rotation_stats_deg.max, 0.0, 1e-6);
  double step_length_sum = 0.0;
  for (size_t i = 0; i + 1 < gt.size(); ++i) {
    step_length_sum += (gt[i + 1].world_from_cam.translation -
                        gt[i].world_from_cam.translation)
                           .norm();
  }
  EXPECT_NEAR(none.step_translation_stats_m.mean,
              (1.0 - s) * step_length_sum / (gt.size() - 1), 1e-9);
}

// The estimate is the ground truth scaled by 2 about the origin. With
// centres c_i = m + d_i (m the centroid, sum d_i = 0, the d_i spanning 3D),
// the best rigid alignment of 2 c_i to c_i is R = I, t = -m, leaving the
// error |2 c_i - m - c_i| = |d_i|; no alignment leaves |c_i|; sim3 removes
// everything.
TEST(PoseEvaluator, ScaleChangeKnownErrorsPerAlignment) {
  const std::vector<FramePose> gt = GroundTruth();
  std::vector<FramePose> estimated = gt;
  for (FramePose& pose : estimated) {
    pose.world_from_cam.translation *= 2.0;
  }
  const Reconstruction model = ModelFromPoses(estimated);
  const Eigen::Vector3d centroid(1, 2, 3);

  const PoseEvaluation se3 = EvaluatePoses(model, gt, Options("se3"));
  const PoseEvaluation none = EvaluatePoses(model, gt, Options("none"));
  const PoseEvaluation sim3 = EvaluatePoses(model, gt, Options("sim3"));
  ASSERT_EQ(se3.errors.size(), 6u);
  EXPECT_DOUBLE_EQ(se3.scale, 1.0);
  EXPECT_TRUE(se3.rotation.isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  EXPECT_TRUE(se3.translation.isApprox(-centroid, 1e-12));
  for (size_t i = 0; i < 6; ++i) {
    const Eigen::Vector3d c = gt[i].world_from_cam.translation;
    EXPECT_NEAR(se3.errors[i].position_error_m, (c - centroid).norm(), 1e-9);
    EXPECT_NEAR(se3.errors[i].rotation_error_deg, 0.0, 1e-6);
    EXPECT_NEAR(none.errors[i].position_error_m, c.norm(), 1e-12);
    EXPECT_NEAR(sim3.errors[i].position_error_m, 0.0, 1e-9);
  }
  // |d_i| = 1, 1, 2, 2, 3, 3.
  EXPECT_NEAR(se3.position_stats_m.mean, 2.0, 1e-9);
  EXPECT_NEAR(se3.position_stats_m.median, 2.0, 1e-9);
  EXPECT_NEAR(se3.position_stats_m.rmse, std::sqrt(28.0 / 6.0), 1e-9);
  EXPECT_NEAR(se3.position_stats_m.max, 3.0, 1e-9);
  EXPECT_NEAR(sim3.scale, 0.5, 1e-12);
}

// One of five images shifted by 0.1 m, one more ground-truth frame that is
// not in the model, one model image rotated by 3 degrees.
TEST(PoseEvaluator, ShiftedAndRotatedImagesAndMissingFrame) {
  const std::vector<FramePose> gt = GroundTruth();
  std::vector<FramePose> estimated(gt.begin(), gt.begin() + 5);
  estimated[2].world_from_cam.translation += Eigen::Vector3d(0.1, 0, 0);
  estimated[4].world_from_cam.rotation =
      estimated[4].world_from_cam.rotation *
      Rotation(3.0, Eigen::Vector3d(0.3, -1, 0.2));
  const PoseEvaluation evaluation =
      EvaluatePoses(ModelFromPoses(estimated), gt, Options("none"));
  EXPECT_EQ(evaluation.num_ground_truth_frames, 6u);
  EXPECT_EQ(evaluation.num_matched, 5u);
  EXPECT_EQ(evaluation.num_missing, 1u);
  ASSERT_EQ(evaluation.missing_frames.size(), 1u);
  EXPECT_EQ(evaluation.missing_frames[0], "000005");
  EXPECT_NEAR(evaluation.position_stats_m.mean, 0.02, 1e-12);
  EXPECT_NEAR(evaluation.position_stats_m.median, 0.0, 1e-12);
  EXPECT_NEAR(evaluation.position_stats_m.max, 0.1, 1e-12);
  EXPECT_NEAR(evaluation.position_stats_m.rmse, std::sqrt(0.01 / 5), 1e-12);
  EXPECT_NEAR(evaluation.rotation_stats_deg.max, 3.0, 1e-9);
  EXPECT_NEAR(evaluation.rotation_stats_deg.mean, 0.6, 1e-9);
  EXPECT_NEAR(evaluation.errors[4].rotation_error_deg, 3.0, 1e-9);
  // Recalls over the 6 ground-truth frames; thresholds 0.02, 0.05, 0.2,
  // 0.5 m and 0.5, 1, 5, 10 deg.
  const std::vector<double> position = {4 / 6.0, 4 / 6.0, 5 / 6.0, 5 / 6.0};
  const std::vector<double> rotation = {4 / 6.0, 4 / 6.0, 5 / 6.0, 5 / 6.0};
  const std::vector<double> both = {3 / 6.0, 3 / 6.0, 5 / 6.0, 5 / 6.0};
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(evaluation.position_recalls[k], position[k], 1e-12) << k;
    EXPECT_NEAR(evaluation.rotation_recalls[k], rotation[k], 1e-12) << k;
    EXPECT_NEAR(evaluation.pose_recalls[k], both[k], 1e-12) << k;
  }
  // Steps 0-1, 1-2, 2-3, 3-4 (4-5 lacks frame 5): the shift of frame 2
  // lengthens two steps by 0.1 m, the turn of frame 4 turns step 3-4.
  EXPECT_EQ(evaluation.step_translation_stats_m.count, 4u);
  EXPECT_NEAR(evaluation.step_translation_stats_m.mean, 0.05, 1e-12);
  EXPECT_NEAR(evaluation.step_translation_stats_m.max, 0.1, 1e-12);
  EXPECT_NEAR(evaluation.step_rotation_stats_deg.mean, 0.75, 1e-9);
  EXPECT_NEAR(evaluation.step_rotation_stats_deg.max, 3.0, 1e-9);
  const std::string table = FormatPoseEvaluation(evaluation);
  EXPECT_NE(table.find("5 matched, 1 missing"), std::string::npos) << table;
  EXPECT_NE(table.find("4 steps"), std::string::npos) << table;
}

TEST(PoseEvaluator, TooFewImagesForAlignmentThrows) {
  const std::vector<FramePose> gt = GroundTruth();
  const Reconstruction model =
      ModelFromPoses(std::vector<FramePose>(gt.begin(), gt.begin() + 2));
  for (const std::string alignment : {"se3", "sim3"}) {
    try {
      EvaluatePoses(model, gt, Options(alignment));
      ADD_FAILURE() << "no exception for " << alignment;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("at least 3"),
                std::string::npos)
          << error.what();
    }
  }
  EXPECT_EQ(EvaluatePoses(model, gt, Options("none")).num_matched, 2u);
}

TEST(PoseEvaluator, MatchesByExactNameOrFileStem) {
  std::vector<FramePose> gt = GroundTruth();
  gt[0].frame = "left/img.jpg";
  Reconstruction model = ModelFromPoses(gt);
  model.images[0].name = "left/img.jpg";   // Exact name.
  model.images[1].name = "cam0/000001.png";  // Stem.
  model.images[2].name = "unrelated.png";  // No frame.
  const PoseEvaluation evaluation = EvaluatePoses(model, gt, Options("none"));
  EXPECT_EQ(evaluation.num_matched, 5u);
  EXPECT_EQ(evaluation.num_unmatched_images, 1u);
  EXPECT_EQ(evaluation.num_missing, 1u);
  EXPECT_EQ(evaluation.errors[0].frame, "left/img.jpg");
  EXPECT_EQ(evaluation.errors[1].frame, "000001");
}

// Both axes fits remove an exact similarity like the centres-only ones.
TEST(PoseEvaluator, AxesAlignmentRemovesASimilarity) {
  const std::vector<FramePose> gt = GroundTruth();
  const double s = 2.5;
  const Eigen::Quaterniond rotation = Rotation(-41.0, Eigen::Vector3d(3, 1, 2));
  const Eigen::Vector3d t(-7.0, 4.0, 1.5);
  std::vector<FramePose> estimated = gt;
  for (FramePose& pose : estimated) {
    pose.world_from_cam.translation =
        s * (rotation * pose.world_from_cam.translation) + t;
    pose.world_from_cam.rotation = rotation * pose.world_from_cam.rotation;
  }
  const PoseEvaluation sim3 =
      EvaluatePoses(ModelFromPoses(estimated), gt, Options("sim3_axes"));
  EXPECT_EQ(sim3.alignment, "sim3_axes");
  EXPECT_NEAR(sim3.position_stats_m.max, 0.0, 1e-9);
  EXPECT_NEAR(sim3.rotation_stats_deg.max, 0.0, 1e-6);
  EXPECT_NEAR(sim3.scale, 1.0 / s, 1e-12);
  EXPECT_TRUE(
      sim3.rotation.isApprox(rotation.conjugate().toRotationMatrix(), 1e-9));
  // se3_axes: the rotation is exact (orientations and centre directions
  // agree); the scale stays 1.
  const PoseEvaluation se3 =
      EvaluatePoses(ModelFromPoses(estimated), gt, Options("se3_axes"));
  EXPECT_DOUBLE_EQ(se3.scale, 1.0);
  EXPECT_TRUE(
      se3.rotation.isApprox(rotation.conjugate().toRotationMatrix(), 1e-9));
  EXPECT_NEAR(se3.rotation_stats_deg.max, 0.0, 1e-6);
}

// A straight street: 20 cameras along x with 1 cm of lateral and vertical
// wobble, looking sideways. The estimate is the ground truth in a frame
// rolled by 4 deg about the street (the gauge) with 2 cm of noise on the
// centres and 0.05 deg on the orientations. The centres alone cannot see
// the roll (the noise decides it); the fit of the centres and the axes
// recovers it.
TEST(PoseEvaluator, AxesFitRecoversRollAboutStraightTrajectory) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<FramePose> gt;
  for (int i = 0; i < 20; ++i) {
    FramePose pose;
    pose.frame = "frame" + std::to_string(i);
    pose.world_from_cam.translation =
        Eigen::Vector3d(2.0 * i, 0.01 * normal(rng), 1.5 + 0.01 * normal(rng));
    // Camera z (viewing) along world +y, camera y down.
    Eigen::Matrix3d world_from_cam;
    world_from_cam.col(0) = Eigen::Vector3d(1, 0, 0);
    world_from_cam.col(1) = Eigen::Vector3d(0, 0, -1);
    world_from_cam.col(2) = Eigen::Vector3d(0, 1, 0);
    pose.world_from_cam.rotation =
        Eigen::Quaterniond(world_from_cam) *
        Rotation(0.5 * i, Eigen::Vector3d(0, 1, 0));
    gt.push_back(pose);
  }
  const Eigen::Quaterniond roll = Rotation(4.0, Eigen::Vector3d::UnitX());
  std::vector<FramePose> estimated = gt;
  for (FramePose& pose : estimated) {
    const Eigen::Vector3d noise(normal(rng), normal(rng), normal(rng));
    pose.world_from_cam.translation =
        roll * pose.world_from_cam.translation + 0.02 * noise;
    const Eigen::Vector3d axis(normal(rng), normal(rng), normal(rng));
    pose.world_from_cam.rotation =
        roll * pose.world_from_cam.rotation * Rotation(0.05, axis);
  }
  const Reconstruction model = ModelFromPoses(estimated);
  for (const std::string prefix : {"se3", "sim3"}) {
    const PoseEvaluation centres = EvaluatePoses(model, gt, Options(prefix));
    const PoseEvaluation axes =
        EvaluatePoses(model, gt, Options(prefix + "_axes"));
    // Roll left by the centres-only fit: degrees; by the axes fit: the
    // orientation noise.
    EXPECT_GT(centres.rotation_stats_deg.mean, 1.0) << prefix;
    EXPECT_LT(axes.rotation_stats_deg.mean, 0.1) << prefix;
    const double residual_roll_deg =
        Eigen::AngleAxisd(axes.rotation * roll.toRotationMatrix()).angle() *
        180.0 / M_PI;
    EXPECT_LT(residual_roll_deg, 0.05) << prefix;
    // The centres are matched as well as before (within their noise).
    EXPECT_LT(axes.position_stats_m.rmse, 0.04) << prefix;
    EXPECT_LT(axes.position_stats_m.rmse,
              centres.position_stats_m.rmse + 0.005)
        << prefix;
  }
}

TEST(PoseEvaluator, OptionsCheck) {
  PoseEvaluationOptions options;
  EXPECT_TRUE(options.Check());
  options.alignment = "affine";
  EXPECT_FALSE(options.Check());
  options.alignment = "sim3_axes";
  EXPECT_TRUE(options.Check());
  options.axes_weight = -1.0;
  EXPECT_FALSE(options.Check());
  options = PoseEvaluationOptions();
  options.position_thresholds_m = {0.1, 0.05};
  EXPECT_FALSE(options.Check());
  options = PoseEvaluationOptions();
  options.rotation_thresholds_deg = {0.0, 1.0};
  EXPECT_FALSE(options.Check());
  options.rotation_thresholds_deg = {};
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(EvaluatePoses(ModelFromPoses(GroundTruth()), GroundTruth(),
                             options),
               Error);
}

TEST(PoseEvaluator, WritesJson) {
  const std::vector<FramePose> gt = GroundTruth();
  const PoseEvaluation evaluation =
      EvaluatePoses(ModelFromPoses(gt), gt, Options("sim3"));
  const std::string path =
      JoinPaths(testing::CreateTestDir(), "poses.json");
  WritePoseEvaluationJson(path, evaluation);
  const Json json = ReadJsonFile(path);
  // The keys scripts/pose_table.py and the report read, in this order.
  std::vector<std::string> keys;
  for (const auto& item : json.items()) {
    keys.push_back(item.key());
  }
  EXPECT_EQ(keys, std::vector<std::string>(
                      {"evaluator", "alignment", "transform",
                       "num_ground_truth_frames", "num_model_images",
                       "num_matched", "num_missing", "num_unmatched_images",
                       "position_error_m", "rotation_error_deg",
                       "step_translation_error_m", "step_rotation_error_deg",
                       "position_thresholds_m", "position_recalls",
                       "rotation_thresholds_deg", "rotation_recalls",
                       "pose_recalls", "missing_frames", "images"}));
  EXPECT_EQ(json.at("evaluator"), "pose");
  EXPECT_EQ(json.at("alignment"), "sim3");
  EXPECT_TRUE(json.at("num_matched").is_number_unsigned());
  EXPECT_EQ(json.at("num_matched"), 6);
  EXPECT_EQ(json.at("position_recalls"), Json({1.0, 1.0, 1.0, 1.0}));
  EXPECT_EQ(json.at("position_thresholds_m"),
            Json(evaluation.position_thresholds_m));
  EXPECT_EQ(json.at("position_error_m").at("count"), 6);
  EXPECT_EQ(json.at("position_error_m").at("max").get<double>(),
            evaluation.position_stats_m.max);
  EXPECT_EQ(json.at("transform").at("scale").get<double>(), evaluation.scale);
  ASSERT_EQ(json.at("transform").at("rotation").size(), 3u);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(json.at("transform").at("rotation").at(r).at(c).get<double>(),
                evaluation.rotation(r, c));
    }
  }
  EXPECT_EQ(json.at("transform").at("translation").size(), 3u);
  EXPECT_TRUE(json.at("missing_frames").is_array());
  EXPECT_TRUE(json.at("missing_frames").empty());
  ASSERT_EQ(json.at("images").size(), 6u);
  EXPECT_EQ(json.at("images").at(5).at("frame"), "000005");
  EXPECT_EQ(json.at("images").at(5).at("rotation_error_deg").get<double>(),
            evaluation.errors[5].rotation_error_deg);
}

}  // namespace
}  // namespace colmap_lidar
