// Writing PLY files of ply.h: ASCII or binary little-endian, and COLMAP's
// fused.ply layout.
#include "colmap_ext/util/ply.h"

#include <cmath>
#include <cstring>
#include <iomanip>
#include <limits>
#include <sstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply_internal.h"

namespace colmap_lidar {
namespace {

using ply_internal::IsIntegerType;

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

// Bodies are written through a buffer of about this size, so that writing
// a file never holds a second copy of it (a 600-frame recording's fused
// LIDAR cloud is 1 GB of records).
constexpr size_t kFlushBytes = size_t{1} << 20;

void FlushIfFull(std::string* buffer, std::ostream* stream, bool force) {
  if (force || buffer->size() >= kFlushBytes) {
    stream->write(buffer->data(), static_cast<std::streamsize>(buffer->size()));
    buffer->clear();
  }
}

std::string PlyHeaderText(PlyFormat format, size_t num_vertices,
                          const std::vector<PlyProperty>& properties,
                          size_t num_faces) {
  std::ostringstream header;
  header << "ply\n";
  header << (format == PlyFormat::kAscii ? "format ascii 1.0\n"
                                         : "format binary_little_endian 1.0\n");
  header << "element vertex " << num_vertices << "\n";
  for (const PlyProperty& property : properties) {
    header << "property " << ScalarTypeName(property.type) << " "
           << property.name << "\n";
  }
  if (num_faces > 0) {
    header << "element face " << num_faces << "\n";
    header << "property list uchar int vertex_indices\n";
  }
  header << "end_header\n";
  return header.str();
}

}  // namespace

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

  std::vector<PlyProperty> properties;
  for (const PlyColumn& column : data.vertex_columns) {
    properties.push_back({column.name, column.type});
  }
  const std::string header =
      PlyHeaderText(format, num_vertices, properties, data.faces.size());

  WriteFileAtomically(path, [&](std::ostream& stream) {
    stream << header;
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
        FlushIfFull(&buffer, &stream, /*force=*/false);
      }
      for (const std::vector<uint32_t>& face : data.faces) {
        AppendLittleEndian(static_cast<uint8_t>(face.size()), &buffer);
        for (const uint32_t index : face) {
          AppendLittleEndian(static_cast<int32_t>(index), &buffer);
        }
        FlushIfFull(&buffer, &stream, /*force=*/false);
      }
      FlushIfFull(&buffer, &stream, /*force=*/true);
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
  WriteFileAtomically(path, [&](std::ostream& stream) {
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
      FlushIfFull(&buffer, &stream, /*force=*/false);
    }
    FlushIfFull(&buffer, &stream, /*force=*/true);
  });
}

void WritePlyVertices(
    const std::string& path, const std::vector<PlyProperty>& properties,
    size_t num_vertices,
    const std::function<void(size_t vertex, double* values)>& fill) {
  THROW_CHECK(!properties.empty(), "No vertex property writing " << path);
  const std::string header = PlyHeaderText(PlyFormat::kBinaryLittleEndian,
                                           num_vertices, properties, 0);
  WriteFileAtomically(path, [&](std::ostream& stream) {
    stream << header;
    std::vector<double> values(properties.size());
    std::string buffer;
    for (size_t i = 0; i < num_vertices; ++i) {
      fill(i, values.data());
      for (size_t c = 0; c < properties.size(); ++c) {
        CheckRepresentable(values[c], properties[c].type, properties[c].name,
                           path);
        AppendBinary(values[c], properties[c].type, &buffer);
      }
      FlushIfFull(&buffer, &stream, /*force=*/false);
    }
    FlushIfFull(&buffer, &stream, /*force=*/true);
  });
}

}  // namespace colmap_lidar
