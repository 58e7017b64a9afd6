// Helpers shared by the files that implement ply.h (ply.cc, ply_header.cc,
// ply_reader.cc, ply_writer.cc); not part of the module's interface.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "colmap_ext/util/ply.h"

namespace colmap_lidar {
namespace ply_internal {

inline bool IsIntegerType(PlyScalarType type) {
  return type != PlyScalarType::kFloat32 && type != PlyScalarType::kFloat64;
}

// Header description of one property: a scalar, or a list with a count type
// and an item type.
struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyScalarType count_type = PlyScalarType::kUInt8;
  PlyScalarType type = PlyScalarType::kFloat32;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  // Offset of the first body byte in the file content.
  size_t body_offset = 0;
};

// Parses the header; the content must start with "ply". Throws naming
// `path` (ply_header.cc).
PlyHeader ParseHeader(const std::string& content, const std::string& path);

}  // namespace ply_internal
}  // namespace colmap_lidar
