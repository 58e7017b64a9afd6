// The PLY header parser (see ply_internal.h).
#include "colmap_ext/util/ply_internal.h"

#include <algorithm>
#include <cstdlib>
#include <sstream>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"

namespace colmap_lidar {
namespace ply_internal {
namespace {

bool ParseScalarType(const std::string& name, PlyScalarType* type) {
  if (name == "int8" || name == "char") {
    *type = PlyScalarType::kInt8;
  } else if (name == "uint8" || name == "uchar") {
    *type = PlyScalarType::kUInt8;
  } else if (name == "int16" || name == "short") {
    *type = PlyScalarType::kInt16;
  } else if (name == "uint16" || name == "ushort") {
    *type = PlyScalarType::kUInt16;
  } else if (name == "int32" || name == "int") {
    *type = PlyScalarType::kInt32;
  } else if (name == "uint32" || name == "uint") {
    *type = PlyScalarType::kUInt32;
  } else if (name == "float32" || name == "float") {
    *type = PlyScalarType::kFloat32;
  } else if (name == "float64" || name == "double") {
    *type = PlyScalarType::kFloat64;
  } else {
    return false;
  }
  return true;
}

}  // namespace

PlyHeader ParseHeader(const std::string& content, const std::string& path) {
  PlyHeader header;
  size_t pos = 0;
  auto next_line = [&](std::string* line) {
    if (pos >= content.size()) {
      return false;
    }
    size_t end = content.find('\n', pos);
    if (end == std::string::npos) {
      end = content.size();
    }
    *line = content.substr(pos, end - pos);
    if (!line->empty() && line->back() == '\r') {
      line->pop_back();
    }
    pos = end + 1;
    return true;
  };

  std::string line;
  THROW_CHECK(next_line(&line) && line == "ply",
              "Bad PLY magic (first line is not \"ply\") in " << path);

  bool has_format = false;
  bool has_end = false;
  int line_number = 1;
  while (next_line(&line)) {
    ++line_number;
    std::istringstream tokens(line);
    std::string keyword;
    tokens >> keyword;
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") {
      continue;
    }
    if (keyword == "end_header") {
      has_end = true;
      break;
    }
    if (keyword == "format") {
      std::string format;
      std::string version;
      tokens >> format >> version;
      if (format == "ascii") {
        header.format = PlyFormat::kAscii;
      } else if (format == "binary_little_endian") {
        header.format = PlyFormat::kBinaryLittleEndian;
      } else if (format == "binary_big_endian") {
        header.format = PlyFormat::kBinaryBigEndian;
      } else {
        THROW_ERROR("Bad PLY header in " << path << " line " << line_number
                                         << ": unknown format '" << format
                                         << "'");
      }
      THROW_CHECK(version == "1.0", "Bad PLY header in "
                                        << path << " line " << line_number
                                        << ": unsupported version '"
                                        << version << "'");
      has_format = true;
    } else if (keyword == "element") {
      PlyElement element;
      std::string count;
      tokens >> element.name >> count;
      THROW_CHECK(!element.name.empty() && !count.empty() &&
                      count.find_first_not_of("0123456789") ==
                          std::string::npos &&
                      count.size() <= 19,
                  "Bad PLY header in " << path << " line " << line_number
                                       << ": '" << line << "'");
      element.count = std::strtoull(count.c_str(), nullptr, 10);
      header.elements.push_back(element);
    } else if (keyword == "property") {
      THROW_CHECK(!header.elements.empty(),
                  "Bad PLY header in " << path << " line " << line_number
                                       << ": property before any element");
      PlyProperty property;
      std::string type_name;
      tokens >> type_name;
      if (type_name == "list") {
        std::string count_type_name;
        std::string item_type_name;
        tokens >> count_type_name >> item_type_name;
        property.is_list = true;
        THROW_CHECK(ParseScalarType(count_type_name, &property.count_type),
                    "Unsupported PLY type '" << count_type_name << "' in "
                                             << path << " line "
                                             << line_number);
        THROW_CHECK(IsIntegerType(property.count_type),
                    "Unsupported PLY list count type '"
                        << count_type_name << "' in " << path << " line "
                        << line_number);
        THROW_CHECK(ParseScalarType(item_type_name, &property.type),
                    "Unsupported PLY type '" << item_type_name << "' in "
                                             << path << " line "
                                             << line_number);
      } else {
        THROW_CHECK(!type_name.empty(), "Bad PLY header in "
                                            << path << " line " << line_number
                                            << ": property without type");
        THROW_CHECK(ParseScalarType(type_name, &property.type),
                    "Unsupported PLY type '" << type_name << "' in " << path
                                             << " line " << line_number);
      }
      tokens >> property.name;
      THROW_CHECK(!property.name.empty(),
                  "Bad PLY header in " << path << " line " << line_number
                                       << ": property without name");
      header.elements.back().properties.push_back(property);
    } else {
      THROW_ERROR("Bad PLY header in " << path << " line " << line_number
                                       << ": unknown keyword '" << keyword
                                       << "'");
    }
  }
  THROW_CHECK(has_end, "Bad PLY header in " << path << ": no end_header");
  THROW_CHECK(has_format, "Bad PLY header in " << path << ": no format line");
  header.body_offset = std::min(pos, content.size());
  return header;
}

}  // namespace ply_internal
}  // namespace colmap_lidar
