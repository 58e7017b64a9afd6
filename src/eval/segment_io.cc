#include "src/eval/segment_io.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <sstream>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {
namespace {

void CheckSegmentFinite(const Segment3D& segment, const std::string& path,
                        const std::string& where) {
  THROW_CHECK(segment.start.allFinite() && segment.end.allFinite(),
              "Non-finite segment coordinate in " << path << " " << where);
}

// --- Minimal PLY header/body walker, only to reach the "edge" element,
// which ReadPly skips. ---

struct PlyPropertyDesc {
  std::string name;
  bool is_list = false;
  int count_size = 0;  // Bytes of the list count (lists only).
  std::string count_type;
  std::string type;  // Scalar type or list item type.
};

struct PlyElementDesc {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyPropertyDesc> properties;
};

int PlyTypeSize(const std::string& type, const std::string& path) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") {
    return 1;
  }
  if (type == "short" || type == "ushort" || type == "int16" ||
      type == "uint16") {
    return 2;
  }
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" ||
      type == "float" || type == "float32") {
    return 4;
  }
  if (type == "double" || type == "float64") {
    return 8;
  }
  THROW_ERROR("Unsupported PLY property type '" << type << "' in " << path);
}

class PlyBodyReader {
 public:
  PlyBodyReader(const std::string& content, size_t offset, bool big_endian,
                const std::string& path)
      : content_(content), pos_(offset), big_endian_(big_endian), path_(path) {}

  double Read(const std::string& type) {
    const int size = PlyTypeSize(type, path_);
    THROW_CHECK(pos_ + size <= content_.size(),
                "Truncated PLY body in " << path_);
    unsigned char bytes[8];
    std::memcpy(bytes, content_.data() + pos_, size);
    pos_ += size;
    if (big_endian_) {
      std::reverse(bytes, bytes + size);
    }
    auto as = [&bytes](auto value) {
      std::memcpy(&value, bytes, sizeof(value));
      return static_cast<double>(value);
    };
    if (type == "char" || type == "int8") return as(int8_t());
    if (type == "uchar" || type == "uint8") return as(uint8_t());
    if (type == "short" || type == "int16") return as(int16_t());
    if (type == "ushort" || type == "uint16") return as(uint16_t());
    if (type == "int" || type == "int32") return as(int32_t());
    if (type == "uint" || type == "uint32") return as(uint32_t());
    if (type == "float" || type == "float32") return as(float());
    return as(double());
  }

 private:
  const std::string& content_;
  size_t pos_;
  bool big_endian_;
  std::string path_;
};

