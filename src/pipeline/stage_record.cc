#include "src/pipeline/stage_record.h"

#include <cmath>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {

void WriteStageRecord(const std::string& path, const StageRecord& record) {
  THROW_CHECK(record.note.find('\n') == std::string::npos,
              "Stage note of " << record.stage << " has a newline");
  WriteFileAtomically(
      path,
      [&record](std::ostream& stream) {
        stream << std::setprecision(17);
        stream << "stage " << record.stage << "\n"
               << "wall_seconds " << record.wall_seconds << "\n"
               << "cpu_seconds " << record.cpu_seconds << "\n"
               << "peak_memory_bytes " << record.peak_memory_bytes << "\n"
               << "finished_at " << record.finished_at << "\n"
               << "note " << record.note << "\n";
      },
      /*binary=*/false);
}

bool ReadStageRecord(const std::string& path, StageRecord* record) {
  if (!ExistsFile(path)) {
    return false;
  }
  std::ifstream stream(path);
  THROW_CHECK(stream.good(), "Cannot read the stage mark " << path);
  *record = StageRecord();
  bool has_stage = false;
  std::string line;
  int line_number = 0;
  while (std::getline(stream, line)) {
    ++line_number;
    if (StringTrim(line).empty()) {
      continue;
    }
    const size_t space = line.find(' ');
    const std::string key = line.substr(0, space);
    const std::string value =
        space == std::string::npos ? "" : line.substr(space + 1);
    try {
      if (key == "stage") {
        record->stage = value;
        has_stage = !value.empty();
      } else if (key == "wall_seconds") {
        record->wall_seconds = std::stod(value);
      } else if (key == "cpu_seconds") {
        record->cpu_seconds = std::stod(value);
      } else if (key == "peak_memory_bytes") {
        record->peak_memory_bytes = std::stoull(value);
      } else if (key == "finished_at") {
        record->finished_at = value;
      } else if (key == "note") {
        record->note = value;
      } else {
        THROW_ERROR("Unknown key '" << key << "' in the stage mark " << path
                                   << ", line " << line_number);
      }
    } catch (const std::logic_error&) {
      THROW_ERROR("Bad value '" << value << "' for " << key
                                << " in the stage mark " << path << ", line "
                                << line_number);
    }
  }
  THROW_CHECK(has_stage, "The stage mark " << path << " names no stage");
  THROW_CHECK(std::isfinite(record->wall_seconds) &&
                  std::isfinite(record->cpu_seconds),
              "Non-finite time in the stage mark " << path);
  return true;
}

void WriteStageRecordsJson(const std::string& path,
                           const std::vector<StageRecord>& records) {
  Json stages = Json::array();
  for (const StageRecord& record : records) {
    Json& stage = stages.emplace_back();
    stage["stage"] = record.stage;
    stage["wall_seconds"] = record.wall_seconds;
    stage["cpu_seconds"] = record.cpu_seconds;
    stage["peak_memory_bytes"] = record.peak_memory_bytes;
    stage["finished_at"] = record.finished_at;
    stage["note"] = record.note;
  }
  Json json;
  json["stages"] = std::move(stages);
  WriteJsonFile(path, json);
}

std::string UtcTimestamp() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  std::ostringstream text;
  text << std::put_time(&utc, "%Y-%m-%dT%H:%M:%SZ");
  return text.str();
}

}  // namespace colmap_lidar
