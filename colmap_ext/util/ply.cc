#include "colmap_ext/util/ply.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <limits>
#include <sstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {
namespace {

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

// The names COLMAP and most tools write.
const char* ScalarTypeName(PlyScalarType type) {
  switch (type) {
    case PlyScalarType::kInt8:
      return "char";
    case PlyScalarType::kUInt8:
      return "uchar";
    case PlyScalarType::kInt16:
      return "short";
    case PlyScalarType::kUInt16:
      return "ushort";
    case PlyScalarType::kInt32:
      return "int";
    case PlyScalarType::kUInt32:
      return "uint";
    case PlyScalarType::kFloat32:
      return "float";
    case PlyScalarType::kFloat64:
      return "double";
  }
  return "?";
}

size_t ScalarTypeSize(PlyScalarType type) {
  switch (type) {
    case PlyScalarType::kInt8:
    case PlyScalarType::kUInt8:
      return 1;
    case PlyScalarType::kInt16:
    case PlyScalarType::kUInt16:
      return 2;
    case PlyScalarType::kInt32:
    case PlyScalarType::kUInt32:
    case PlyScalarType::kFloat32:
      return 4;
    case PlyScalarType::kFloat64:
      return 8;
  }
  return 0;
}

bool IsIntegerType(PlyScalarType type) {
  return type != PlyScalarType::kFloat32 && type != PlyScalarType::kFloat64;
}

// Parses the header; the content must start with "ply".
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

// Reads scalar values from a binary body of either endianness.
class BinaryBodyReader {
 public:
  BinaryBodyReader(const std::string& content, size_t offset,
                   bool big_endian, const std::string& path)
      : data_(content.data()),
        size_(content.size()),
        pos_(offset),
        big_endian_(big_endian),
        path_(path) {}

  double Read(PlyScalarType type) {
    const size_t num_bytes = ScalarTypeSize(type);
    THROW_CHECK(size_ - pos_ >= num_bytes,
                "Truncated PLY body in " << path_ << " (binary data ends at byte "
                                         << size_ << ")");
    unsigned char bytes[8];
    std::memcpy(bytes, data_ + pos_, num_bytes);
    pos_ += num_bytes;
    if (big_endian_) {
      for (size_t i = 0; i < num_bytes / 2; ++i) {
        std::swap(bytes[i], bytes[num_bytes - 1 - i]);
      }
    }
    switch (type) {
      case PlyScalarType::kInt8:
        return Decode<int8_t>(bytes);
      case PlyScalarType::kUInt8:
        return Decode<uint8_t>(bytes);
      case PlyScalarType::kInt16:
        return Decode<int16_t>(bytes);
      case PlyScalarType::kUInt16:
        return Decode<uint16_t>(bytes);
      case PlyScalarType::kInt32:
        return Decode<int32_t>(bytes);
      case PlyScalarType::kUInt32:
        return Decode<uint32_t>(bytes);
      case PlyScalarType::kFloat32:
        return Decode<float>(bytes);
      case PlyScalarType::kFloat64:
        return Decode<double>(bytes);
    }
    return 0.0;
  }

  size_t Remaining() const { return size_ - pos_; }

 private:
  template <typename T>
  static double Decode(const unsigned char* bytes) {
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return static_cast<double>(value);
  }

  const char* data_;
  size_t size_;
  size_t pos_;
  bool big_endian_;
  const std::string& path_;
};

// Reads white-space separated numbers from an ASCII body.
class AsciiBodyReader {
 public:
  AsciiBodyReader(const std::string& content, size_t offset,
                  const std::string& path)
      : content_(content), pos_(offset), path_(path) {}

