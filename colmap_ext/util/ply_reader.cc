// Reading PLY files of ply.h: ASCII and binary bodies of either endianness.
#include "colmap_ext/util/ply.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply_internal.h"

namespace colmap_lidar {
namespace {

using ply_internal::IsIntegerType;
using ply_internal::ParseHeader;
using ply_internal::PlyElement;
using ply_internal::PlyHeader;
using ply_internal::PlyProperty;

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

}  // namespace

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
