#include "src/mesh/delaunay_triangulation.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <utility>

#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

constexpr uint32_t kNoVertex = 0xFFFFFFFFu;

// Spreads the low 21 bits of `value` to every third bit.
uint64_t SpreadBits(uint64_t value) {
  value &= (1ull << 21) - 1;
  value = (value | (value << 32)) & 0x1f00000000ffffull;
  value = (value | (value << 16)) & 0x1f0000ff0000ffull;
  value = (value | (value << 8)) & 0x100f00f00f00f00full;
  value = (value | (value << 4)) & 0x10c30c30c30c30c3ull;
  value = (value | (value << 2)) & 0x1249249249249249ull;
  return value;
}

// Sorts the point indices by the Morton code of their 1 cm cell of a grid
// fixed in the world (21 bits per axis around the origin: +-10 km), ties by
// index.
void SortInWorldGridOrder(const std::vector<Eigen::Vector3d>& positions,
                          std::vector<size_t>* indices) {
  constexpr double kCellM = 0.01;
  std::vector<std::pair<uint64_t, size_t>> keyed;
  keyed.reserve(indices->size());
  for (const size_t index : *indices) {
    uint64_t code = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double cell = std::floor(positions[index][axis] / kCellM);
      const uint64_t biased = static_cast<uint64_t>(
          std::clamp(cell + (1 << 20), 0.0, static_cast<double>((1 << 21) - 1)));
      code |= SpreadBits(biased) << axis;
    }
    keyed.emplace_back(code, index);
  }
  std::sort(keyed.begin(), keyed.end());
  for (size_t i = 0; i < keyed.size(); ++i) (*indices)[i] = keyed[i].second;
}

// True when the visual point may be represented by `vertex_position`: close
// in every observing image, in pixels and in relative depth.
bool IsCloseInImages(const DelaunayTriangulationOptions& options,
                     const MeshingInput& input, size_t point_idx,
                     const Eigen::Vector3d& vertex_position) {
  const Eigen::Vector3d& position = input.positions[point_idx];
  const double max_sq_dist = options.max_proj_dist_px * options.max_proj_dist_px;
  for (const uint32_t sensor_idx : input.visibility[point_idx]) {
    const MeshingSensor& sensor = input.sensors[sensor_idx];
    if (!sensor.is_camera) return false;
    const Eigen::Vector3d a = sensor.proj_matrix * position.homogeneous();
    const Eigen::Vector3d b = sensor.proj_matrix * vertex_position.homogeneous();
    if (a.z() <= 0 || b.z() <= 0) return false;
    const double depth_ratio = a.z() / b.z();
    if (std::abs(depth_ratio - 1.0) > options.max_depth_dist) return false;
    if ((a.hnormalized() - b.hnormalized()).squaredNorm() > max_sq_dist) {
      return false;
    }
  }
  return true;
}

}  // namespace

bool DelaunayTriangulationOptions::Check() const {
  if (!(max_proj_dist_px >= 0)) {
    LOG(ERROR) << "DelaunayMeshing.max_proj_dist_px must be >= 0";
    return false;
  }
  if (!(max_depth_dist >= 0 && max_depth_dist <= 1)) {
    LOG(ERROR) << "DelaunayMeshing.max_depth_dist must be in [0, 1]";
    return false;
  }
  if (!(min_lidar_vertex_distance_m >= 0)) {
    LOG(ERROR) << "DelaunayMeshing.min_lidar_vertex_distance_m must be >= 0";
    return false;
  }
  return true;
}