  double Read(PlyScalarType type) {
    const char* data = content_.c_str();
    while (pos_ < content_.size() && std::isspace(
                                         static_cast<unsigned char>(data[pos_]))) {
      ++pos_;
    }
    THROW_CHECK(pos_ < content_.size(),
                "Truncated PLY body in " << path_ << " (ASCII values end early)");
    char* end = nullptr;
    const double value = std::strtod(data + pos_, &end);
    const size_t new_pos = static_cast<size_t>(end - data);
    THROW_CHECK(new_pos > pos_ &&
                    (new_pos == content_.size() ||
                     std::isspace(static_cast<unsigned char>(data[new_pos]))),
                "Bad ASCII value '"
                    << content_.substr(pos_, std::min<size_t>(
                                                 20, content_.size() - pos_))
                    << "' in PLY body of " << path_);
    THROW_CHECK(!IsIntegerType(type) || value == std::floor(value),
                "Non-integer value for an integer property in PLY body of "
                    << path_);
    pos_ = new_pos;
    // A float property holds a float: round the decimal text to it so that
    // ASCII and binary files with the same content read the same.
    if (type == PlyScalarType::kFloat32) {
      return static_cast<double>(static_cast<float>(value));
    }
    return value;
  }

  size_t Remaining() const { return content_.size() - pos_; }

 private:
  const std::string& content_;
  size_t pos_;
  const std::string& path_;
};

// Reads a list count and checks it is a valid non-negative integer.
template <typename Reader>
uint64_t ReadListCount(Reader* reader, const PlyProperty& property,
                       const std::string& path) {
  const double count = reader->Read(property.count_type);
  // Every item takes at least one byte (binary) or character (ASCII): a
  // larger count is a corrupt file, and must not size an allocation.
  THROW_CHECK(count >= 0 && count <= static_cast<double>(reader->Remaining()),
              "Bad list count " << count << " for property '" << property.name
                                << "' in " << path << " ("
                                << reader->Remaining() << " bytes left)");
  return static_cast<uint64_t>(count);
}

template <typename Reader>
void ReadBody(const PlyHeader& header, Reader* reader, const std::string& path,
              PlyData* data) {
  for (const PlyElement& element : header.elements) {
    // Guard allocations against absurd counts in a corrupt header: every
    // element instance needs at least one byte of body (or one property).
    // An element without properties has no bytes to read, whatever its
    // count (looping over a count of 10^19 would hang).
    if (element.properties.empty()) {
      continue;
    }
    THROW_CHECK(element.count <= reader->Remaining(),
                "Truncated PLY body in " << path << ": element '"
                                         << element.name << "' declares "
                                         << element.count << " entries");
    const bool is_vertex = element.name == "vertex";
    const bool is_face = element.name == "face";
    // Column index for each property of the vertex element (-1: skipped).
    std::vector<int> column_of_property(element.properties.size(), -1);
    if (is_vertex) {
      THROW_CHECK(data->vertex_columns.empty(),
                  "Bad PLY header in " << path << ": two vertex elements");
      for (size_t i = 0; i < element.properties.size(); ++i) {
        const PlyProperty& property = element.properties[i];
        if (property.is_list) {
          continue;
        }
        column_of_property[i] = static_cast<int>(data->vertex_columns.size());
        PlyColumn column;
        column.name = property.name;
        column.type = property.type;
        column.values.reserve(element.count);
        data->vertex_columns.push_back(std::move(column));
      }
    }
    int face_property = -1;
    if (is_face) {
      for (size_t i = 0; i < element.properties.size(); ++i) {
        const PlyProperty& property = element.properties[i];
        if (property.is_list && (property.name == "vertex_indices" ||
                                 property.name == "vertex_index")) {
          face_property = static_cast<int>(i);
          break;
        }
      }
      if (face_property >= 0) {
        data->faces.reserve(data->faces.size() + element.count);
      }
    }

    for (uint64_t k = 0; k < element.count; ++k) {
      for (size_t i = 0; i < element.properties.size(); ++i) {
        const PlyProperty& property = element.properties[i];
        if (property.is_list) {
          const uint64_t count = ReadListCount(reader, property, path);
          if (static_cast<int>(i) == face_property) {
            std::vector<uint32_t> face(count);
            for (uint64_t j = 0; j < count; ++j) {
              const double index = reader->Read(property.type);
              THROW_CHECK(index >= 0 && index <= 4294967295.0,
                          "Bad face vertex index " << index << " in " << path);
              face[j] = static_cast<uint32_t>(index);
            }
            data->faces.push_back(std::move(face));
          } else {
            for (uint64_t j = 0; j < count; ++j) {
              reader->Read(property.type);
            }
          }
        } else {
          const double value = reader->Read(property.type);
          if (column_of_property[i] >= 0) {
            data->vertex_columns[column_of_property[i]].values.push_back(value);
          }
        }
      }
    }
  }
}

// Checks that `value` fits `type` when `type` is an integer type.
void CheckRepresentable(double value, PlyScalarType type,
                        const std::string& column, const std::string& path) {
  THROW_CHECK(std::isfinite(value) || !IsIntegerType(type),
              "Non-finite value in integer column '" << column
                                                     << "' writing " << path);
  double min_value = 0;
  double max_value = 0;
  switch (type) {
    case PlyScalarType::kInt8:
      min_value = -128;
      max_value = 127;
      break;
    case PlyScalarType::kUInt8:
      max_value = 255;
      break;
    case PlyScalarType::kInt16:
      min_value = -32768;
      max_value = 32767;
      break;
    case PlyScalarType::kUInt16:
      max_value = 65535;
      break;
    case PlyScalarType::kInt32:
      min_value = -2147483648.0;
      max_value = 2147483647.0;
      break;
    case PlyScalarType::kUInt32:
      max_value = 4294967295.0;
      break;
    case PlyScalarType::kFloat32:
    case PlyScalarType::kFloat64:
      return;
  }
  THROW_CHECK(value >= min_value && value <= max_value,
              "Value " << value << " does not fit the type "
                       << ScalarTypeName(type) << " of column '" << column
                       << "' writing " << path);
}

template <typename T>
void AppendLittleEndian(T value, std::string* buffer) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  buffer->append(bytes, sizeof(T));
}

