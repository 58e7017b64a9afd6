#include "src/mesh/delaunay_mesher.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>

#include <Eigen/Geometry>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/parallel.h"
#include "colmap_ext/util/process_group.h"
#include "src/mesh/graph_cut.h"
#include "src/mesh/point_decimation.h"
#include "src/mesh/progress_watchdog.h"
#include "src/mesh/tiled_meshing.h"

namespace colmap_lidar {
namespace {

class StageTimer {
 public:
  StageTimer() : start_(std::chrono::steady_clock::now()) {}
  double Seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start_)
        .count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

// Cosine of the angle between facet k of `cell` and the cell's circumsphere
// (Labatut et al. 2009, Fig. 9): the signed distance of the circumcentre
// from the facet plane, towards the cell, over the circumradius. 1 for an
// infinite cell, so that hull facets are never penalised from outside.
double CosFacetCircumsphere(const MeshDelaunay& delaunay,
                            const MeshCellHandle& cell, int k) {
  if (delaunay.is_infinite(cell)) return 1.0;
  Eigen::Vector3d p[4];
  for (int i = 0; i < 4; ++i) p[i] = ToEigen(cell->vertex(i)->point());
  const Eigen::Vector3d& a = p[(k + 1) % 4];
  const Eigen::Vector3d& b = p[(k + 2) % 4];
  const Eigen::Vector3d& c = p[(k + 3) % 4];
  Eigen::Vector3d normal = (b - a).cross(c - a);
  const double normal_norm = normal.norm();
  if (normal_norm == 0) return 0.0;
  normal /= normal_norm;
  if (normal.dot(p[k] - a) < 0) normal = -normal;
  const Eigen::Vector3d center = ToEigen(CGAL::circumcenter(
      cell->vertex(0)->point(), cell->vertex(1)->point(),
      cell->vertex(2)->point(), cell->vertex(3)->point()));
  const double radius = (center - a).norm();
  if (!std::isfinite(radius) || radius == 0) return 0.0;
  return std::clamp(normal.dot(center - a) / radius, -1.0, 1.0);
}

// The facets between differently labelled cells, oriented so that the
// normal points into the outside (source) cell.
TriangleMesh ExtractSurface(const MeshingTriangulation& triangulation,
                            const std::vector<bool>& is_outside) {
  const MeshDelaunay& delaunay = triangulation.delaunay;
  TriangleMesh mesh;
  mesh.vertices.reserve(triangulation.NumVertices());
  for (const MeshVertexHandle& vertex : triangulation.vertices) {
    mesh.vertices.push_back(ToEigen(vertex->point()));
  }
  for (const MeshCellHandle& cell : triangulation.cells) {
    for (int k = 0; k < 4; ++k) {
      const MeshCellHandle neighbor = cell->neighbor(k);
      if (cell->info() > neighbor->info()) continue;  // Each facet once.
      if (is_outside[cell->info()] == is_outside[neighbor->info()]) continue;
      if (delaunay.is_infinite(cell, k)) continue;  // Facet at infinity.
      std::array<MeshVertexHandle, 3> v;
      for (int i = 0, j = 0; i < 4; ++i) {
        if (i != k) v[j++] = cell->vertex(i);
      }
      // A finite reference point on a known side of the facet.
      const bool cell_is_finite = !delaunay.is_infinite(cell);
      const MeshPoint& reference =
          cell_is_finite ? cell->vertex(k)->point()
                         : neighbor->vertex(neighbor->index(cell))->point();
      const bool reference_is_outside =
          cell_is_finite ? is_outside[cell->info()]
                         : is_outside[neighbor->info()];
      const CGAL::Orientation side = CGAL::orientation(
          v[0]->point(), v[1]->point(), v[2]->point(), reference);
      // The normal (v1 - v0) x (v2 - v0) points to the POSITIVE side.
      const bool normal_towards_reference = side == CGAL::POSITIVE;
      if (normal_towards_reference != reference_is_outside) {
        std::swap(v[1], v[2]);
      }
      mesh.faces.push_back({v[0]->info(), v[1]->info(), v[2]->info()});
    }
  }
  // Not in the cells' order: equal surfaces give equal files.
  SortFacesCanonically(&mesh);
  return mesh;
}

}  // namespace

bool DelaunayMeshingOptions::Check() const {
  if (!ViewOptions().Check()) return false;
  if (!TriangulationOptions().Check()) return false;
  if (!VisibilityOptions().Check()) return false;
  if (!CleanupOptions().Check()) return false;
  if (snap_to_creases && !crease_snapping.Check()) return false;
  if (!(quality_regularization >= 0)) {
    LOG(ERROR) << "DelaunayMeshing.quality_regularization must be >= 0";
    return false;
  }
  if (!(max_memory_gb > 0) || !std::isfinite(max_memory_gb)) {
    LOG(ERROR) << "DelaunayMeshing.max_memory_gb must be finite and > 0";
    return false;
  }
  if (!(tile_margin_m >= 0) || !std::isfinite(tile_margin_m)) {
    LOG(ERROR) << "DelaunayMeshing.tile_margin_m must be >= 0";
    return false;
  }
  return true;
}

size_t DelaunayMeshingOptions::MaxNumPoints() const {
  return static_cast<size_t>(max_memory_gb * (1ull << 30) /
                             kEstimatedBytesPerPoint);
}

ViewRegionOptions DelaunayMeshingOptions::ViewOptions() const {
  ViewRegionOptions options;
  options.depth_quantile = view_depth_quantile;
  options.depth_factor = view_depth_factor;
  return options;
}

DelaunayTriangulationOptions DelaunayMeshingOptions::TriangulationOptions()
    const {
  DelaunayTriangulationOptions options;
  options.max_proj_dist_px = max_proj_dist_px;
  options.max_depth_dist = max_depth_dist;
  options.min_lidar_vertex_distance_m = min_lidar_vertex_distance_m;
  options.world_grid_order = world_grid_order;
  return options;
}

VisibilityIntegrationOptions DelaunayMeshingOptions::VisibilityOptions()
    const {
  VisibilityIntegrationOptions options;
  options.distance_sigma_factor = distance_sigma_factor;
  options.behind_distance_factor = behind_distance_factor;
  options.max_free_space_length_factor = max_free_space_length_factor;
  options.distance_sigma_m = distance_sigma_m;
  options.num_threads = num_threads;
  return options;
}

MeshCleanupOptions DelaunayMeshingOptions::CleanupOptions() const {
  MeshCleanupOptions options;
  options.max_edge_length_factor = max_edge_length_factor;
  options.min_component_faces = min_component_faces;
  options.median_edge_length_m = cleanup_median_edge_length_m;
  return options;
}

size_t PeakResidentMemoryBytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) {
      return static_cast<size_t>(std::stoull(line.substr(6))) * 1024;
    }
  }
  return 0;
}

