#include "src/matching/track_export.h"

#include <cmath>

#include <gtest/gtest.h>

#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

TEST(TrackExport, WritesValidJsonWithObservations) {
  const std::string dir = testing::CreateTestDir();
  Database database(JoinPaths(dir, "database.db"));
  const camera_t camera_id = database.WriteCamera(
      Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240}));
  std::vector<image_t> image_ids;
  for (const char* name : {"a \"quoted\".png", "sub/b.png"}) {
    DatabaseImage image;
    image.name = name;
    image.camera_id = camera_id;
    image_ids.push_back(database.WriteImage(image));
  }
  LineSegmentRecord segment;
  segment.start2D = {10.5, 20.25};
  segment.end2D = {100.0, 0.1};
  segment.start3D_in_cam = {-1.0, 0.5, 5.0};
  segment.end3D_in_cam = {1.0 / 3.0, -0.25, 7.0};
  WriteLineSegments(&database, image_ids[0], {LineSegmentRecord(), segment});
  WriteLineSegments(&database, image_ids[1], {segment});
  LineTrackRecord track;
  track.line3D_id = 4;
  track.plucker << 1, 0, 0, 0, 2, -3;
  track.elements = {{image_ids[0], 1}, {image_ids[1], 0}};
  const std::string path = JoinPaths(dir, "tracks.json");
  WriteLineTracksJson(path, database, {track});

  const Json json = ReadJsonFile(path);
  EXPECT_EQ(json.at("num_tracks"), 1);
  ASSERT_EQ(json.at("tracks").size(), 1u);
  const Json& track_json = json.at("tracks").at(0);
  std::vector<std::string> keys;
  for (const auto& item : track_json.items()) {
    keys.push_back(item.key());
  }
  EXPECT_EQ(keys, std::vector<std::string>({"line3D_id", "plucker",
                                            "start_in_world", "end_in_world",
                                            "observations"}));
  EXPECT_EQ(track_json.at("plucker"), Json({1.0, 0.0, 0.0, 0.0, 2.0, -3.0}));
  const Json& observation = track_json.at("observations").at(0);
  EXPECT_EQ(observation.at("image_name"), "a \"quoted\".png");
  EXPECT_EQ(observation.at("start2D"), Json({10.5, 20.25}));
  // The shortest round-trip text: 1/3 reads back exactly.
  EXPECT_EQ(observation.at("end3D_in_cam").at(0).get<double>(), 1.0 / 3.0);

  // An independent JSON parser reads it and finds the values.
  const std::string check = JoinPaths(dir, "check.py");
  WriteFileAtomically(
      check,
      [&](std::ostream& out) {
        out << "import json, sys\n"
               "d = json.load(open(sys.argv[1]))\n"
               "t = d['tracks'][0]\n"
               "assert d['num_tracks'] == 1 and t['line3D_id'] == 4\n"
               "assert t['plucker'] == [1, 0, 0, 0, 2, -3]\n"
               "o = t['observations']\n"
               "assert len(o) == 2 and o[1]['image_name'] == 'sub/b.png'\n"
               "assert o[0]['segment_idx'] == 1\n"
               "assert o[1]['end3D_in_cam'][0] == 1.0 / 3.0\n";
      },
      false);
  EXPECT_EQ(testing::RunCommand("python3 " + check + " " + path,
                                JoinPaths(dir, "check.log")),
            0)
      << ReadTextFile(JoinPaths(dir, "check.log"));

  // A missing segment is an error naming the track.
  track.elements[1].line2D_idx = 5;
  EXPECT_THROW(WriteLineTracksJson(path, database, {track}), Error);
  // So is a non-finite coordinate (JSON has no NaN).
  track.elements[1].line2D_idx = 0;
  track.plucker(0) = std::nan("");
  EXPECT_THROW(WriteLineTracksJson(path, database, {track}), Error);
}

}  // namespace
}  // namespace colmap_lidar