void AppendBinary(double value, PlyScalarType type, std::string* buffer) {
  switch (type) {
    case PlyScalarType::kInt8:
      AppendLittleEndian(static_cast<int8_t>(std::lround(value)), buffer);
      break;
    case PlyScalarType::kUInt8:
      AppendLittleEndian(static_cast<uint8_t>(std::lround(value)), buffer);
      break;
    case PlyScalarType::kInt16:
      AppendLittleEndian(static_cast<int16_t>(std::lround(value)), buffer);
      break;
    case PlyScalarType::kUInt16:
      AppendLittleEndian(static_cast<uint16_t>(std::lround(value)), buffer);
      break;
    case PlyScalarType::kInt32:
      AppendLittleEndian(static_cast<int32_t>(std::llround(value)), buffer);
      break;
    case PlyScalarType::kUInt32:
      AppendLittleEndian(static_cast<uint32_t>(std::llround(value)), buffer);
      break;
    case PlyScalarType::kFloat32:
      AppendLittleEndian(static_cast<float>(value), buffer);
      break;
    case PlyScalarType::kFloat64:
      AppendLittleEndian(value, buffer);
      break;
  }
}

// Shortest text that reads back to the same value of `type`.
void AppendAscii(double value, PlyScalarType type, std::ostream* stream) {
  if (IsIntegerType(type)) {
    *stream << std::llround(value);
  } else if (type == PlyScalarType::kFloat32) {
    *stream << std::setprecision(std::numeric_limits<float>::max_digits10)
            << static_cast<float>(value);
  } else {
    *stream << std::setprecision(std::numeric_limits<double>::max_digits10)
            << value;
  }
}

}  // namespace

size_t PlyData::NumVertices() const {
  return vertex_columns.empty() ? 0 : vertex_columns.front().values.size();
}

const PlyColumn* PlyData::FindColumn(const std::string& name) const {
  for (const PlyColumn& column : vertex_columns) {
    if (column.name == name) {
      return &column;
    }
  }
  return nullptr;
}

PlyColumn* PlyData::FindColumn(const std::string& name) {
  for (PlyColumn& column : vertex_columns) {
    if (column.name == name) {
      return &column;
    }
  }
  return nullptr;
}