// Reads the (vertex1, vertex2) pairs of the "edge" element; returns false
// when the file has no edge element.
bool ReadPlyEdges(const std::string& path,
                  std::vector<std::pair<int64_t, int64_t>>* edges) {
  const std::string content = ReadTextFile(path);
  const size_t header_end = content.find("end_header");
  THROW_CHECK(StringStartsWith(content, "ply") &&
                  header_end != std::string::npos,
              "Not a PLY file (no 'ply' magic or no end_header): " << path);
  size_t body_offset = content.find('\n', header_end);
  THROW_CHECK(body_offset != std::string::npos,
              "Bad PLY header in " << path);
  ++body_offset;

  std::string format;
  std::vector<PlyElementDesc> elements;
  std::istringstream header(content.substr(0, header_end));
  std::string line;
  while (std::getline(header, line)) {
    std::istringstream tokens(StringTrim(line));
    std::string keyword;
    tokens >> keyword;
    if (keyword == "format") {
      tokens >> format;
    } else if (keyword == "element") {
      PlyElementDesc element;
      tokens >> element.name >> element.count;
      THROW_CHECK(!tokens.fail(), "Bad PLY element line in " << path << ": '"
                                                             << line << "'");
      elements.push_back(element);
    } else if (keyword == "property") {
      THROW_CHECK(!elements.empty(),
                  "Bad PLY header in " << path << ": property before element");
      PlyPropertyDesc property;
      std::string type;
      tokens >> type;
      if (type == "list") {
        property.is_list = true;
        tokens >> property.count_type >> property.type >> property.name;
        property.count_size = PlyTypeSize(property.count_type, path);
      } else {
        property.type = type;
        tokens >> property.name;
      }
      PlyTypeSize(property.type, path);
      THROW_CHECK(!tokens.fail(), "Bad PLY property line in " << path << ": '"
                                                              << line << "'");
      elements.back().properties.push_back(property);
    }
  }
  const auto edge_it =
      std::find_if(elements.begin(), elements.end(),
                   [](const PlyElementDesc& e) { return e.name == "edge"; });
  if (edge_it == elements.end()) {
    return false;
  }
  int vertex1_index = -1;
  int vertex2_index = -1;
  for (size_t i = 0; i < edge_it->properties.size(); ++i) {
    if (edge_it->properties[i].name == "vertex1") vertex1_index = i;
    if (edge_it->properties[i].name == "vertex2") vertex2_index = i;
  }
  THROW_CHECK(vertex1_index >= 0 && vertex2_index >= 0 &&
                  !edge_it->properties[vertex1_index].is_list &&
                  !edge_it->properties[vertex2_index].is_list,
              "The edge element of " << path
                                     << " needs scalar vertex1 and vertex2");

  edges->clear();
  edges->reserve(edge_it->count);
  if (format == "ascii") {
    // ASCII: whitespace-separated tokens; a list is its count then items.
    std::istringstream body(content.substr(body_offset));
    auto next = [&body, &path]() {
      double value;
      body >> value;
      THROW_CHECK(!body.fail(), "Truncated or malformed PLY body in " << path);
      return value;
    };
    for (const PlyElementDesc& element : elements) {
      const bool is_edge = &element == &*edge_it;
      for (uint64_t k = 0; k < element.count; ++k) {
        std::vector<double> values(element.properties.size(), 0.0);
        for (size_t i = 0; i < element.properties.size(); ++i) {
          values[i] = next();
          if (element.properties[i].is_list) {
            const int64_t count = static_cast<int64_t>(values[i]);
            for (int64_t j = 0; j < count; ++j) next();
          }
        }
        if (is_edge) {
          edges->emplace_back(static_cast<int64_t>(values[vertex1_index]),
                              static_cast<int64_t>(values[vertex2_index]));
        }
      }
      if (is_edge) break;
    }
    return true;
  }
  THROW_CHECK(format == "binary_little_endian" || format == "binary_big_endian",
              "Unknown PLY format '" << format << "' in " << path);
  PlyBodyReader reader(content, body_offset, format == "binary_big_endian",
                       path);
  for (const PlyElementDesc& element : elements) {
    const bool is_edge = &element == &*edge_it;
    for (uint64_t k = 0; k < element.count; ++k) {
      std::vector<double> values(element.properties.size(), 0.0);
      for (size_t i = 0; i < element.properties.size(); ++i) {
        const PlyPropertyDesc& property = element.properties[i];
        if (property.is_list) {
          const int64_t count =
              static_cast<int64_t>(reader.Read(property.count_type));
          for (int64_t j = 0; j < count; ++j) reader.Read(property.type);
        } else {
          values[i] = reader.Read(property.type);
        }
      }
      if (is_edge) {
        edges->emplace_back(static_cast<int64_t>(values[vertex1_index]),
                            static_cast<int64_t>(values[vertex2_index]));
      }
    }
    if (is_edge) break;
  }
  return true;
}

}  // namespace

std::vector<Segment3D> ReadSegmentsText(const std::string& path) {
  CheckFileExists(path, "Segment file");
  std::istringstream lines(ReadTextFile(path));
  std::vector<Segment3D> segments;
  std::string line;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    line = StringTrim(line);
    if (line.empty() || line[0] == '#') {
      continue;
    }
    std::istringstream fields(line);
    std::vector<double> values;
    std::string token;
    while (values.size() < 6 && fields >> token) {
      values.push_back(ParseDouble(
          token, path + " line " + std::to_string(line_number)));
    }
    THROW_CHECK(values.size() == 6,
                "Segment line " << line_number << " of " << path
                                << " has fewer than 6 numbers "
                                   "(x1 y1 z1 x2 y2 z2): '"
                                << line << "'");
    Segment3D segment;
    segment.start = Eigen::Vector3d(values[0], values[1], values[2]);
    segment.end = Eigen::Vector3d(values[3], values[4], values[5]);
    CheckSegmentFinite(segment, path, "line " + std::to_string(line_number));
    segments.push_back(segment);
  }
  return segments;
}

std::vector<Segment3D> ReadSegmentsPly(const std::string& path) {
  CheckFileExists(path, "Segment PLY");
  const PlyData data = ReadPly(path);
  const std::vector<Eigen::Vector3d> vertices =
      data.NumVertices() > 0 ? data.Positions(path)
                             : std::vector<Eigen::Vector3d>();
  std::vector<std::pair<int64_t, int64_t>> edges;
  if (!ReadPlyEdges(path, &edges)) {
    THROW_CHECK(vertices.size() % 2 == 0,
                "Segment PLY " << path << " has no edge element and an odd "
                               << "number of vertices (" << vertices.size()
                               << "); vertices 2i, 2i+1 form segment i");
    for (size_t i = 0; i + 1 < vertices.size(); i += 2) {
      edges.emplace_back(i, i + 1);
    }
  }
  std::vector<Segment3D> segments;
  segments.reserve(edges.size());
  for (size_t e = 0; e < edges.size(); ++e) {
    const auto [v1, v2] = edges[e];
    THROW_CHECK(v1 >= 0 && v2 >= 0 &&
                    static_cast<size_t>(v1) < vertices.size() &&
                    static_cast<size_t>(v2) < vertices.size(),
                "Edge " << e << " of " << path << " refers to vertex " << v1
                        << " or " << v2 << " but there are "
                        << vertices.size() << " vertices");
    Segment3D segment;
    segment.start = vertices[v1];
    segment.end = vertices[v2];
    CheckSegmentFinite(segment, path, "edge " + std::to_string(e));
    segments.push_back(segment);
  }
  return segments;
}

