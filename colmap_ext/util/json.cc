#include "colmap_ext/util/json.h"

#include <ostream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

void WriteJsonFile(const std::string& path, const Json& json) {
  // Serialised before the file is opened, so that a string that is not
  // UTF-8 leaves no file behind.
  std::string text;
  try {
    text = json.dump(/*indent=*/2);
  } catch (const Json::exception& error) {
    THROW_ERROR("Cannot write the JSON file " << path << ": "
                                              << error.what());
  }
  text += '\n';
  WriteFileAtomically(
      path, [&text](std::ostream& stream) { stream << text; },
      /*binary=*/false);
}

Json ReadJsonFile(const std::string& path) {
  const std::string text = ReadTextFile(path);
  try {
    return Json::parse(text);
  } catch (const Json::exception& error) {
    THROW_ERROR("Cannot parse the JSON file " << path << ": "
                                              << error.what());
  }
}

}  // namespace colmap_lidar
