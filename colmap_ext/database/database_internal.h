// Helpers shared by the files that implement Database (database.cc and the
// database_<table>.cc files); not part of the module's interface.
#pragma once

#include <cstdint>

namespace colmap_lidar {
namespace database_internal {

// COLMAP's ids are unsigned; SQLite binds signed 64-bit integers.
inline int64_t ToSqliteId(const uint64_t id) {
  return static_cast<int64_t>(id);
}

}  // namespace database_internal
}  // namespace colmap_lidar