std::vector<Segment3D> ReadSegmentsObj(const std::string& path) {
  CheckFileExists(path, "Segment OBJ");
  std::istringstream lines(ReadTextFile(path));
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::vector<int64_t>> polylines;
  std::vector<int> polyline_lines;
  std::string line;
  int line_number = 0;
  while (std::getline(lines, line)) {
    ++line_number;
    std::istringstream fields(StringTrim(line));
    std::string keyword;
    fields >> keyword;
    const std::string where = path + " line " + std::to_string(line_number);
    if (keyword == "v") {
      std::string x, y, z;
      fields >> x >> y >> z;
      THROW_CHECK(!fields.fail(), "Malformed vertex in " << where);
      vertices.emplace_back(ParseDouble(x, where), ParseDouble(y, where),
                            ParseDouble(z, where));
    } else if (keyword == "l") {
      std::vector<int64_t> indices;
      std::string token;
      while (fields >> token) {
        // "i/vt" forms: only the vertex index matters.
        indices.push_back(ParseInt(token.substr(0, token.find('/')), where));
      }
      THROW_CHECK(indices.size() >= 2,
                  "Line element with fewer than 2 vertices in " << where);
      // Resolve relative (negative) indices against the vertices so far.
      for (int64_t& index : indices) {
        index = index < 0 ? static_cast<int64_t>(vertices.size()) + index
                          : index - 1;
      }
      polylines.push_back(indices);
      polyline_lines.push_back(line_number);
    }
  }
  std::vector<Segment3D> segments;
  for (size_t p = 0; p < polylines.size(); ++p) {
    for (const int64_t index : polylines[p]) {
      THROW_CHECK(index >= 0 && static_cast<size_t>(index) < vertices.size(),
                  "Vertex index out of range in " << path << " line "
                                                  << polyline_lines[p]);
    }
    for (size_t k = 1; k < polylines[p].size(); ++k) {
      Segment3D segment;
      segment.start = vertices[polylines[p][k - 1]];
      segment.end = vertices[polylines[p][k]];
      CheckSegmentFinite(segment, path,
                         "line " + std::to_string(polyline_lines[p]));
      segments.push_back(segment);
    }
  }
  return segments;
}

std::vector<Segment3D> ReadSegments(const std::string& path) {
  if (ExistsDir(path)) {
    const Reconstruction model = ReadReconstruction(path);
    std::vector<Segment3D> segments;
    segments.reserve(model.lines3D.size());
    for (const auto& [line3D_id, line3D] : model.lines3D) {
      Segment3D segment;
      segment.start = line3D.start_in_world;
      segment.end = line3D.end_in_world;
      CheckSegmentFinite(segment, path,
                         "lines3D id " + std::to_string(line3D_id));
      segments.push_back(segment);
    }
    if (segments.empty()) {
      LOG(WARNING) << "The model in " << path << " has no 3D lines";
    }
    return segments;
  }
  CheckFileExists(path, "Segment file");
  const std::string lower = StringToLower(path);
  if (StringEndsWith(lower, ".ply")) {
    return ReadSegmentsPly(path);
  }
  if (StringEndsWith(lower, ".obj")) {
    return ReadSegmentsObj(path);
  }
  return ReadSegmentsText(path);
}

void WriteSegmentsPly(const std::string& path,
                      const std::vector<Segment3D>& segments) {
  WriteFileAtomically(path, [&segments](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\n"
        << "comment colmap-lidar 3D segments: vertices 2i, 2i+1 form "
           "segment i\n"
        << "element vertex " << 2 * segments.size() << "\n"
        << "property double x\nproperty double y\nproperty double z\n"
        << "element edge " << segments.size() << "\n"
        << "property int vertex1\nproperty int vertex2\nend_header\n";
    for (const Segment3D& segment : segments) {
      WriteBinaryArray(out, segment.start.data(), 3);
      WriteBinaryArray(out, segment.end.data(), 3);
    }
    for (size_t i = 0; i < segments.size(); ++i) {
      WriteBinary<int32_t>(out, static_cast<int32_t>(2 * i));
      WriteBinary<int32_t>(out, static_cast<int32_t>(2 * i + 1));
    }
  });
}

void WriteSegmentsText(const std::string& path,
                       const std::vector<Segment3D>& segments) {
  WriteFileAtomically(
      path,
      [&segments](std::ostream& out) {
        out << "# 3D segments (world frame, metres): x1 y1 z1 x2 y2 z2\n";
        out << std::setprecision(17);
        for (const Segment3D& s : segments) {
          out << s.start.x() << " " << s.start.y() << " " << s.start.z() << " "
              << s.end.x() << " " << s.end.y() << " " << s.end.z() << "\n";
        }
      },
      /*binary=*/false);
}

}  // namespace colmap_lidar
