#include "src/sfm/workspace_line_adjustment.h"

#include <gtest/gtest.h>

#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/database/line_tracks_table.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"
#include "src/eval/segment_io.h"
#include "src/matching/line_association.h"
#include "src/matching/synthetic_line_views.h"

namespace colmap_lidar {
namespace {

// A workspace of the synthetic facade on disk (src/matching/
// synthetic_line_views.h): database.db with every view's segments (2D and
// LIDAR 3D endpoints) and prior poses, model/ with the poses perturbed by
// 5 cm / 0.5 deg, and the line tracks of the association (line_matcher)
// in ext_line_tracks unless `with_tracks` is false.
class WorkspaceLineAdjustmentTest : public ::testing::Test {
 protected:
  void MakeWorkspace(bool with_tracks) {
    const SyntheticLineScene scene = MakeSyntheticLineScene({});
    num_views_ = scene.segments.size();
    dir_ = testing::CreateTestDir();
    paths_.database_path = JoinPaths(dir_, "database.db");
    paths_.input_path = JoinPaths(dir_, "model");
    paths_.output_path = JoinPaths(dir_, "refined");
    const std::vector<Rigid3d> noisy =
        PerturbPoses(scene.cam_from_world, 0.05, 0.5, /*seed=*/3);
    Database database(paths_.database_path);
    Reconstruction model;
    Camera camera = scene.camera;
    camera.camera_id = database.WriteCamera(camera);
    model.cameras[camera.camera_id] = camera;
    for (size_t v = 0; v < num_views_; ++v) {
      DatabaseImage db_image;
      db_image.image_id = static_cast<image_t>(v + 1);
      db_image.name = "view" + std::to_string(v) + ".png";
      db_image.camera_id = camera.camera_id;
      db_image.prior_q = noisy[v].rotation;
      db_image.prior_t = noisy[v].Inverse().translation;
      database.WriteImage(db_image);
      WriteLineSegments(&database, db_image.image_id, scene.segments[v]);
      Image image;
      image.image_id = db_image.image_id;
      image.name = db_image.name;
      image.camera_id = camera.camera_id;
      image.cam_from_world = noisy[v];
      model.images.push_back(image);
    }
    WriteReconstruction(paths_.input_path, model, ModelFormat::kBinary);
    if (with_tracks) {
      LineMatchingOptions matching;
      matching.t_LBD = 100.0;  // The synthetic descriptors.
      matching.pose_sigma_t_m = 0.05;
      matching.pose_sigma_r_deg = 0.5;
      num_tracks_ =
          MatchWorkspaceLines(&database, model, matching).tracks.size();
      ASSERT_GT(num_tracks_, 50u);
    }
    options_.num_threads = 2;
  }