void PlyData::AddColumn(const std::string& name, PlyScalarType type,
                        std::vector<double> values) {
  THROW_CHECK(!name.empty() && name.find_first_of(" \t\r\n") ==
                                   std::string::npos,
              "Bad PLY column name '" << name << "'");
  THROW_CHECK(FindColumn(name) == nullptr,
              "PLY column '" << name << "' already exists");
  THROW_CHECK(vertex_columns.empty() || values.size() == NumVertices(),
              "PLY column '" << name << "' has " << values.size()
                             << " values, the others have "
                             << NumVertices());
  PlyColumn column;
  column.name = name;
  column.type = type;
  column.values = std::move(values);
  vertex_columns.push_back(std::move(column));
}

std::vector<Eigen::Vector3d> PlyData::Positions(
    const std::string& path_for_errors) const {
  const PlyColumn* x = FindColumn("x");
  const PlyColumn* y = FindColumn("y");
  const PlyColumn* z = FindColumn("z");
  THROW_CHECK(x != nullptr && y != nullptr && z != nullptr,
              "PLY vertices have no x, y, z properties: " << path_for_errors);
  std::vector<Eigen::Vector3d> positions(NumVertices());
  for (size_t i = 0; i < positions.size(); ++i) {
    positions[i] = Eigen::Vector3d(x->values[i], y->values[i], z->values[i]);
  }
  return positions;
}

PlyData ReadPly(const std::string& path) {
  THROW_CHECK(ExistsFile(path), "PLY file does not exist: " << path);
  const std::string content = ReadTextFile(path);
  const PlyHeader header = ParseHeader(content, path);
  PlyData data;
  if (header.format == PlyFormat::kAscii) {
    AsciiBodyReader reader(content, header.body_offset, path);
    ReadBody(header, &reader, path, &data);
  } else {
    BinaryBodyReader reader(content, header.body_offset,
                            header.format == PlyFormat::kBinaryBigEndian, path);
    ReadBody(header, &reader, path, &data);
  }
  const size_t num_vertices = data.NumVertices();
  for (const std::vector<uint32_t>& face : data.faces) {
    for (const uint32_t index : face) {
      THROW_CHECK(index < num_vertices, "Face vertex index "
                                            << index << " out of range ("
                                            << num_vertices
                                            << " vertices) in " << path);
    }
  }
  return data;
}

void WritePly(const std::string& path, const PlyData& data, PlyFormat format) {
  THROW_CHECK(format != PlyFormat::kBinaryBigEndian,
              "Writing big-endian PLY is not supported: " << path);
  const size_t num_vertices = data.NumVertices();
  for (const PlyColumn& column : data.vertex_columns) {
    THROW_CHECK(column.values.size() == num_vertices,
                "PLY column '" << column.name << "' has "
                               << column.values.size() << " values, expected "
                               << num_vertices << " writing " << path);
    for (const double value : column.values) {
      CheckRepresentable(value, column.type, column.name, path);
    }
  }
  for (const std::vector<uint32_t>& face : data.faces) {
    THROW_CHECK(face.size() <= 255, "Face with " << face.size()
                                                 << " vertices (max 255) writing "
                                                 << path);
    for (const uint32_t index : face) {
      THROW_CHECK(index < num_vertices &&
                      index <= static_cast<uint32_t>(
                                   std::numeric_limits<int32_t>::max()),
                  "Face vertex index " << index << " out of range ("
                                       << num_vertices << " vertices) writing "
                                       << path);
    }
  }

  std::ostringstream header;
  header << "ply\n";
  header << (format == PlyFormat::kAscii ? "format ascii 1.0\n"
                                         : "format binary_little_endian 1.0\n");
  header << "element vertex " << num_vertices << "\n";
  for (const PlyColumn& column : data.vertex_columns) {
    header << "property " << ScalarTypeName(column.type) << " " << column.name
           << "\n";
  }
  if (!data.faces.empty()) {
    header << "element face " << data.faces.size() << "\n";
    header << "property list uchar int vertex_indices\n";
  }
  header << "end_header\n";

  WriteFileAtomically(path, [&](std::ostream& stream) {
    stream << header.str();
    if (format == PlyFormat::kAscii) {
      for (size_t i = 0; i < num_vertices; ++i) {
        for (size_t c = 0; c < data.vertex_columns.size(); ++c) {
          if (c > 0) {
            stream << " ";
          }
          AppendAscii(data.vertex_columns[c].values[i],
                      data.vertex_columns[c].type, &stream);
        }
        stream << "\n";
      }
      for (const std::vector<uint32_t>& face : data.faces) {
        stream << face.size();
        for (const uint32_t index : face) {
          stream << " " << index;
        }
        stream << "\n";
      }
    } else {
      std::string buffer;
      for (size_t i = 0; i < num_vertices; ++i) {
        for (const PlyColumn& column : data.vertex_columns) {
          AppendBinary(column.values[i], column.type, &buffer);
        }
      }
      for (const std::vector<uint32_t>& face : data.faces) {
        AppendLittleEndian(static_cast<uint8_t>(face.size()), &buffer);
        for (const uint32_t index : face) {
          AppendLittleEndian(static_cast<int32_t>(index), &buffer);
        }
      }
      stream.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    }
  });
}