void BuildMeshingTriangulation(const DelaunayTriangulationOptions& options,
                               const MeshingInput& input,
                               MeshingTriangulation* triangulation) {
  THROW_CHECK(options.Check(), "Invalid Delaunay triangulation options");
  input.Check();
  MeshDelaunay& delaunay = triangulation->delaunay;
  delaunay.clear();
  triangulation->vertices.clear();
  triangulation->vertex_sources.clear();
  triangulation->point_to_vertex.assign(input.NumPoints(), kNoVertex);

  // Line samples first, then visual points, then LIDAR voxels (so that a
  // voxel finds the visual vertices it may merge into); each group in
  // spatial order so that the previous vertex is a good location hint.
  std::vector<size_t> line_points;
  std::vector<size_t> visual_points;
  std::vector<size_t> lidar_points;
  for (uint32_t i = 0; i < input.NumPoints(); ++i) {
    switch (input.sources[i]) {
      case MeshingPointSource::kLine:
        line_points.push_back(i);
        break;
      case MeshingPointSource::kVisual:
        visual_points.push_back(i);
        break;
      case MeshingPointSource::kLidar:
        lidar_points.push_back(i);
        break;
    }
  }
  {
    std::vector<MeshPoint> points;
    points.reserve(input.NumPoints());
    for (const Eigen::Vector3d& position : input.positions) {
      points.push_back(ToCgal(position));
    }
    using Traits = CGAL::Spatial_sort_traits_adapter_3<
        MeshKernel, CGAL::Pointer_property_map<MeshPoint>::type>;
    const Traits traits(CGAL::make_property_map(points));
    for (std::vector<size_t>* group :
         {&line_points, &visual_points, &lidar_points}) {
      if (options.world_grid_order) {
        SortInWorldGridOrder(input.positions, group);
      } else {
        CGAL::spatial_sort(group->begin(), group->end(), traits);
      }
    }
  }

  const double sq_lidar_dist = options.min_lidar_vertex_distance_m *
                               options.min_lidar_vertex_distance_m;
  MeshCellHandle hint;
  size_t num_merged = 0;
  // world_grid_order: the merge candidates are the vertices within a grid
  // neighbourhood (kMergeCellM cells, the 27 around the point), not those
  // of the enclosing cell, whose shape depends on points far away.
  constexpr double kMergeCellM = 0.1;
  std::unordered_map<uint64_t, std::vector<uint32_t>> vertex_grid;
  const auto grid_key = [](const Eigen::Vector3d& position, int dx, int dy,
                           int dz) {
    const auto cell = [](double value, int offset) {
      return static_cast<uint64_t>(
                 static_cast<int64_t>(std::floor(value / kMergeCellM)) +
                 offset + (1 << 20)) &
             ((1ull << 21) - 1);
    };
    return (cell(position.x(), dx) << 42) | (cell(position.y(), dy) << 21) |
           cell(position.z(), dz);
  };
  auto insert = [&](size_t point_idx) {
    const Eigen::Vector3d& position = input.positions[point_idx];
    const MeshPoint point = ToCgal(position);
    const MeshingPointSource source = input.sources[point_idx];
    const bool may_merge =
        delaunay.dimension() == 3 &&
        ((source == MeshingPointSource::kVisual &&
          options.max_proj_dist_px > 0) ||
         (source == MeshingPointSource::kLidar && sq_lidar_dist > 0));
    MeshDelaunay::Locate_type locate_type;
    int li, lj;
    const MeshCellHandle cell =
        delaunay.locate(point, locate_type, li, lj, hint);
    if (may_merge && options.world_grid_order) {
      uint32_t nearest = kNoVertex;
      double nearest_sq_dist = std::numeric_limits<double>::max();
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = vertex_grid.find(grid_key(position, dx, dy, dz));
            if (it == vertex_grid.end()) continue;
            for (const uint32_t candidate : it->second) {
              if (source == MeshingPointSource::kLidar &&
                  triangulation->vertex_sources[candidate] ==
                      MeshingPointSource::kLidar) {
                continue;
              }
              const double sq_dist =
                  (ToEigen(triangulation->vertices[candidate]->point()) -
                   position)
                      .squaredNorm();
              if (sq_dist < nearest_sq_dist ||
                  (sq_dist == nearest_sq_dist && candidate < nearest)) {
                nearest_sq_dist = sq_dist;
                nearest = candidate;
              }
            }
          }
        }
      }
      const bool merge =
          nearest != kNoVertex &&
          (source == MeshingPointSource::kLidar
               ? nearest_sq_dist <= sq_lidar_dist
               : IsCloseInImages(
                     options, input, point_idx,
                     ToEigen(triangulation->vertices[nearest]->point())));
      if (merge) {
        triangulation->point_to_vertex[point_idx] = nearest;
        ++num_merged;
        return;
      }
    } else if (may_merge && !delaunay.is_infinite(cell)) {
      // The nearest finite vertex of the enclosing cell (for a LIDAR voxel:
      // the nearest visual or line vertex).
      int nearest = -1;
      double nearest_sq_dist = std::numeric_limits<double>::max();
      for (int k = 0; k < 4; ++k) {
        if (source == MeshingPointSource::kLidar &&
            triangulation->vertex_sources[cell->vertex(k)->info()] ==
                MeshingPointSource::kLidar) {
          continue;
        }
        const double sq_dist =
            (ToEigen(cell->vertex(k)->point()) - position).squaredNorm();
        if (sq_dist < nearest_sq_dist) {
          nearest_sq_dist = sq_dist;
          nearest = k;
        }
      }
      const MeshVertexHandle vertex =
          nearest < 0 ? MeshVertexHandle() : cell->vertex(nearest);
      const bool merge =
          nearest >= 0 &&
          (source == MeshingPointSource::kLidar
               ? nearest_sq_dist <= sq_lidar_dist
               : IsCloseInImages(options, input, point_idx,
                                 ToEigen(vertex->point())));
      if (merge) {
        triangulation->point_to_vertex[point_idx] = vertex->info();
        hint = cell;
        ++num_merged;
        return;
      }
    }
    const size_t num_before = delaunay.number_of_vertices();
    const MeshVertexHandle vertex =
        delaunay.insert(point, locate_type, cell, li, lj);
    if (delaunay.number_of_vertices() > num_before) {
      vertex->info() = static_cast<uint32_t>(triangulation->vertices.size());
      triangulation->vertices.push_back(vertex);
      triangulation->vertex_sources.push_back(source);
      if (options.world_grid_order) {
        vertex_grid[grid_key(position, 0, 0, 0)].push_back(vertex->info());
      }
    } else {
      ++num_merged;  // An exact duplicate.
    }
    triangulation->point_to_vertex[point_idx] = vertex->info();
    hint = vertex->cell();
  };
  for (const std::vector<size_t>* group :
       {&line_points, &visual_points, &lidar_points}) {
    for (const size_t point_idx : *group) insert(point_idx);
  }

  THROW_CHECK(delaunay.dimension() == 3,
              "The " << input.NumPoints()
                     << " meshing points span no volume (dimension "
                     << delaunay.dimension() << ")");

  // Cells numbered by their first vertex (a counting sort, stable in
  // CGAL's order): the vertices are in spatial order within each group, and
  // so are the cells then, which keeps the per-cell arrays and the graph
  // cut's nodes of neighbouring cells near each other in memory (CGAL's own
  // order follows the insertions' history; the max-flow is memory-bound).
  const size_t num_vertices = triangulation->vertices.size();
  std::vector<size_t> key_begin(num_vertices + 2, 0);
  auto cell_key = [&](const MeshCellHandle& cell) {
    uint32_t key = static_cast<uint32_t>(num_vertices);
    for (int k = 0; k < 4; ++k) {
      if (!delaunay.is_infinite(cell->vertex(k))) {
        key = std::min(key, cell->vertex(k)->info());
      }
    }
    return key;
  };
  for (auto it = delaunay.all_cells_begin(); it != delaunay.all_cells_end();
       ++it) {
    ++key_begin[cell_key(it) + 1];
  }
  std::partial_sum(key_begin.begin(), key_begin.end(), key_begin.begin());
  triangulation->cells.assign(delaunay.number_of_cells(), MeshCellHandle());
  for (auto it = delaunay.all_cells_begin(); it != delaunay.all_cells_end();
       ++it) {
    const size_t index = key_begin[cell_key(it)]++;
    it->info() = static_cast<uint32_t>(index);
    triangulation->cells[index] = it;
  }
  LOG(INFO) << "Delaunay triangulation: " << triangulation->NumVertices()
            << " vertices from " << input.NumPoints() << " points ("
            << num_merged << " merged), " << triangulation->NumCells()
            << " cells";
}

}  // namespace colmap_lidar
