#include "src/pipeline/stage_record.h"

#include <fstream>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

TEST(StageRecord, RoundTrips) {
  const std::string dir = testing::CreateTestDir();
  StageRecord record;
  record.stage = "patch_match";
  record.wall_seconds = 212.375;
  record.cpu_seconds = 401.5;
  record.peak_memory_bytes = 812343296;
  record.finished_at = UtcTimestamp();
  record.note = "60 references, 60 computed";
  const std::string path = JoinPaths(dir, "patch_match.done");
  WriteStageRecord(path, record);
  StageRecord read;
  ASSERT_TRUE(ReadStageRecord(path, &read));
  EXPECT_EQ(read.stage, record.stage);
  EXPECT_EQ(read.wall_seconds, record.wall_seconds);
  EXPECT_EQ(read.cpu_seconds, record.cpu_seconds);
  EXPECT_EQ(read.peak_memory_bytes, record.peak_memory_bytes);
  EXPECT_EQ(read.finished_at, record.finished_at);
  EXPECT_EQ(read.note, record.note);
  EXPECT_EQ(record.finished_at.size(), 20u);  // 2026-11-22T05:12:03Z
  EXPECT_EQ(record.finished_at.back(), 'Z');
}

TEST(StageRecord, MissingFileIsNotDone) {
  StageRecord record;
  EXPECT_FALSE(ReadStageRecord(JoinPaths(testing::CreateTestDir(), "x.done"), &record));
}

TEST(StageRecord, CorruptMarksThrowNamingTheFile) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "mesh.done");
  {
    std::ofstream stream(path);
    stream << "stage mesh\nwall_seconds abc\n";
  }
  StageRecord record;
  try {
    ReadStageRecord(path, &record);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("wall_seconds"),
              std::string::npos);
  }
  {
    std::ofstream stream(path);
    stream << "wall_seconds 1\n";
  }
  EXPECT_THROW(ReadStageRecord(path, &record), Error);
  {
    std::ofstream stream(path);
    stream << "stage mesh\ncolour blue\n";
  }
  EXPECT_THROW(ReadStageRecord(path, &record), Error);
}

TEST(StageRecord, NotesWithNewlinesAreRefused) {
  StageRecord record;
  record.stage = "fusion";
  record.note = "two\nlines";
  EXPECT_THROW(
      WriteStageRecord(JoinPaths(testing::CreateTestDir(), "fusion.done"), record),
      Error);
}

}  // namespace
}  // namespace colmap_lidar
