// Delaunay meshing by spatial tiles (not in the paper): bounded memory for
// recordings whose points do not fit one triangulation (issue 19).
//
// The mesher costs about kEstimatedBytesPerPoint (2.5 kB) per input point at
// its peak, so the points that fit DelaunayMeshingOptions::max_memory_gb
// are bounded (3.4 M at 8 GiB); a 600-frame street has 17.6 M. Beyond the budget
// the input is cut into square tiles in the plane of its two main axes (the
// principal axes of the points: along and across a street, or across a
// square), each tile meshed on its own (DelaunayMeshing: triangulation,
// visibility, graph cut, clean-up, crease snapping) with the points of its
// core and of a margin of tile_margin_m around it, and only the faces whose
// centroid lies in the core are kept. The margin gives the surface near a
// core's edge the same neighbours and the same free-space rays as in one
// piece (rays are carved at most max_free_space_length_factor sigma, 4-7 m
// on the benchmark scenes, in front of their point), so both tiles at a
// seam build the same faces there from the same points: the union shares
// the seam's vertices (merged by position) and is closed where the scene
// is. That needs the tiles to decide alike: they merge visual points by the
// world grid rule (DelaunayTriangulationOptions::world_grid_order) and share
// the fullest tile's free-space sigma and clean-up median edge length; and
// each gets 8 corner points without rays around its points and sensors,
// whose faces are dropped (a tile whose hull is a flat sheet of ground has
// no finite cell above it to carve). The tile edge is the largest (from half the extent down by 20 %
// steps, not below two margins) whose core and margin hold at most the
// budget's points; a tile that still exceeds it (a margin as dense as the
// budget) is decimated by the mesher's own guard.
//
// Inputs within the budget are meshed in one piece, exactly as
// DelaunayMeshing does.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "src/mesh/delaunay_mesher.h"
#include "src/mesh/meshing_input.h"
#include "src/mesh/triangle_mesh.h"

namespace colmap_lidar {

// The tiles of an input: tile (i, j) has the core
// u in [u_min + i * size, u_min + (i + 1) * size) and likewise for v, with
// u = axis_u . (x - origin), v = axis_v . (x - origin); the first and last
// tiles of a row or column extend to infinity.
struct MeshingTiles {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX();
  Eigen::Vector3d axis_v = Eigen::Vector3d::UnitY();
  double u_min = 0;
  double v_min = 0;
  // Infinite for a single tile (the whole input).
  double size_m = std::numeric_limits<double>::infinity();
  double margin_m = 0;
  int num_u = 1;
  int num_v = 1;
  // Points in the fullest tile's core and margin.
  size_t max_tile_points = 0;

  int NumTiles() const { return num_u * num_v; }
  // Tile index of a position's core.
  int TileOf(const Eigen::Vector3d& position) const;
  // Whether a position lies in tile `tile`'s core widened by `margin`.
  bool Contains(int tile, const Eigen::Vector3d& position,
                double margin) const;
  // The positions in each tile's core and margin: their number, and their
  // indices (ascending), by tile.
  std::vector<size_t> CountPoints(
      const std::vector<Eigen::Vector3d>& positions) const;
  std::vector<std::vector<uint32_t>> PointsPerTile(
      const std::vector<Eigen::Vector3d>& positions) const;

 private:
  // Calls visit(tile) for each tile whose core and margin hold `position`.
  template <typename Visit>
  void ForEachTileOf(const Eigen::Vector3d& position, Visit&& visit) const;
};

// The tiles for `input` whose core and margin hold at most
// `max_tile_points` points each (see the file comment); one tile when the
// whole input does.
MeshingTiles ChooseMeshingTiles(const MeshingInput& input,
                                size_t max_tile_points, double margin_m);

// The tile budget of TiledDelaunayMeshing for `num_points` input points
// (all of them held in memory): the points of options.max_memory_gb minus
// the held input's share, at least a tenth of them.
size_t MaxTilePointsForBudget(const DelaunayMeshingOptions& options,
                              size_t num_points);

// The input points `points` (tile `tile`'s, PointsPerTile), every sensor
// (indices unchanged) and the creases with an end point in the tile's core
// and margin.
MeshingInput TileMeshingInput(const MeshingInput& input,
                              const std::vector<uint32_t>& points,
                              const MeshingTiles& tiles, int tile);

// Meshes `input` in one piece when it fits options.max_memory_gb, else by
// tiles (file comment). The summary's counts and times are summed over the
// tiles; its peak memory is the process's. Throws colmap_lidar::Error on
// invalid options or input.
//
// Under mpirun / srun (ProcessGroup::World(), every rank with the same
// input) the tiles are split over the ranks: rank 0 meshes the reference
// tile and sends its sigma and edge length to all; each other tile goes to
// one rank (fullest first, to the rank with the fewest points so far); rank
// 0 gathers the kept faces (tile_merger.h) and merges them in the order of
// one process, so it returns the same mesh byte for byte; the other ranks
// return an empty mesh. In one piece, rank 0 alone meshes.
TriangleMesh TiledDelaunayMeshing(const DelaunayMeshingOptions& options,
                                  const MeshingInput& input,
                                  DelaunayMeshingSummary* summary = nullptr);

}  // namespace colmap_lidar
