#include "src/mesh/triangle_mesh.h"

#include <algorithm>
#include <numeric>
#include <unordered_map>

#include <Eigen/Geometry>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"

namespace colmap_lidar {
namespace {

uint64_t EdgeKey(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(a) << 32) | b;
}

// Union-find over face indices.
class DisjointSets {
 public:
  explicit DisjointSets(size_t size) : parent_(size) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  uint32_t Find(uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void Union(uint32_t a, uint32_t b) {
    a = Find(a);
    b = Find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<uint32_t> parent_;
};

}  // namespace

Eigen::Vector3d TriangleMesh::FaceNormal(size_t face_idx) const {
  const auto& face = faces.at(face_idx);
  const Eigen::Vector3d normal = (vertices[face[1]] - vertices[face[0]])
                                     .cross(vertices[face[2]] - vertices[face[0]]);
  const double norm = normal.norm();
  return norm > 0 ? Eigen::Vector3d(normal / norm) : Eigen::Vector3d::Zero();
}

void TriangleMesh::CheckIndices() const {
  for (size_t i = 0; i < faces.size(); ++i) {
    for (const uint32_t idx : faces[i]) {
      THROW_CHECK(idx < vertices.size(), "Face " << i << " refers to vertex "
                                                 << idx << " of "
                                                 << vertices.size());
    }
  }
}

bool MeshCleanupOptions::Check() const {
  if (!(median_edge_length_m >= 0) || !std::isfinite(median_edge_length_m)) {
    LOG(ERROR) << "MeshCleanup.median_edge_length_m must be finite and >= 0";
    return false;
  }
  if (max_edge_length_factor < 0) {
    LOG(ERROR) << "MeshCleanup.max_edge_length_factor must be >= 0";
    return false;
  }
  if (min_component_faces < 0) {
    LOG(ERROR) << "MeshCleanup.min_component_faces must be >= 0";
    return false;
  }
  return true;
}

MeshCleanupSummary CleanupMesh(const MeshCleanupOptions& options,
                               TriangleMesh* mesh) {
  THROW_CHECK(options.Check(), "Invalid mesh clean-up options");
  MeshCleanupSummary summary;
  auto& faces = mesh->faces;
  const auto& vertices = mesh->vertices;

  if (options.max_edge_length_factor > 0 && !faces.empty()) {
    std::vector<double> longest(faces.size());
    std::vector<double> lengths;
    lengths.reserve(3 * faces.size());
    for (size_t i = 0; i < faces.size(); ++i) {
      double max_length = 0;
      for (int k = 0; k < 3; ++k) {
        const double length =
            (vertices[faces[i][k]] - vertices[faces[i][(k + 1) % 3]]).norm();
        lengths.push_back(length);
        max_length = std::max(max_length, length);
      }
      longest[i] = max_length;
    }
    auto median = lengths.begin() + lengths.size() / 2;
    std::nth_element(lengths.begin(), median, lengths.end());
    summary.median_edge_length_m = options.median_edge_length_m > 0
                                       ? options.median_edge_length_m
                                       : *median;
    const double max_length =
        options.max_edge_length_factor * summary.median_edge_length_m;
    size_t num_kept = 0;
    for (size_t i = 0; i < faces.size(); ++i) {
      if (longest[i] <= max_length) faces[num_kept++] = faces[i];
    }
    summary.num_long_edge_faces_removed = faces.size() - num_kept;
    faces.resize(num_kept);
  }

  if (options.min_component_faces > 0 && !faces.empty()) {
    // Faces sharing an edge are in one component.
    DisjointSets sets(faces.size());
    std::unordered_map<uint64_t, uint32_t> edge_to_face;
    edge_to_face.reserve(3 * faces.size());
    for (uint32_t i = 0; i < faces.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const auto [it, inserted] = edge_to_face.emplace(
            EdgeKey(faces[i][k], faces[i][(k + 1) % 3]), i);
        if (!inserted) sets.Union(i, it->second);
      }
    }
    std::vector<uint32_t> component_size(faces.size(), 0);
    for (uint32_t i = 0; i < faces.size(); ++i) ++component_size[sets.Find(i)];
    size_t num_kept = 0;
    for (uint32_t i = 0; i < faces.size(); ++i) {
      const uint32_t root = sets.Find(i);
      if (component_size[root] >=
          static_cast<uint32_t>(options.min_component_faces)) {
        faces[num_kept++] = faces[i];
      } else if (root == i) {
        ++summary.num_components_removed;
      }
    }
    summary.num_small_component_faces_removed = faces.size() - num_kept;
    faces.resize(num_kept);
  }

