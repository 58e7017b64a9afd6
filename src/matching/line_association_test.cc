#include "src/matching/line_association.h"

#include <gtest/gtest.h>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"
#include "src/matching/synthetic_line_views.h"

namespace colmap_lidar {
namespace {

LineMatchingOptions SyntheticOptions() {
  LineMatchingOptions options;
  options.t_LBD = 100.0;
  return options;
}

TEST(LineAssociation, ExactPosesGiveLongPureTracks) {
  const SyntheticLineScene scene = MakeSyntheticLineScene({});
  const LineAssociation association = AssociateLines(
      MakeSyntheticViews(scene, scene.cam_from_world), SyntheticOptions());
  const TrackQuality quality = EvaluateTracks(scene, association.tracks);
  std::cout << association.summary.Format() << std::endl;
  std::cout << "precision " << quality.precision << ", mean length "
            << quality.mean_track_length << ", recall " << quality.recall
            << std::endl;
  EXPECT_GE(quality.precision, 0.98);
  EXPECT_GE(quality.mean_track_length, 5.0);
  EXPECT_GE(quality.recall, 0.8);
  EXPECT_EQ(association.summary.num_tracks, association.tracks.size());
}

TEST(LineAssociation, NoisyPriorsWithUncertaintyTolerances) {
  const SyntheticLineScene scene = MakeSyntheticLineScene({});
  const std::vector<Rigid3d> noisy =
      PerturbPoses(scene.cam_from_world, 0.5, 5.0, /*seed=*/2);
  LineMatchingOptions options = SyntheticOptions();
  options.pose_sigma_t_m = 0.5;
  options.pose_sigma_r_deg = 5.0;
  options.refine_relative_poses = false;
  const LineAssociation association =
      AssociateLines(MakeSyntheticViews(scene, noisy), options);
  const TrackQuality quality = EvaluateTracks(scene, association.tracks);
  std::cout << association.summary.Format() << std::endl;
  std::cout << "precision " << quality.precision << ", mean length "
            << quality.mean_track_length << ", recall " << quality.recall
            << std::endl;
  EXPECT_GE(quality.precision, 0.9);
  EXPECT_GE(quality.mean_track_length, 2.5);
}

TEST(LineAssociation, NoisyPriorsWithPairRegistration) {
  // The views registered on their segments (relative_line_pose.h, then
  // pose_graph.h), Algorithm 1 with the exact-pose thresholds.
  const SyntheticLineScene scene = MakeSyntheticLineScene({});
  const std::vector<Rigid3d> noisy =
      PerturbPoses(scene.cam_from_world, 0.5, 5.0, /*seed=*/2);
  LineMatchingOptions options = SyntheticOptions();
  options.pose_sigma_t_m = 0.5;
  options.pose_sigma_r_deg = 5.0;
  ASSERT_TRUE(options.RegistersPairs());
  const LineAssociation association =
      AssociateLines(MakeSyntheticViews(scene, noisy), options);
  const TrackQuality quality = EvaluateTracks(scene, association.tracks);
  std::cout << association.summary.Format() << std::endl;
  std::cout << "precision " << quality.precision << ", mean length "
            << quality.mean_track_length << ", recall " << quality.recall
            << std::endl;
  EXPECT_GT(association.summary.pairwise.num_registered_pairs, 0u);
  EXPECT_GT(association.summary.pairwise.num_consistent_pairs,
            association.summary.pairwise.num_registered_pairs / 2);
  EXPECT_GE(quality.precision, 0.98);
  EXPECT_GE(quality.mean_track_length, 5.0);
  EXPECT_GE(quality.recall, 0.8);
}

TEST(LineAssociation, ClearRepairsWhatConnectedComponentsDrop) {
  // Geometry only (no descriptors) with noisy priors and the thresholds
  // grown by the pose uncertainty (no registration): the window lips and
  // backs, 15 cm apart, get confused and pairwise matches conflict.
  const SyntheticLineScene scene = MakeSyntheticLineScene({});
  const std::vector<Rigid3d> noisy =
      PerturbPoses(scene.cam_from_world, 0.5, 5.0, /*seed=*/2);
  LineMatchingOptions options;
  options.t_LBD = 256.0;
  options.refine_relative_poses = false;
  options.pose_sigma_t_m = 0.5;
  options.pose_sigma_r_deg = 5.0;
  const std::vector<MatchingView> views = MakeSyntheticViews(scene, noisy);
  const LineAssociation with_clear = AssociateLines(views, options);
  options.use_clear = false;
  const LineAssociation without = AssociateLines(views, options);
  const TrackQuality a = EvaluateTracks(scene, with_clear.tracks);
  const TrackQuality b = EvaluateTracks(scene, without.tracks);
  std::cout << "CLEAR: " << a.num_tracks << " tracks, precision "
            << a.precision << ", recall " << a.recall
            << "; connected components: " << b.num_tracks
            << " tracks, precision " << b.precision << ", recall " << b.recall
            << std::endl;
  EXPECT_GT(with_clear.summary.num_matches_removed, 0u);
  EXPECT_GT(a.recall, b.recall);
  EXPECT_GE(a.precision, b.precision);
}

TEST(LineAssociation, WorkspaceRoundTrip) {
  const SyntheticLineScene scene = MakeSyntheticLineScene({});
  const std::string dir = testing::CreateTestDir();
  const std::string database_path = JoinPaths(dir, "database.db");
  Reconstruction model;
  {
    Database database(database_path);
    Camera camera = scene.camera;
    camera.camera_id = database.WriteCamera(camera);
    model.cameras[camera.camera_id] = camera;
    // Image ids 1..N as MakeSyntheticViews numbers them.
    for (size_t v = 0; v < scene.segments.size(); ++v) {
      DatabaseImage db_image;
      db_image.image_id = static_cast<image_t>(v + 1);
      db_image.name = "view" + std::to_string(v) + ".png";
      db_image.camera_id = camera.camera_id;
      database.WriteImage(db_image);
      WriteLineSegments(&database, db_image.image_id, scene.segments[v]);
      Image image;
      image.image_id = db_image.image_id;
      image.name = db_image.name;
      image.camera_id = camera.camera_id;
      image.cam_from_world = scene.cam_from_world[v];
      model.images.push_back(image);
    }
  }
  Database database(database_path);
  LineMatchingOptions options = SyntheticOptions();
  // No scans in this database: the visibility test runs without LIDAR.
  const LineAssociation association =
      MatchWorkspaceLines(&database, model, options);
  ASSERT_GT(association.tracks.size(), 50u);
  EXPECT_EQ(NumLineTracks(database), association.tracks.size());
  EXPECT_EQ(NumLineMatches(database), association.pairwise_matches.size());
  const std::vector<LineTrackRecord> read = ReadLineTracks(database);
  ASSERT_EQ(read.size(), association.tracks.size());
  EXPECT_EQ(read[0].plucker, association.tracks[0].plucker);
  EXPECT_EQ(EvaluateTracks(scene, read).precision,
            EvaluateTracks(scene, association.tracks).precision);
  // A match of the table is one of Algorithm 1's, in pair orientation.
  const PairwiseLineMatch& match = association.pairwise_matches.front();
  const LineMatchesBlob blob = ReadLineMatches(
      database, static_cast<image_t>(match.view2 + 1),
      static_cast<image_t>(match.view1 + 1));
  bool found = false;
  for (int r = 0; r < blob.rows(); ++r) {
    found |= blob(r, 0) == static_cast<uint32_t>(match.segment2) &&
             blob(r, 1) == static_cast<uint32_t>(match.segment1);
  }
  EXPECT_TRUE(found);

  // Re-running replaces the tables.
  MatchWorkspaceLines(&database, model, options);
  EXPECT_EQ(NumLineTracks(database), association.tracks.size());

  // lines3D next to the model.
  SetModelLines3D(association.tracks, &model);
  const std::string model_dir = JoinPaths(dir, "model");
  WriteReconstruction(model_dir, model, ModelFormat::kBinary);
  const Reconstruction model_read = ReadReconstruction(model_dir);
  ASSERT_EQ(model_read.lines3D.size(), association.tracks.size());
  const Line3D& line = model_read.lines3D.at(1);
  EXPECT_EQ(line.start_in_world, association.tracks[0].start_in_world);
  EXPECT_EQ(line.track.size(), association.tracks[0].elements.size());
}

}  // namespace
}  // namespace colmap_lidar
