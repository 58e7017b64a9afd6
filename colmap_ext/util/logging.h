// Error policy (see docs/house-style): programmer errors and I/O failures
// throw colmap_lidar::Error with a message that names the file or option;
// the command boundary (src/exe) turns it into a message and a
// non-zero exit. Expected empty results are values plus a LOG(WARNING).
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

#include <glog/logging.h>

namespace colmap_lidar {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace colmap_lidar

// Throws colmap_lidar::Error with a streamed message:
//   THROW_ERROR("Cannot open " << path);
#define THROW_ERROR(stream_expr)                            \
  do {                                                      \
    std::ostringstream colmap_lidar_error_stream;           \
    colmap_lidar_error_stream << stream_expr;               \
    throw ::colmap_lidar::Error(colmap_lidar_error_stream.str()); \
  } while (false)

// Throws colmap_lidar::Error unless the condition holds:
//   THROW_CHECK(file.good(), "Cannot read " << path);
#define THROW_CHECK(condition, stream_expr) \
  do {                                      \
    if (!(condition)) {                     \
      THROW_ERROR(stream_expr);             \
    }                                       \
  } while (false)