TriangleMesh DelaunayMeshing(const DelaunayMeshingOptions& options,
                             const MeshingInput& input_in,
                             DelaunayMeshingSummary* summary_out) {
  THROW_CHECK(options.Check(), "Invalid Delaunay meshing options");
  input_in.Check();
  THROW_CHECK(input_in.NumPoints() >= 4,
              "Delaunay meshing needs at least 4 points, got "
                  << input_in.NumPoints());
  const StageTimer total_timer;
  DelaunayMeshingSummary summary;
  summary.num_input_points = input_in.NumPoints();

  // With view_depth_factor > 0 only the region the images see is meshed
  // (view_region.h); a copy is made only when points fall outside it.
  MeshingInput reduced;
  const MeshingInput* input = &input_in;
  summary.view_max_depth_m = ViewRegionMaxDepth(options.ViewOptions(),
                                                input_in);
  if (summary.view_max_depth_m > 0) {
    size_t num_outside = 0;
    for (const Eigen::Vector3d& position : input_in.positions) {
      num_outside +=
          !IsInViewRegion(input_in, summary.view_max_depth_m, position);
    }
    if (num_outside > 0) {
      reduced = input_in;
      summary.num_points_outside_view =
          CropToViewRegion(summary.view_max_depth_m, &reduced);
      input = &reduced;
    }
    LOG(INFO) << "View region: depth <= " << summary.view_max_depth_m
              << " m in a camera's image; " << summary.num_points_outside_view
              << " of " << input_in.NumPoints() << " points outside, removed";
    THROW_CHECK(input->NumPoints() >= 4,
                "Delaunay meshing: only " << input->NumPoints()
                    << " points lie in the cameras' view region");
  }

  // Memory guard.
  const size_t max_num_points = options.MaxNumPoints();
  if (input->NumPoints() > max_num_points) {
    LOG(WARNING) << input->NumPoints() << " points exceed the memory guard ("
                 << max_num_points << " points for " << options.max_memory_gb
                 << " GiB); decimating";
    if (input != &reduced) reduced = input_in;
    summary.decimation_voxel_size_m =
        DecimateMeshingInput(max_num_points, &reduced);
    input = &reduced;
  }

  StageTimer timer;
  MeshingTriangulation triangulation;
  {
    const ProgressWatchdog watchdog("Delaunay triangulation");
    BuildMeshingTriangulation(options.TriangulationOptions(), *input,
                              &triangulation);
  }
  summary.num_vertices = triangulation.NumVertices();
  summary.num_cells = triangulation.NumCells();
  summary.triangulation_seconds = timer.Seconds();

  timer = StageTimer();
  CellGraphWeights weights;
  {
    const ProgressWatchdog watchdog("Visibility integration");
    weights = IntegrateVisibility(options.VisibilityOptions(), *input,
                                  triangulation);
  }
  summary.num_rays = weights.num_rays;
  summary.num_failed_walks = weights.num_failed_walks;
  summary.distance_sigma_m = weights.distance_sigma;
  summary.visibility_seconds = timer.Seconds();

  timer = StageTimer();
  // The graph's edges, one per facet with capacity, in the cells' order;
  // built by chunks of cells on the threads (two circumspheres per facet),
  // the chunks then joined in order.
  const MeshDelaunay& delaunay = triangulation.delaunay;
  const size_t num_cells = triangulation.NumCells();
  constexpr size_t kCellsPerChunk = 1 << 16;
  const size_t num_chunks = (num_cells + kCellsPerChunk - 1) / kCellsPerChunk;
  std::vector<std::vector<GraphCutEdge>> chunk_edges(num_chunks);
  ParallelFor(0, static_cast<int>(num_chunks), options.num_threads,
              [&](int chunk_idx) {
    const size_t chunk = static_cast<size_t>(chunk_idx);
    std::vector<GraphCutEdge>& out = chunk_edges[chunk];
    out.reserve(2 * kCellsPerChunk);
    const size_t end = std::min(num_cells, (chunk + 1) * kCellsPerChunk);
    for (size_t c = chunk * kCellsPerChunk; c < end; ++c) {
      const MeshCellHandle& cell = triangulation.cells[c];
      for (int k = 0; k < 4; ++k) {
        const MeshCellHandle neighbor = cell->neighbor(k);
        if (cell->info() > neighbor->info()) continue;
        const int mirror = neighbor->index(cell);
        // Facets at infinity (between two infinite cells) cost
        // quality_regularization, which keeps an infinite cell with little
        // evidence from taking the other label than its neighbours (that
        // would open the surface along the hull).
        double shape = options.quality_regularization;
        if (!delaunay.is_infinite(cell, k)) {
          shape *= 1.0 - std::min(CosFacetCircumsphere(delaunay, cell, k),
                                  CosFacetCircumsphere(delaunay, neighbor,
                                                       mirror));
        }
        GraphCutEdge edge;
        edge.from = cell->info();
        edge.to = neighbor->info();
        edge.capacity = static_cast<float>(
            weights.facet_in[4 * static_cast<size_t>(neighbor->info()) +
                             mirror] +
            shape);
        edge.reverse_capacity = static_cast<float>(
            weights.facet_in[4 * static_cast<size_t>(cell->info()) + k] +
            shape);
        if (edge.capacity > 0 || edge.reverse_capacity > 0) {
          out.push_back(edge);
        }
      }
    }
  });
  std::vector<GraphCutEdge> edges;
  {
    size_t num_edges = 0;
    for (const std::vector<GraphCutEdge>& part : chunk_edges) {
      num_edges += part.size();
    }
    edges.reserve(num_edges);
    for (std::vector<GraphCutEdge>& part : chunk_edges) {
      edges.insert(edges.end(), part.begin(), part.end());
      std::vector<GraphCutEdge>().swap(part);
    }
  }
  std::vector<float>().swap(weights.facet_in);
  GraphCutResult cut;
  {
    // Boost's max-flow has no progress callback: the watchdog logs the
    // elapsed time.
    const ProgressWatchdog watchdog("Graph cut (max-flow)");
    cut = ComputeMinStCut(weights.source, weights.sink, edges);
  }
  std::vector<GraphCutEdge>().swap(edges);
  summary.max_flow = cut.max_flow;
  summary.graph_cut_seconds = timer.Seconds();
  LOG(INFO) << "Graph cut: " << triangulation.NumCells() << " cells, flow "
            << cut.max_flow << ", "
            << summary.graph_cut_seconds << " s";

  TriangleMesh mesh;
  {
    const ProgressWatchdog watchdog("Surface extraction and clean-up");
    mesh = ExtractSurface(triangulation, cut.is_source_side);
    summary.num_surface_faces = mesh.faces.size();
    summary.cleanup = CleanupMesh(options.CleanupOptions(), &mesh);
  }
  if (options.snap_to_creases && !input->creases.empty()) {
    summary.crease_snapping =
        SnapMeshToCreases(options.crease_snapping, input->creases,
                          input->positions, input->crease_spacing_m, &mesh);
    LOG(INFO) << "Crease snapping: "
              << summary.crease_snapping.num_vertices_moved
              << " vertices near " << summary.crease_snapping.num_creases
              << " line creases moved onto their faces by "
              << summary.crease_snapping.median_move_m << " m (median), "
              << summary.crease_snapping.max_move_m << " m at most; "
              << summary.crease_snapping.num_vertices_off_wedge
              << " left where the points around them are off the wedge";
  }
  summary.num_faces = mesh.faces.size();
  summary.num_mesh_vertices = mesh.vertices.size();
  summary.total_seconds = total_timer.Seconds();
  summary.peak_memory_bytes = PeakResidentMemoryBytes();
  LOG(INFO) << "Surface: " << summary.num_surface_faces << " faces, "
            << summary.num_faces << " after clean-up ("
            << summary.cleanup.num_long_edge_faces_removed << " long-edge, "
            << summary.cleanup.num_small_component_faces_removed
            << " in small components), " << summary.num_mesh_vertices
            << " vertices";
  if (mesh.faces.empty()) {
    LOG(WARNING) << "The Delaunay mesh is empty";
  }
  if (summary_out != nullptr) *summary_out = summary;
  return mesh;
}

