// The parts of ply.h: the header parser in ply_header.cc, reading in
// ply_reader.cc, writing in ply_writer.cc; here the PlyData container.
#include "colmap_ext/util/ply.h"

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

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

}  // namespace colmap_lidar
