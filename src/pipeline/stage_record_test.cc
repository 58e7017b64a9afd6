#include "src/pipeline/stage_record.h"

#include <fstream>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
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

// stages.json: the keys src/pipeline/report.py and scripts/matrix_table.py
// read, in pipeline order.
TEST(StageRecord, RecordsJson) {
  StageRecord first;
  first.stage = "import";
  first.wall_seconds = 1.0;
  first.cpu_seconds = 0.1;
  first.peak_memory_bytes = 5000000000;
  first.finished_at = "2026-11-22T05:12:03Z";
  first.note = "60 \"frames\"";
  StageRecord second = first;
  second.stage = "mesh";
  second.wall_seconds = 212.375;
  const std::string path =
      JoinPaths(testing::CreateTestDir(), "stages.json");
  WriteStageRecordsJson(path, {first, second});
  const Json json = ReadJsonFile(path);
  ASSERT_EQ(json.size(), 1u);
  const Json& stages = json.at("stages");
  ASSERT_EQ(stages.size(), 2u);
  std::vector<std::string> keys;
  for (const auto& item : stages.at(0).items()) {
    keys.push_back(item.key());
  }
  EXPECT_EQ(keys, std::vector<std::string>(
                      {"stage", "wall_seconds", "cpu_seconds",
                       "peak_memory_bytes", "finished_at", "note"}));
  EXPECT_EQ(stages.at(0).at("stage"), "import");
  EXPECT_EQ(stages.at(1).at("stage"), "mesh");
  EXPECT_TRUE(stages.at(0).at("wall_seconds").is_number_float());
  EXPECT_EQ(stages.at(1).at("wall_seconds").get<double>(), 212.375);
  EXPECT_EQ(stages.at(0).at("cpu_seconds").get<double>(), 0.1);
  EXPECT_EQ(stages.at(0).at("peak_memory_bytes").get<uint64_t>(),
            5000000000u);
  EXPECT_EQ(stages.at(0).at("note"), "60 \"frames\"");
  // An empty pipeline is an empty list, not null.
  WriteStageRecordsJson(path, {});
  EXPECT_EQ(ReadJsonFile(path).at("stages"), Json::array());
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
