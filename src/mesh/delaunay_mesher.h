// Delaunay meshing of visual points, LIDAR voxels and 3D line samples
// (Amblard et al., Sec. III-E, last paragraph; the method of Labatut, Pons
// and Keriven 2009 as in COLMAP's delaunay_mesher, which Debian's COLMAP
// lacks):
// 1. a 3D Delaunay triangulation of all points (delaunay_triangulation.h);
// 2. every sensor-to-point ray carves free space (visibility_integration.h);
// 3. a minimum s-t cut labels the cells outside (source) or inside (sink),
//    with a surface-quality term on each facet (Labatut Fig. 9: 1 - the
//    smaller cosine of the angles between the facet and the circumspheres
//    of its two cells, times quality_regularization);
// 4. the facets between outside and inside cells are the mesh, oriented
//    towards the outside; then clean-up (triangle_mesh.h);
// 5. the vertices near the creases that the validated 3D line segments found
//    move onto the creases' two faces (crease_snapping.h).
//
// Memory (benchmarks/bench_meshing, synthetic box scene, 12 cameras, ~7
// observations per point): without vertex merging, 292k points -> 292k
// vertices, 1.77M cells, 2.0M rays peaked at 558 MiB, i.e. ~2.0 kB per
// inserted point; with the default 2 px merging 972k points -> 197k vertices
// peaked at 548 MiB. kEstimatedBytesPerPoint (2.5 kB, no merging assumed) is
// the budget's unit: max_memory_gb = 8 admits ~3.4M points in one piece;
// MeshDenseWorkspace meshes larger inputs by tiles (tiled_meshing.h), and
// DelaunayMeshing decimates them on a voxel grid first.
#pragma once

#include <string>

#include "src/mesh/crease_snapping.h"
#include "src/mesh/delaunay_triangulation.h"
#include "src/mesh/meshing_input.h"
#include "src/mesh/triangle_mesh.h"
#include "src/mesh/view_region.h"
#include "src/mesh/visibility_integration.h"

namespace colmap_lidar {

// Budgeted peak resident memory per input point of a full meshing run
// (measured ~2.0 kB without merging, plus margin); used by the memory guard.
constexpr double kEstimatedBytesPerPoint = 2500.0;

struct DelaunayMeshingOptions {
  // With view_depth_factor > 0 the input is cropped to the region the
  // images see (view_region.h): inside a camera's image, at most
  // view_depth_factor times the view_depth_quantile of the visual points'
  // depths in front of it. 0 (default) meshes everything. It was made for
  // KITTI's time (> 34 min then; 74 s now without it, thanks to
  // max_free_space_length_factor), and on the quad it drops the surfaces
  // only the LIDAR sees (recall at 0.1 m 0.83 -> 0.60), hence off.
  double view_depth_quantile = 0.95;
  double view_depth_factor = 0.0;
  // Vertex merging (see delaunay_triangulation.h): pixels, relative depth,
  // metres. max_proj_dist_px = 0 inserts every visual point.
  double max_proj_dist_px = 2.0;
  double max_depth_dist = 0.05;
  double min_lidar_vertex_distance_m = 0.05;
  // Free-space weight falloff sigma relative to the lower-quartile edge
  // length, and where the inside weight goes behind a point (units of sigma).
  double distance_sigma_factor = 1.0;
  double behind_distance_factor = 0.25;
  // Free space carved at most this many sigma in front of a point
  // (visibility_integration.h); 0 carves whole rays.
  double max_free_space_length_factor = 100.0;
  // Weight of the surface-quality term per facet, >= 0.
  double quality_regularization = 1.0;
  // Clean-up of the extracted surface.
  double max_edge_length_factor = 25.0;
  int min_component_faces = 50;
  // Snap the mesh's vertices near the creases of the validated line
  // segments onto the creases' faces (crease_snapping.h); the input's
  // creases come with its line samples.
  bool snap_to_creases = true;
  CreaseSnappingOptions crease_snapping;
  // Memory budget, GiB (> 0): MeshDenseWorkspace meshes inputs whose
  // estimated peak exceeds it by tiles that fit it (tiled_meshing.h);
  // DelaunayMeshing decimates such an input (or a tile that still exceeds
  // it) on a voxel grid. 8 GiB: a laptop's memory; the benchmark matrix's
  // cells (at most 1.4M points) fit it whole.
  double max_memory_gb = 8.0;
  // Tiles: the margin around each tile's core whose points join its
  // meshing, metres (>= 0; tiled_meshing.h): about twice the free-space
  // carving's reach (max_free_space_length_factor sigma, 4-7 m on the
  // benchmark scenes).
  double tile_margin_m = 10.0;
  // Set by TiledDelaunayMeshing for its tiles, not options of the command:
  // insertion in a world grid's order (DelaunayTriangulationOptions), a
  // fixed free-space sigma (VisibilityIntegrationOptions) and a fixed
  // median edge length of the clean-up (MeshCleanupOptions), metres (0:
  // from the tile).
  bool world_grid_order = false;
  double distance_sigma_m = 0;
  double cleanup_median_edge_length_m = 0;
  // Worker threads for the ray casting; <= 0 uses all cores.
  int num_threads = -1;

  bool Check() const;
  // The input points that max_memory_gb admits in one piece.
  size_t MaxNumPoints() const;
  ViewRegionOptions ViewOptions() const;
  DelaunayTriangulationOptions TriangulationOptions() const;
  VisibilityIntegrationOptions VisibilityOptions() const;
  MeshCleanupOptions CleanupOptions() const;
};

struct DelaunayMeshingSummary {
  size_t num_input_points = 0;
  // Maximum depth of the view region (0: no cropping) and the points
  // outside it, removed.
  double view_max_depth_m = 0;
  size_t num_points_outside_view = 0;
  // Voxel size of the memory guard's decimation; 0 if none.
  double decimation_voxel_size_m = 0;
  // Tiles meshed (1: in one piece) and their edge, metres (0: one piece).
  int num_tiles = 1;
  double tile_size_m = 0;
  size_t num_vertices = 0;
  size_t num_cells = 0;
  size_t num_rays = 0;
  size_t num_failed_walks = 0;
  double distance_sigma_m = 0;
  double max_flow = 0;
  size_t num_surface_faces = 0;
  MeshCleanupSummary cleanup;
  CreaseSnappingSummary crease_snapping;
  size_t num_faces = 0;
  size_t num_mesh_vertices = 0;
  double triangulation_seconds = 0;
  double visibility_seconds = 0;
  double graph_cut_seconds = 0;
  double total_seconds = 0;
  // Peak resident set size of the process so far (VmHWM), bytes.
  size_t peak_memory_bytes = 0;
};

// Meshes `input`. Throws colmap_lidar::Error on invalid options or input.
TriangleMesh DelaunayMeshing(const DelaunayMeshingOptions& options,
                             const MeshingInput& input,
                             DelaunayMeshingSummary* summary = nullptr);

// The lidar_delaunay_mesher command: reads the workspace (and lines, with
// the database of their 2D segments; see ReadMeshingInput), meshes, writes
// `output_path` (WriteMeshPly).
DelaunayMeshingSummary MeshDenseWorkspace(
    const DelaunayMeshingOptions& options,
    const MeshingInputOptions& input_options,
    const std::string& workspace_path, const std::string& lines_model_path,
    const std::string& output_path, const std::string& database_path = "");

// VmHWM of /proc/self/status in bytes; 0 when unavailable.
size_t PeakResidentMemoryBytes();

}  // namespace colmap_lidar
