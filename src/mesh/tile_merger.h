// The union of meshing tiles (tiled_meshing.h, issue 19): what one tile
// gives, its transport between the ranks of an MPI job, and the merge.
//
// Tiles share the vertices of their seams (both sides triangulate the same
// points there), so the union merges vertices by their exact position. The
// result depends on the order the tiles are added in (a merged vertex keeps
// the index of its first tile): TiledDelaunayMeshing adds them in one order
// whatever the number of ranks, so that a job on N ranks writes the mesh of
// one process byte for byte.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "src/mesh/delaunay_mesher.h"
#include "src/mesh/triangle_mesh.h"

namespace colmap_lidar {

// What one tile gives the merge: the faces it keeps (no corner vertex,
// centroid in its core) with their own vertices, and its summary. Not
// meshed: a tile without points to mesh, which adds nothing.
struct MeshedTile {
  bool meshed = false;
  TriangleMesh kept;
  DelaunayMeshingSummary summary;
  // Points meshed (core, margin and the 8 corners) and faces before the
  // crop to the core: for the log, not transported.
  size_t num_points = 0;
  size_t num_faces = 0;
};

// A meshed tile's kept faces and the summary fields that the merge uses, as
// bytes for another rank of the same binary; empty for a tile that was not
// meshed.
std::string SerializeMeshedTile(const MeshedTile& tile);

// The inverse of SerializeMeshedTile for non-empty bytes. Throws
// colmap_lidar::Error on truncated or trailing bytes or a face that refers
// to a missing vertex.
MeshedTile DeserializeMeshedTile(const std::string& bytes);

// The union of the tiles' kept faces, their vertices merged by exact
// position (-0 = +0) in the order the tiles are added; and their summaries:
// counts, flow and times summed, the decimation voxel and free-space sigma
// the largest.
class TileMerger {
 public:
  void Add(MeshedTile tile);

  const DelaunayMeshingSummary& Summary() const { return summary_; }

  // The merged mesh, its faces in the canonical order
  // (SortFacesCanonically). The merger is empty afterwards.
  TriangleMesh Release();

 private:
  struct PositionKey {
    std::array<uint64_t, 3> bits;
    bool operator==(const PositionKey& other) const {
      return bits == other.bits;
    }
  };
  struct PositionKeyHash {
    size_t operator()(const PositionKey& key) const;
  };
  static PositionKey KeyOf(const Eigen::Vector3d& position);

  TriangleMesh mesh_;
  std::unordered_map<PositionKey, uint32_t, PositionKeyHash> vertex_index_;
  DelaunayMeshingSummary summary_;
};

}  // namespace colmap_lidar