  RemoveUnusedVertices(mesh);
  return summary;
}

void SortFacesCanonically(TriangleMesh* mesh) {
  for (std::array<uint32_t, 3>& face : mesh->faces) {
    std::rotate(face.begin(), std::min_element(face.begin(), face.end()),
                face.end());
  }
  std::sort(mesh->faces.begin(), mesh->faces.end());
}

void RemoveUnusedVertices(TriangleMesh* mesh) {
  constexpr uint32_t kUnused = 0xFFFFFFFFu;
  std::vector<uint32_t> new_index(mesh->vertices.size(), kUnused);
  for (const auto& face : mesh->faces) {
    for (const uint32_t idx : face) new_index[idx] = 0;
  }
  uint32_t num_used = 0;
  for (size_t i = 0; i < new_index.size(); ++i) {
    if (new_index[i] != kUnused) {
      new_index[i] = num_used;
      mesh->vertices[num_used++] = mesh->vertices[i];
    }
  }
  mesh->vertices.resize(num_used);
  for (auto& face : mesh->faces) {
    for (uint32_t& idx : face) idx = new_index[idx];
  }
}

size_t RemoveNonFiniteFaces(TriangleMesh* mesh) {
  const size_t num_faces = mesh->faces.size();
  mesh->faces.erase(
      std::remove_if(mesh->faces.begin(), mesh->faces.end(),
                     [mesh](const std::array<uint32_t, 3>& face) {
                       for (const uint32_t idx : face) {
                         if (!mesh->vertices[idx].allFinite()) return true;
                       }
                       return false;
                     }),
      mesh->faces.end());
  RemoveUnusedVertices(mesh);
  return num_faces - mesh->faces.size();
}

MeshEdgeStats ComputeMeshEdgeStats(const TriangleMesh& mesh) {
  std::unordered_map<uint64_t, uint32_t> edge_count;
  edge_count.reserve(3 * mesh.faces.size());
  for (const auto& face : mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      ++edge_count[EdgeKey(face[k], face[(k + 1) % 3])];
    }
  }
  MeshEdgeStats stats;
  stats.num_edges = edge_count.size();
  for (const auto& [key, count] : edge_count) {
    const std::array<uint32_t, 2> edge = {static_cast<uint32_t>(key >> 32),
                                          static_cast<uint32_t>(key)};
    if (count == 1) stats.boundary_edges.push_back(edge);
    if (count > 2) stats.non_manifold_edges.push_back(edge);
  }
  return stats;
}

void WriteMeshPly(const std::string& path, const TriangleMesh& mesh) {
  mesh.CheckIndices();
  PlyData data;
  std::vector<double> x, y, z;
  x.reserve(mesh.vertices.size());
  y.reserve(mesh.vertices.size());
  z.reserve(mesh.vertices.size());
  for (const Eigen::Vector3d& vertex : mesh.vertices) {
    x.push_back(vertex.x());
    y.push_back(vertex.y());
    z.push_back(vertex.z());
  }
  data.AddColumn("x", PlyScalarType::kFloat32, std::move(x));
  data.AddColumn("y", PlyScalarType::kFloat32, std::move(y));
  data.AddColumn("z", PlyScalarType::kFloat32, std::move(z));
  data.faces.reserve(mesh.faces.size());
  for (const auto& face : mesh.faces) {
    data.faces.push_back({face[0], face[1], face[2]});
  }
  WritePly(path, data);
}

TriangleMesh ReadMeshPly(const std::string& path) {
  const PlyData data = ReadPly(path);
  TriangleMesh mesh;
  mesh.vertices = data.Positions(path);
  mesh.faces.reserve(data.faces.size());
  for (size_t i = 0; i < data.faces.size(); ++i) {
    const auto& face = data.faces[i];
    THROW_CHECK(face.size() == 3, "Face " << i << " of " << path << " has "
                                          << face.size() << " vertices");
    mesh.faces.push_back({face[0], face[1], face[2]});
  }
  try {
    mesh.CheckIndices();
  } catch (const Error& error) {
    THROW_ERROR(path << ": " << error.what());
  }
  return mesh;
}

}  // namespace colmap_lidar
