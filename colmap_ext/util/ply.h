// PLY reading and writing (ASCII and binary, either endianness on read).
// Reading accepts any element and property layout: the "vertex" element's
// scalar properties come back as named columns, the "face" element's index
// list as polygons; other elements are skipped. Writing produces the layouts
// COLMAP writes (fused.ply: float x y z nx ny nz, uchar red green blue) and
// whatever columns the caller adds.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {

enum class PlyScalarType {
  kInt8,
  kUInt8,
  kInt16,
  kUInt16,
  kInt32,
  kUInt32,
  kFloat32,
  kFloat64,
};

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };

// One scalar property of the vertex element, values converted to double.
struct PlyColumn {
  std::string name;
  PlyScalarType type = PlyScalarType::kFloat32;
  std::vector<double> values;
};

struct PlyData {
  // Vertex properties in file order; all columns have the same length.
  std::vector<PlyColumn> vertex_columns;
  // Polygons of the face element (vertex_indices or vertex_index), if any.
  std::vector<std::vector<uint32_t>> faces;

  size_t NumVertices() const;
  // nullptr when the column does not exist.
  const PlyColumn* FindColumn(const std::string& name) const;
  PlyColumn* FindColumn(const std::string& name);
  // Appends a column; throws if the length differs from existing columns.
  void AddColumn(const std::string& name, PlyScalarType type,
                 std::vector<double> values);
  // The x, y, z columns as points; throws naming `path_for_errors` if any is
  // missing.
  std::vector<Eigen::Vector3d> Positions(
      const std::string& path_for_errors = "") const;
};

// Throws colmap_lidar::Error naming the path on a missing file, a malformed
// header, a truncated body or an unsupported type.
PlyData ReadPly(const std::string& path);

// Writes atomically (temporary name, then rename). Faces are written as
// "property list uchar int vertex_indices".
void WritePly(const std::string& path, const PlyData& data,
              PlyFormat format = PlyFormat::kBinaryLittleEndian);

// A vertex property of a streamed PLY.
struct PlyProperty {
  std::string name;
  PlyScalarType type = PlyScalarType::kFloat32;
};

// Writes a binary little-endian PLY of `num_vertices` vertices (no faces)
// atomically, the bytes WritePly would write for the same columns, without
// holding the vertices: fill(i, values) sets vertex i's values, one per
// property in order. Throws naming the path and the property when a value
// does not fit its type; the file is then not written.
void WritePlyVertices(
    const std::string& path, const std::vector<PlyProperty>& properties,
    size_t num_vertices,
    const std::function<void(size_t vertex, double* values)>& fill);

// A point of COLMAP's fused.ply.
struct PlyPoint {
  Eigen::Vector3f xyz = Eigen::Vector3f::Zero();
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  std::array<uint8_t, 3> rgb = {0, 0, 0};
};

// Byte-identical to COLMAP's WriteBinaryPlyPoints (27-byte records).
void WriteColmapPlyPoints(const std::string& path,
                          const std::vector<PlyPoint>& points);
// Reads points with x y z and optional nx ny nz / red green blue.
std::vector<PlyPoint> ReadPlyPoints(const std::string& path);

}  // namespace colmap_lidar
