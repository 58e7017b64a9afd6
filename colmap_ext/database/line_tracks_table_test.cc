#include "colmap_ext/database/line_tracks_table.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

class LineTracksTableTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = JoinPaths(testing::CreateTestDir(), "database.db");
    database_.Open(path_);
    const camera_t camera_id = database_.WriteCamera(
        Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240}));
    for (const char* name : {"a.png", "b.png", "c.png"}) {
      DatabaseImage image;
      image.name = name;
      image.camera_id = camera_id;
      image_ids_.push_back(database_.WriteImage(image));
    }
  }

  LineTrackRecord MakeTrack(line3D_t id) const {
    LineTrackRecord track;
    track.line3D_id = id;
    track.plucker << 0.0, 0.6, 0.8, 1.0 / 3.0, -2.0, 7.5 + id;
    track.start_in_world = Eigen::Vector3d(1.0, 2.0, 3.0 + id);
    track.end_in_world = Eigen::Vector3d(-1.0, 0.125, 1e-3);
    track.elements = {{image_ids_[0], static_cast<uint32_t>(id)},
                      {image_ids_[2], static_cast<uint32_t>(2 * id + 1)}};
    return track;
  }

  std::string path_;
  Database database_;
  std::vector<image_t> image_ids_;
};

TEST_F(LineTracksTableTest, TablesAreCreatedOnOpen) {
  for (const char* table :
       {"ext_line_matches", "ext_line_tracks", "ext_line_track_elements"}) {
    SqliteStatement statement = database_.Prepare(
        std::string("SELECT count(*) FROM sqlite_master WHERE name = '") +
        table + "'");
    ASSERT_TRUE(statement.Step());
    EXPECT_EQ(statement.ColumnInt64(0), 1) << table;
  }
}

TEST_F(LineTracksTableTest, MatchesRoundTripInBothOrientations) {
  LineMatchesBlob matches(3, 2);
  matches << 0, 5, 1, 7, 4, 2;
  // Written from the larger id: stored with the smaller id's column first.
  WriteLineMatches(&database_, image_ids_[1], image_ids_[0], matches);
  database_.Close();
  database_.Open(path_);
  EXPECT_EQ(ReadLineMatches(database_, image_ids_[1], image_ids_[0]), matches);
  LineMatchesBlob swapped(3, 2);
  swapped << 5, 0, 7, 1, 2, 4;
  EXPECT_EQ(ReadLineMatches(database_, image_ids_[0], image_ids_[1]), swapped);
  EXPECT_EQ(ReadLineMatches(database_, image_ids_[0], image_ids_[2]).rows(),
            0);
  EXPECT_EQ(NumLineMatches(database_), 3u);

  // The row is keyed by COLMAP's pair id and the blob is rows x 2 uint32 in
  // the stored orientation.
  SqliteStatement statement = database_.Prepare(
      "SELECT pair_id, rows, cols, data FROM ext_line_matches");
  ASSERT_TRUE(statement.Step());
  EXPECT_EQ(statement.ColumnInt64(0),
            static_cast<int64_t>(image_ids_[0]) * 2147483647 + image_ids_[1]);
  EXPECT_EQ(statement.ColumnInt64(1), 3);
  EXPECT_EQ(statement.ColumnInt64(2), 2);
  uint32_t data[6];
  statement.ColumnBlobArray(3, 6, data, "data");
  EXPECT_EQ(data[0], 5u);
  EXPECT_EQ(data[1], 0u);
  EXPECT_EQ(data[5], 4u);

  // Rewriting replaces; ReadAll returns the stored orientation.
  LineMatchesBlob one(1, 2);
  one << 9, 8;
  WriteLineMatches(&database_, image_ids_[0], image_ids_[1], one);
  const auto all = ReadAllLineMatches(database_);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].second, one);
  ClearLineMatches(&database_);
  EXPECT_EQ(NumLineMatches(database_), 0u);
}

TEST_F(LineTracksTableTest, TracksRoundTripExactly) {
  const std::vector<LineTrackRecord> tracks = {MakeTrack(3), MakeTrack(1)};
  WriteLineTracks(&database_, tracks);
  database_.Close();
  database_.Open(path_);
  const std::vector<LineTrackRecord> read = ReadLineTracks(database_);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(NumLineTracks(database_), 2u);
  // Ordered by id.
  const LineTrackRecord& a = read[0];
  const LineTrackRecord b = MakeTrack(1);
  EXPECT_EQ(a.line3D_id, 1u);
  EXPECT_EQ(a.plucker, b.plucker);
  EXPECT_EQ(a.start_in_world, b.start_in_world);
  EXPECT_EQ(a.end_in_world, b.end_in_world);
  ASSERT_EQ(a.elements.size(), 2u);
  EXPECT_EQ(a.elements[1].image_id, image_ids_[2]);
  EXPECT_EQ(a.elements[1].line2D_idx, 3u);
  EXPECT_EQ(read[1].line3D_id, 3u);

  // Writing replaces every track.
  WriteLineTracks(&database_, {MakeTrack(7)});
  EXPECT_EQ(ReadLineTracks(database_).size(), 1u);
  ClearLineTracks(&database_);
  EXPECT_EQ(NumLineTracks(database_), 0u);
}

TEST_F(LineTracksTableTest, RefusesInconsistentTracksAndRollsBack) {
  WriteLineTracks(&database_, {MakeTrack(1)});
  // Two observations of one image in a track.
  LineTrackRecord twice = MakeTrack(2);
  twice.elements.push_back({image_ids_[0], 9});
  EXPECT_THROW(WriteLineTracks(&database_, {twice}), Error);
  // A segment in two tracks.
  LineTrackRecord a = MakeTrack(4);
  LineTrackRecord b = MakeTrack(5);
  b.elements[0] = a.elements[0];
  EXPECT_THROW(WriteLineTracks(&database_, {a, b}), Error);
  // A missing image.
  LineTrackRecord missing = MakeTrack(6);
  missing.elements[0].image_id = 999;
  EXPECT_THROW(WriteLineTracks(&database_, {missing}), Error);
  // Each failure left the previous content.
  const auto read = ReadLineTracks(database_);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].line3D_id, 1u);
}

TEST_F(LineTracksTableTest, DeletingAnImageRemovesItsElements) {
  WriteLineTracks(&database_, {MakeTrack(1)});
  database_.Execute("DELETE FROM images WHERE image_id = " +
                    std::to_string(image_ids_[2]));
  const auto read = ReadLineTracks(database_);
  ASSERT_EQ(read.size(), 1u);
  ASSERT_EQ(read[0].elements.size(), 1u);
  EXPECT_EQ(read[0].elements[0].image_id, image_ids_[0]);
}

}  // namespace
}  // namespace colmap_lidar