void WriteColmapPlyPoints(const std::string& path,
                          const std::vector<PlyPoint>& points) {
  // The header lines and the 27-byte record of COLMAP 3.8's
  // WriteBinaryPlyPoints with normals and colours (colmap-formats.md 4.7).
  std::string buffer;
  buffer += "ply\n";
  buffer += "format binary_little_endian 1.0\n";
  buffer += "element vertex " + std::to_string(points.size()) + "\n";
  buffer += "property float x\n";
  buffer += "property float y\n";
  buffer += "property float z\n";
  buffer += "property float nx\n";
  buffer += "property float ny\n";
  buffer += "property float nz\n";
  buffer += "property uchar red\n";
  buffer += "property uchar green\n";
  buffer += "property uchar blue\n";
  buffer += "end_header\n";
  buffer.reserve(buffer.size() + points.size() * 27);
  for (const PlyPoint& point : points) {
    for (int i = 0; i < 3; ++i) {
      AppendLittleEndian(point.xyz(i), &buffer);
    }
    for (int i = 0; i < 3; ++i) {
      AppendLittleEndian(point.normal(i), &buffer);
    }
    for (int i = 0; i < 3; ++i) {
      AppendLittleEndian(point.rgb[i], &buffer);
    }
  }
  WriteFileAtomically(path, [&](std::ostream& stream) {
    stream.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  });
}

std::vector<PlyPoint> ReadPlyPoints(const std::string& path) {
  const PlyData data = ReadPly(path);
  const std::vector<Eigen::Vector3d> positions = data.Positions(path);
  const PlyColumn* nx = data.FindColumn("nx");
  const PlyColumn* ny = data.FindColumn("ny");
  const PlyColumn* nz = data.FindColumn("nz");
  const bool has_normals = nx != nullptr && ny != nullptr && nz != nullptr;
  const PlyColumn* red = data.FindColumn("red");
  const PlyColumn* green = data.FindColumn("green");
  const PlyColumn* blue = data.FindColumn("blue");
  const bool has_colors = red != nullptr && green != nullptr && blue != nullptr;

  auto to_color = [](double value) {
    return static_cast<uint8_t>(
        std::lround(std::min(255.0, std::max(0.0, value))));
  };

  std::vector<PlyPoint> points(positions.size());
  for (size_t i = 0; i < points.size(); ++i) {
    points[i].xyz = positions[i].cast<float>();
    if (has_normals) {
      points[i].normal = Eigen::Vector3f(static_cast<float>(nx->values[i]),
                                         static_cast<float>(ny->values[i]),
                                         static_cast<float>(nz->values[i]));
    }
    if (has_colors) {
      points[i].rgb = {to_color(red->values[i]), to_color(green->values[i]),
                       to_color(blue->values[i])};
    }
  }
  return points;
}

}  // namespace colmap_lidar
