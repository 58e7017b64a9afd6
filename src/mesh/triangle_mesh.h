// A triangle mesh as the Delaunay mesher outputs it, its clean-up (long
// edges, small connected components, unused vertices) and its PLY I/O.
// Faces are oriented counter-clockwise seen from outside, i.e. the normal
// (v1 - v0) x (v2 - v0) points into free space (towards the sensors).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<uint32_t, 3>> faces;

  // Unit normal of a face; zero for a degenerate face.
  Eigen::Vector3d FaceNormal(size_t face_idx) const;
  // Throws colmap_lidar::Error if a face refers to a missing vertex.
  void CheckIndices() const;
};

struct MeshCleanupOptions {
  // Faces whose longest edge exceeds this factor times the median edge length
  // of the mesh are removed; 0 disables the test.
  double max_edge_length_factor = 25.0;
  // The median edge length that factor applies to, metres; 0: the mesh's
  // own. The tiles of one scene share their first tile's
  // (tiled_meshing.h): a sparse tile's own median would keep the long faces
  // that the whole scene's removes.
  double median_edge_length_m = 0;
  // Connected components (through shared edges) with fewer faces are
  // removed; 0 keeps all.
  int min_component_faces = 50;

  bool Check() const;
};

struct MeshCleanupSummary {
  size_t num_long_edge_faces_removed = 0;
  // The median edge length the long-edge test used, metres (0: no test).
  double median_edge_length_m = 0;
  size_t num_small_component_faces_removed = 0;
  size_t num_components_removed = 0;
};

// Applies the tests above in that order and removes vertices no face uses
// (vertex order is otherwise kept).
MeshCleanupSummary CleanupMesh(const MeshCleanupOptions& options,
                               TriangleMesh* mesh);

// Puts the faces in a canonical order: each from its smallest vertex index
// (which keeps its orientation), then sorted, so that equal surfaces give
// equal files whatever order built them.
void SortFacesCanonically(TriangleMesh* mesh);

// Drops unused vertices and renumbers the faces.
void RemoveUnusedVertices(TriangleMesh* mesh);

// Drops the faces that use a vertex with a non-finite coordinate, then the
// unused vertices (stock poisson_mesher can emit NaN vertices). Returns the
// number of faces dropped.
size_t RemoveNonFiniteFaces(TriangleMesh* mesh);

// Edges (as sorted vertex pairs) used by exactly one face, and by more than
// two faces. A closed 2-manifold mesh has neither.
struct MeshEdgeStats {
  size_t num_edges = 0;
  std::vector<std::array<uint32_t, 2>> boundary_edges;
  std::vector<std::array<uint32_t, 2>> non_manifold_edges;
};
MeshEdgeStats ComputeMeshEdgeStats(const TriangleMesh& mesh);

// Binary little-endian PLY: float x y z per vertex and
// "property list uchar int vertex_indices" faces (the layout of colmap's
// poisson_mesher output, readable by MeshLab, Open3D and ReadPly). Atomic.
void WriteMeshPly(const std::string& path, const TriangleMesh& mesh);
// Reads vertices and triangular faces; throws naming the path when there is
// no x/y/z, a face is not a triangle or an index is out of range.
TriangleMesh ReadMeshPly(const std::string& path);

}  // namespace colmap_lidar
