#include "src/matching/workspace_line_matching.h"

#include <gtest/gtest.h>

#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/database/line_tracks_table.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/testing.h"
#include "src/matching/synthetic_line_views.h"

namespace colmap_lidar {
namespace {

// A workspace of the synthetic facade on disk: database.db with the
// segments of every view, and the exact poses as a sparse model in model/.
class WorkspaceLineMatchingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const SyntheticLineScene scene = MakeSyntheticLineScene({});
    num_views_ = scene.segments.size();
    dir_ = testing::CreateTestDir();
    paths_.database_path = JoinPaths(dir_, "database.db");
    paths_.input_path = JoinPaths(dir_, "model");
    Database database(paths_.database_path);
    Reconstruction model;
    Camera camera = scene.camera;
    camera.camera_id = database.WriteCamera(camera);
    model.cameras[camera.camera_id] = camera;
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
    WriteReconstruction(paths_.input_path, model, ModelFormat::kBinary);
    // The synthetic descriptors (see line_association_test).
    options_.t_LBD = 100.0;
  }

  size_t NumTracksInDatabase() const {
    return NumLineTracks(Database(paths_.database_path));
  }

  std::string dir_;
  size_t num_views_ = 0;
  WorkspaceLineMatchingPaths paths_;
  LineMatchingOptions options_;
};

TEST_F(WorkspaceLineMatchingTest, WritesTablesModelAndJson) {
  paths_.output_path = JoinPaths(dir_, "with_lines");
  paths_.tracks_json_path = JoinPaths(dir_, "tracks.json");
  const WorkspaceLineMatchingSummary summary =
      RunWorkspaceLineMatching(paths_, options_);
  ASSERT_EQ(summary.error, "");
  const size_t num_tracks = summary.association.num_tracks;
  EXPECT_GT(num_tracks, 50u);
  EXPECT_EQ(summary.association.num_views, static_cast<int>(num_views_));
  EXPECT_EQ(NumTracksInDatabase(), num_tracks);

  // The model copy: the input's images plus one lines3D per track.
  EXPECT_EQ(summary.num_model_lines3D, num_tracks);
  const Reconstruction written = ReadReconstruction(paths_.output_path);
  EXPECT_EQ(written.images.size(), num_views_);
  EXPECT_EQ(written.lines3D.size(), num_tracks);
  size_t num_observations = 0;
  for (const auto& [line3D_id, line3D] : written.lines3D) {
    EXPECT_GE(line3D.track.size(), 2u);
    num_observations += line3D.track.size();
  }
  EXPECT_EQ(num_observations, summary.association.num_track_observations);
  // The input model is left as it was.
  EXPECT_TRUE(ReadReconstruction(paths_.input_path).lines3D.empty());

  // The JSON: every track with its observations.
  EXPECT_EQ(summary.num_exported_tracks, num_tracks);
  const Json json = ReadJsonFile(paths_.tracks_json_path);
  EXPECT_EQ(json.at("num_tracks").get<size_t>(), num_tracks);
  ASSERT_EQ(json.at("tracks").size(), num_tracks);
  size_t num_json_observations = 0;
  for (const Json& track : json.at("tracks")) {
    num_json_observations += track.at("observations").size();
  }
  EXPECT_EQ(num_json_observations,
            summary.association.num_track_observations);
}

TEST_F(WorkspaceLineMatchingTest, OutputsAreOptional) {
  const WorkspaceLineMatchingSummary summary =
      RunWorkspaceLineMatching(paths_, options_);
  ASSERT_EQ(summary.error, "");
  EXPECT_GT(summary.association.num_tracks, 50u);
  // The tables are always written; the model copy and the JSON only when
  // asked for.
  EXPECT_EQ(NumTracksInDatabase(), summary.association.num_tracks);
  EXPECT_EQ(summary.num_model_lines3D, 0u);
  EXPECT_EQ(summary.num_exported_tracks, 0u);
  EXPECT_FALSE(ExistsFile(JoinPaths(dir_, "tracks.json")));
}

TEST_F(WorkspaceLineMatchingTest, RefusesMissingDatabase) {
  paths_.database_path = JoinPaths(dir_, "missing.db");
  paths_.output_path = JoinPaths(dir_, "with_lines");
  paths_.tracks_json_path = JoinPaths(dir_, "tracks.json");
  const WorkspaceLineMatchingSummary summary =
      RunWorkspaceLineMatching(paths_, options_);
  EXPECT_EQ(summary.error,
            "--database_path " + paths_.database_path + " does not exist");
  // Nothing created: no database, no model, no JSON.
  EXPECT_FALSE(ExistsFile(paths_.database_path));
  EXPECT_FALSE(ExistsDir(paths_.output_path));
  EXPECT_FALSE(ExistsFile(paths_.tracks_json_path));
}

TEST_F(WorkspaceLineMatchingTest, RefusesMissingModel) {
  paths_.input_path = JoinPaths(dir_, "no_model");
  CreateDirIfNotExists(paths_.input_path);
  paths_.output_path = JoinPaths(dir_, "with_lines");
  paths_.tracks_json_path = JoinPaths(dir_, "tracks.json");
  const WorkspaceLineMatchingSummary summary =
      RunWorkspaceLineMatching(paths_, options_);
  EXPECT_EQ(summary.error,
            "--input_path " + paths_.input_path + " holds no sparse model");
  EXPECT_EQ(NumTracksInDatabase(), 0u);
  EXPECT_FALSE(ExistsDir(paths_.output_path));
  EXPECT_FALSE(ExistsFile(paths_.tracks_json_path));
}

}  // namespace
}  // namespace colmap_lidar