DelaunayMeshingSummary MeshDenseWorkspace(
    const DelaunayMeshingOptions& options,
    const MeshingInputOptions& input_options,
    const std::string& workspace_path, const std::string& lines_model_path,
    const std::string& output_path, const std::string& database_path) {
  const StageTimer timer;
  MeshingInputOptions threaded_input_options = input_options;
  threaded_input_options.num_threads = options.num_threads;
  const MeshingInput input = ReadMeshingInput(
      threaded_input_options, workspace_path, lines_model_path, database_path);
  DelaunayMeshingSummary summary;
  const TriangleMesh mesh = TiledDelaunayMeshing(options, input, &summary);
  // Under mpirun the tiles are meshed on every rank and merged on rank 0,
  // which alone writes.
  if (!ProcessGroup::World().IsRoot()) return summary;
  WriteMeshPly(output_path, mesh);
  summary.total_seconds = timer.Seconds();
  summary.peak_memory_bytes = PeakResidentMemoryBytes();
  LOG(INFO) << "Wrote " << output_path << ": " << mesh.vertices.size()
            << " vertices, " << mesh.faces.size() << " faces in "
            << summary.total_seconds << " s, peak memory "
            << summary.peak_memory_bytes / (1024.0 * 1024.0) << " MiB";
  return summary;
}

}  // namespace colmap_lidar
