// What a pipeline stage did: its times and peak memory, kept in
// <workspace>/pipeline/<stage>.done once the stage has finished. The file is
// also the stage's "done" mark: a re-run skips a stage whose mark exists
// (resumable after an interruption), and running a stage again removes the
// marks of all later stages, whose inputs it changes.
//
// Format: one "key value" pair per line (value = the rest of the line):
//   stage patch_match
//   wall_seconds 212.4
//   cpu_seconds 401.9
//   peak_memory_bytes 812343296
//   finished_at 2026-11-22T05:12:03Z
//   note 60 reference images, 60 computed
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace colmap_lidar {

struct StageRecord {
  std::string stage;
  double wall_seconds = 0.0;
  // User + system time of the process and the colmap children it ran.
  double cpu_seconds = 0.0;
  // Largest resident size of the process or of one child during the stage.
  size_t peak_memory_bytes = 0;
  // UTC, ISO 8601.
  std::string finished_at;
  // One line about the outcome (counts); no newlines.
  std::string note;
};

// Written atomically; throws naming the path on a write failure.
void WriteStageRecord(const std::string& path, const StageRecord& record);
// Returns false when the file does not exist; throws naming the path and
// line when it exists but cannot be parsed (a corrupt mark is not "done").
bool ReadStageRecord(const std::string& path, StageRecord* record);

// <records_path>/stages.json: the records in pipeline order, for the report.
void WriteStageRecordsJson(const std::string& path,
                           const std::vector<StageRecord>& records);

// The current UTC time as 2026-11-22T05:12:03Z.
std::string UtcTimestamp();

}  // namespace colmap_lidar
