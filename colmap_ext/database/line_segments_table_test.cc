#include "colmap_ext/database/line_segments_table.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

LineSegmentRecord MakeSegment(int seed) {
  LineSegmentRecord segment;
  segment.start2D = Eigen::Vector2d(10.5 + seed, 20.25);
  segment.end2D = Eigen::Vector2d(100.125, 200.0 - seed);
  segment.start3D_in_cam = Eigen::Vector3d(-1.0, 0.5, 5.0 + seed);
  segment.end3D_in_cam = Eigen::Vector3d(1.0 / 3.0, -0.25, 7.0);
  segment.num_inliers = 12 + seed;
  for (int i = 0; i < 32; ++i) {
    segment.descriptor[i] = static_cast<uint8_t>(i * 7 + seed);
  }
  return segment;
}

void ExpectEqual(const LineSegmentRecord& a, const LineSegmentRecord& b) {
  EXPECT_EQ(a.start2D, b.start2D);
  EXPECT_EQ(a.end2D, b.end2D);
  EXPECT_EQ(a.start3D_in_cam, b.start3D_in_cam);
  EXPECT_EQ(a.end3D_in_cam, b.end3D_in_cam);
  EXPECT_EQ(a.num_inliers, b.num_inliers);
  EXPECT_EQ(a.descriptor, b.descriptor);
}

class LineSegmentsTableTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = JoinPaths(testing::CreateTestDir(), "database.db");
    database_.Open(path_);
    const camera_t camera_id = database_.WriteCamera(
        Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240}));
    for (const char* name : {"a.png", "b.png"}) {
      DatabaseImage image;
      image.name = name;
      image.camera_id = camera_id;
      image_ids_.push_back(database_.WriteImage(image));
    }
  }

  std::string path_;
  Database database_;
  std::vector<image_t> image_ids_;
};

TEST_F(LineSegmentsTableTest, TableIsCreatedOnOpen) {
  SqliteStatement statement = database_.Prepare(
      "SELECT count(*) FROM sqlite_master WHERE name = 'ext_line_segments'");
  ASSERT_TRUE(statement.Step());
  EXPECT_EQ(statement.ColumnInt64(0), 1);
}

TEST_F(LineSegmentsTableTest, RoundTripExactBytes) {
  const std::vector<LineSegmentRecord> segments = {MakeSegment(0),
                                                   MakeSegment(1),
                                                   MakeSegment(2)};
  WriteLineSegments(&database_, image_ids_[0], segments);
  database_.Close();
  database_.Open(path_);
  const std::vector<LineSegmentRecord> read =
      ReadLineSegments(database_, image_ids_[0]);
  ASSERT_EQ(read.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    ExpectEqual(read[i], segments[i]);
  }
  EXPECT_TRUE(ReadLineSegments(database_, image_ids_[1]).empty());
  EXPECT_EQ(NumLineSegments(database_), 3u);
  EXPECT_EQ(NumLineSegmentsForImage(database_, image_ids_[0]), 3u);
  EXPECT_EQ(ReadImageIdsWithLineSegments(database_),
            std::vector<image_t>{image_ids_[0]});

  // The blob layout is the documented one: 4 then 6 float64.
  SqliteStatement statement = database_.Prepare(
      "SELECT length(segment2D), length(segment3D), length(descriptor) FROM "
      "ext_line_segments WHERE idx = 1");
  ASSERT_TRUE(statement.Step());
  EXPECT_EQ(statement.ColumnInt64(0), 32);
  EXPECT_EQ(statement.ColumnInt64(1), 48);
  EXPECT_EQ(statement.ColumnInt64(2), 32);
}

TEST_F(LineSegmentsTableTest, RewriteReplacesOnlyThatImage) {
  WriteLineSegments(&database_, image_ids_[0],
                    {MakeSegment(0), MakeSegment(1), MakeSegment(2)});
  WriteLineSegments(&database_, image_ids_[1], {MakeSegment(5)});
  WriteLineSegments(&database_, image_ids_[0], {MakeSegment(9)});
  const std::vector<LineSegmentRecord> first =
      ReadLineSegments(database_, image_ids_[0]);
  ASSERT_EQ(first.size(), 1u);
  ExpectEqual(first[0], MakeSegment(9));
  ASSERT_EQ(ReadLineSegments(database_, image_ids_[1]).size(), 1u);
  ExpectEqual(ReadLineSegments(database_, image_ids_[1])[0], MakeSegment(5));
  WriteLineSegments(&database_, image_ids_[0], {});
  EXPECT_EQ(NumLineSegments(database_), 1u);
}

TEST_F(LineSegmentsTableTest, UnknownImageThrowsAndLeavesNothing) {
  EXPECT_THROW(WriteLineSegments(&database_, 999, {MakeSegment(0)}), Error);
  EXPECT_EQ(NumLineSegments(database_), 0u);
}

TEST_F(LineSegmentsTableTest, DeletingTheImageCascades) {
  WriteLineSegments(&database_, image_ids_[0], {MakeSegment(0)});
  database_.Execute("DELETE FROM images WHERE image_id = " +
                    std::to_string(image_ids_[0]));
  EXPECT_EQ(NumLineSegments(database_), 0u);
}

TEST_F(LineSegmentsTableTest, StockColmapStillOpensTheDatabase) {
  WriteLineSegments(&database_, image_ids_[0], {MakeSegment(0)});
  database_.Close();
  // database_cleaner opens the file with foreign keys on and deletes
  // images; the cascade must not make it fail.
  const std::string log = JoinPaths(testing::CreateTestDir(), "colmap.log");
  EXPECT_EQ(testing::RunCommand("colmap database_cleaner --database_path " +
                                    path_ + " --type images",
                                log),
            0)
      << ReadTextFile(log);
  database_.Open(path_);
  EXPECT_EQ(database_.NumImages(), 0u);
  EXPECT_EQ(NumLineSegments(database_), 0u);
}

TEST_F(LineSegmentsTableTest, CacheReadsSegmentsAndNamesTheDatabase) {
  WriteLineSegments(&database_, image_ids_[0], {MakeSegment(0), MakeSegment(1)});
  LineSegmentCache cache(database_);
  ExpectEqual(cache.Segment(image_ids_[0], 1, 7), MakeSegment(1));
  ExpectEqual(cache.Segment(image_ids_[0], 0, 7), MakeSegment(0));
  try {
    cache.Segment(image_ids_[1], 0, 7);  // b.png has no segment.
    FAIL() << "expected an error";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(path_), std::string::npos) << message;
    EXPECT_NE(message.find("line track 7"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace colmap_lidar
