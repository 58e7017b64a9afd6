#include "src/mesh/tile_merger.h"

#include <algorithm>
#include <cstring>
#include <utility>
#include <vector>

#include "colmap_ext/util/byte_stream.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// The summary fields that travel: the counts, then the reals below.
constexpr size_t kNumCounts = 7;
constexpr size_t kNumReals = 7;
constexpr size_t kVertexBytes = 3 * sizeof(double);
constexpr size_t kFaceBytes = 3 * sizeof(uint32_t);

}  // namespace

std::string SerializeMeshedTile(const MeshedTile& tile) {
  if (!tile.meshed) return std::string();
  const DelaunayMeshingSummary& summary = tile.summary;
  const std::array<uint64_t, kNumCounts> counts = {
      summary.num_vertices,      summary.num_cells,
      summary.num_rays,          summary.num_failed_walks,
      summary.num_surface_faces, tile.kept.vertices.size(),
      tile.kept.faces.size()};
  const std::array<double, kNumReals> reals = {
      summary.decimation_voxel_size_m, summary.distance_sigma_m,
      summary.max_flow,                summary.triangulation_seconds,
      summary.visibility_seconds,      summary.graph_cut_seconds,
      summary.total_seconds};
  std::string bytes;
  bytes.reserve(sizeof(counts) + sizeof(reals) +
                tile.kept.vertices.size() * kVertexBytes +
                tile.kept.faces.size() * kFaceBytes);
  ByteWriter writer(&bytes);
  writer.Values(counts.data(), counts.size());
  writer.Values(reals.data(), reals.size());
  for (const Eigen::Vector3d& vertex : tile.kept.vertices) {
    writer.Values(vertex.data(), 3);
  }
  for (const std::array<uint32_t, 3>& face : tile.kept.faces) {
    writer.Values(face.data(), 3);
  }
  return bytes;
}

MeshedTile DeserializeMeshedTile(const std::string& bytes) {
  std::array<uint64_t, kNumCounts> counts;
  std::array<double, kNumReals> reals;
  ByteReader reader(bytes);
  reader.Values(counts.data(), counts.size());
  reader.Values(reals.data(), reals.size());
  const uint64_t num_vertices = counts[5];
  const uint64_t num_faces = counts[6];
  // Checked before anything is allocated for them.
  const size_t remaining = reader.Remaining();
  THROW_CHECK(num_vertices <= remaining / kVertexBytes &&
                  num_faces <= remaining / kFaceBytes &&
                  num_vertices * kVertexBytes + num_faces * kFaceBytes ==
                      remaining,
              "A tile's mesh from another rank has "
                  << remaining << " bytes for " << num_vertices
                  << " vertices and " << num_faces << " faces");
  MeshedTile tile;
  tile.meshed = true;
  DelaunayMeshingSummary& summary = tile.summary;
  summary.num_vertices = counts[0];
  summary.num_cells = counts[1];
  summary.num_rays = counts[2];
  summary.num_failed_walks = counts[3];
  summary.num_surface_faces = counts[4];
  summary.decimation_voxel_size_m = reals[0];
  summary.distance_sigma_m = reals[1];
  summary.max_flow = reals[2];
  summary.triangulation_seconds = reals[3];
  summary.visibility_seconds = reals[4];
  summary.graph_cut_seconds = reals[5];
  summary.total_seconds = reals[6];
  tile.kept.vertices.resize(num_vertices);
  tile.kept.faces.resize(num_faces);
  for (Eigen::Vector3d& vertex : tile.kept.vertices) {
    reader.Values(vertex.data(), 3);
  }
  for (std::array<uint32_t, 3>& face : tile.kept.faces) {
    reader.Values(face.data(), 3);
  }
  tile.kept.CheckIndices();
  return tile;
}

size_t TileMerger::PositionKeyHash::operator()(const PositionKey& key) const {
  uint64_t hash = 1469598103934665603ull;  // FNV-1a.
  for (const uint64_t bits : key.bits) {
    hash = (hash ^ bits) * 1099511628211ull;
  }
  return static_cast<size_t>(hash);
}

TileMerger::PositionKey TileMerger::KeyOf(const Eigen::Vector3d& position) {
  PositionKey key;
  for (int k = 0; k < 3; ++k) {
    const double value = position[k] == 0.0 ? 0.0 : position[k];  // -0 = 0.
    std::memcpy(&key.bits[k], &value, sizeof(double));
  }
  return key;
}

void TileMerger::Add(MeshedTile tile) {
  if (!tile.meshed) return;
  std::vector<uint32_t> merged_index(tile.kept.vertices.size());
  for (size_t v = 0; v < tile.kept.vertices.size(); ++v) {
    const auto [it, inserted] = vertex_index_.emplace(
        KeyOf(tile.kept.vertices[v]),
        static_cast<uint32_t>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(tile.kept.vertices[v]);
    merged_index[v] = it->second;
  }
  for (const std::array<uint32_t, 3>& face : tile.kept.faces) {
    mesh_.faces.push_back({merged_index[face[0]], merged_index[face[1]],
                           merged_index[face[2]]});
  }
  const DelaunayMeshingSummary& other = tile.summary;
  summary_.num_vertices += other.num_vertices;
  summary_.num_cells += other.num_cells;
  summary_.num_rays += other.num_rays;
  summary_.num_failed_walks += other.num_failed_walks;
  summary_.num_surface_faces += other.num_surface_faces;
  summary_.decimation_voxel_size_m = std::max(
      summary_.decimation_voxel_size_m, other.decimation_voxel_size_m);
  summary_.distance_sigma_m =
      std::max(summary_.distance_sigma_m, other.distance_sigma_m);
  summary_.max_flow += other.max_flow;
  summary_.triangulation_seconds += other.triangulation_seconds;
  summary_.visibility_seconds += other.visibility_seconds;
  summary_.graph_cut_seconds += other.graph_cut_seconds;
  summary_.total_seconds += other.total_seconds;
}

TriangleMesh TileMerger::Release() {
  vertex_index_.clear();
  SortFacesCanonically(&mesh_);
  TriangleMesh mesh = std::move(mesh_);
  mesh_ = TriangleMesh();
  summary_ = DelaunayMeshingSummary();
  return mesh;
}

}  // namespace colmap_lidar