  std::string dir_;
  size_t num_views_ = 0;
  size_t num_tracks_ = 0;
  WorkspaceLineAdjustmentPaths paths_;
  LineBundleAdjustmentOptions options_;
};

TEST_F(WorkspaceLineAdjustmentTest, WritesRefinedModelAndPly) {
  MakeWorkspace(/*with_tracks=*/true);
  const WorkspaceLineAdjustmentSummary summary =
      RunWorkspaceLineAdjustment(paths_, options_);
  ASSERT_EQ(summary.error, "");
  ASSERT_TRUE(summary.solved);
  EXPECT_TRUE(summary.adjustment.usable);
  EXPECT_EQ(summary.load.num_tracks_in_database,
            static_cast<int>(num_tracks_));
  EXPECT_EQ(summary.load.num_tracks, static_cast<int>(num_tracks_));
  EXPECT_EQ(summary.load.num_observations_without_image, 0);
  EXPECT_EQ(summary.num_prior_images, -1);  // No priors by default.
  EXPECT_EQ(summary.adjustment.num_pose_prior_residuals, 0);
  EXPECT_GT(summary.adjustment.num_line_residuals, 0);
  EXPECT_LE(summary.adjustment.final_cost, summary.adjustment.initial_cost);

  // The refined model: the images, no points, one lines3D per track.
  EXPECT_EQ(summary.num_images, num_views_);
  EXPECT_EQ(summary.num_points3D, 0u);
  EXPECT_EQ(summary.num_lines3D, num_tracks_);
  const Reconstruction refined = ReadReconstruction(paths_.output_path);
  EXPECT_EQ(refined.images.size(), num_views_);
  ASSERT_EQ(refined.lines3D.size(), num_tracks_);
  // The first image is the gauge, so its pose is the input's; another one
  // moved.
  const Reconstruction input = ReadReconstruction(paths_.input_path);
  EXPECT_TRUE(refined.images[0].cam_from_world.translation.isApprox(
      input.images[0].cam_from_world.translation, 1e-12));
  EXPECT_FALSE(refined.images[1].cam_from_world.translation.isApprox(
      input.images[1].cam_from_world.translation, 1e-9));

  // The PLY next to the model holds the same segments.
  EXPECT_EQ(summary.lines_ply_path,
            JoinPaths(paths_.output_path, "lines3D.ply"));
  const std::vector<Segment3D> segments =
      ReadSegmentsPly(summary.lines_ply_path);
  ASSERT_EQ(segments.size(), num_tracks_);
  const Line3D& first = refined.lines3D.begin()->second;
  EXPECT_TRUE(segments[0].start.isApprox(first.start_in_world, 1e-12));
  EXPECT_TRUE(segments[0].end.isApprox(first.end_in_world, 1e-12));
}

TEST_F(WorkspaceLineAdjustmentTest, PosePriorsAndPlyPath) {
  MakeWorkspace(/*with_tracks=*/true);
  options_.prior_position_sigma_m = 0.05;
  options_.prior_rotation_sigma_deg = 0.5;
  options_.gauge = LineBAGauge::kPosePriors;
  paths_.lines_ply_path = JoinPaths(dir_, "segments.ply");
  const WorkspaceLineAdjustmentSummary summary =
      RunWorkspaceLineAdjustment(paths_, options_);
  ASSERT_EQ(summary.error, "");
  EXPECT_EQ(summary.num_prior_images, static_cast<int>(num_views_));
  EXPECT_EQ(summary.adjustment.num_pose_prior_residuals,
            static_cast<int>(num_views_));
  EXPECT_EQ(summary.adjustment.num_fixed_images, 0);
  EXPECT_EQ(summary.lines_ply_path, paths_.lines_ply_path);
  EXPECT_EQ(ReadSegmentsPly(paths_.lines_ply_path).size(), num_tracks_);
  EXPECT_FALSE(ExistsFile(JoinPaths(paths_.output_path, "lines3D.ply")));
  EXPECT_EQ(ReadReconstruction(paths_.output_path).lines3D.size(),
            num_tracks_);
}

TEST_F(WorkspaceLineAdjustmentTest, RefusesMissingDatabase) {
  MakeWorkspace(/*with_tracks=*/false);
  paths_.database_path = JoinPaths(dir_, "missing.db");
  const WorkspaceLineAdjustmentSummary summary =
      RunWorkspaceLineAdjustment(paths_, options_);
  EXPECT_EQ(summary.error,
            "--database_path " + paths_.database_path + " does not exist");
  EXPECT_FALSE(summary.solved);
  EXPECT_FALSE(ExistsFile(paths_.database_path));
  EXPECT_FALSE(ExistsDir(paths_.output_path));
}

TEST_F(WorkspaceLineAdjustmentTest, RefusesMissingModel) {
  MakeWorkspace(/*with_tracks=*/true);
  paths_.input_path = JoinPaths(dir_, "no_model");
  CreateDirIfNotExists(paths_.input_path);
  const WorkspaceLineAdjustmentSummary summary =
      RunWorkspaceLineAdjustment(paths_, options_);
  EXPECT_EQ(summary.error,
            "--input_path " + paths_.input_path + " holds no sparse model");
  EXPECT_FALSE(summary.solved);
  EXPECT_FALSE(ExistsDir(paths_.output_path));
}

TEST_F(WorkspaceLineAdjustmentTest, RefusesDatabaseWithoutTracks) {
  MakeWorkspace(/*with_tracks=*/false);
  const WorkspaceLineAdjustmentSummary summary =
      RunWorkspaceLineAdjustment(paths_, options_);
  EXPECT_EQ(summary.error,
            "--database_path " + paths_.database_path +
                " holds no line tracks (ext_line_tracks is empty): run "
                "line_matcher first");
  EXPECT_FALSE(summary.solved);
  EXPECT_FALSE(ExistsDir(paths_.output_path));
}

TEST_F(WorkspaceLineAdjustmentTest, UnusableSolutionWritesNothing) {
  // A model without the tracks' images: every track is dropped, there is
  // nothing to solve, and Ceres' summary is not usable.
  MakeWorkspace(/*with_tracks=*/true);
  Reconstruction no_images = ReadReconstruction(paths_.input_path);
  no_images.images.clear();
  paths_.input_path = JoinPaths(dir_, "no_images");
  WriteReconstruction(paths_.input_path, no_images, ModelFormat::kBinary);
  paths_.lines_ply_path = JoinPaths(dir_, "segments.ply");
  const WorkspaceLineAdjustmentSummary summary =
      RunWorkspaceLineAdjustment(paths_, options_);
  ASSERT_TRUE(summary.solved);
  EXPECT_FALSE(summary.adjustment.usable);
  EXPECT_EQ(summary.load.num_tracks, 0);
  EXPECT_GT(summary.load.num_observations_without_image, 0);
  EXPECT_EQ(summary.error,
            "line_bundle_adjuster: the solution is not usable (" +
                summary.adjustment.termination_message +
                "); nothing written");
  EXPECT_FALSE(ExistsDir(paths_.output_path));
  EXPECT_FALSE(ExistsFile(paths_.lines_ply_path));
}

}  // namespace
}  // namespace colmap_lidar
