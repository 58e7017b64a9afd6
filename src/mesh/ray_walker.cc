#include "src/mesh/ray_walker.h"

#include <algorithm>
#include <numeric>

#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/property_map.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

WalkTopology BuildWalkTopology(const MeshingTriangulation& triangulation) {
  const size_t num_vertices = triangulation.NumVertices();
  const size_t num_cells = triangulation.NumCells();
  THROW_CHECK(num_vertices < WalkTopology::kInfinite &&
                  num_cells < WalkTopology::kNoCell,
              "Too many vertices or cells for 32-bit indices: "
                  << num_vertices << ", " << num_cells);
  const MeshDelaunay& delaunay = triangulation.delaunay;
  WalkTopology topology;

  // Vertices along a Hilbert curve (deterministic: median policy).
  std::vector<MeshPoint> points;
  points.reserve(num_vertices);
  for (const MeshVertexHandle& vertex : triangulation.vertices) {
    points.push_back(vertex->point());
  }
  std::vector<size_t> order(num_vertices);
  std::iota(order.begin(), order.end(), size_t{0});
  using Traits = CGAL::Spatial_sort_traits_adapter_3<
      MeshKernel, CGAL::Pointer_property_map<MeshPoint>::type>;
  CGAL::hilbert_sort(order.begin(), order.end(),
                     Traits(CGAL::make_property_map(points)));
  topology.points.resize(num_vertices);
  topology.vertex_source.resize(num_vertices);
  std::vector<uint32_t> walk_vertex(num_vertices);
  for (size_t w = 0; w < num_vertices; ++w) {
    topology.points[w] = points[order[w]];
    topology.vertex_source[w] = static_cast<uint32_t>(order[w]);
    walk_vertex[order[w]] = static_cast<uint32_t>(w);
  }
  points.clear();
  points.shrink_to_fit();

  // Cells by their first walk vertex: a counting sort, stable in the
  // triangulation's cell order.
  std::vector<uint32_t> cell_key(num_cells);
  std::vector<size_t> key_begin(num_vertices + 1, 0);
  for (size_t c = 0; c < num_cells; ++c) {
    const MeshCellHandle& cell = triangulation.cells[c];
    uint32_t key = WalkTopology::kInfinite;
    for (int k = 0; k < 4; ++k) {
      if (!delaunay.is_infinite(cell->vertex(k))) {
        key = std::min(key, walk_vertex[cell->vertex(k)->info()]);
      }
    }
    cell_key[c] = key;
    ++key_begin[key + 1];
  }
  std::partial_sum(key_begin.begin(), key_begin.end(), key_begin.begin());
  topology.cell_source.resize(num_cells);
  std::vector<uint32_t> walk_cell(num_cells);
  for (size_t c = 0; c < num_cells; ++c) {
    const size_t position = key_begin[cell_key[c]]++;
    topology.cell_source[position] = static_cast<uint32_t>(c);
    walk_cell[c] = static_cast<uint32_t>(position);
  }
  cell_key.clear();
  cell_key.shrink_to_fit();

  topology.cells.resize(num_cells);
  for (size_t w = 0; w < num_cells; ++w) {
    const MeshCellHandle& cell = triangulation.cells[topology.cell_source[w]];
    for (int k = 0; k < 4; ++k) {
      topology.cells[w].vertices[k] =
          delaunay.is_infinite(cell->vertex(k))
              ? WalkTopology::kInfinite
              : walk_vertex[cell->vertex(k)->info()];
      topology.cells[w].neighbors[k] = walk_cell[cell->neighbor(k)->info()];
    }
  }
  topology.vertex_cell.resize(num_vertices);
  for (size_t w = 0; w < num_vertices; ++w) {
    topology.vertex_cell[w] = walk_cell[triangulation
                                            .vertices[topology.vertex_source[w]]
                                            ->cell()
                                            ->info()];
  }
  return topology;
}

void CollectStar(const WalkTopology& topology, uint32_t vertex,
                 std::vector<uint32_t>* star) {
  star->clear();
  star->push_back(topology.vertex_cell[vertex]);
  for (size_t i = 0; i < star->size(); ++i) {
    const uint32_t cell = (*star)[i];
    for (int k = 0; k < 4; ++k) {
      if (topology.Vertex(cell, k) == vertex) continue;
      const uint32_t neighbor = topology.Neighbor(cell, k);
      if (std::find(star->begin(), star->end(), neighbor) == star->end()) {
        star->push_back(neighbor);
      }
    }
  }
}

bool RayWalker::InCone(uint32_t cell, uint32_t vertex) const {
  const int vertex_idx = topology_.IndexOfVertex(cell, vertex);
  for (int j = 0; j < 4; ++j) {
    if (j != vertex_idx &&
        OrientationWithReplaced(cell, j, *target_) == CGAL::NEGATIVE) {
      return false;
    }
  }
  return true;
}

uint32_t RayWalker::FirstCell(uint32_t vertex,
                              const std::vector<uint32_t>& star,
                              uint32_t hint) const {
  if (hint != WalkTopology::kNoCell && InCone(hint, vertex)) return hint;
  for (const uint32_t candidate : star) {
    if (candidate != hint && !topology_.IsInfinite(candidate) &&
        InCone(candidate, vertex)) {
      return candidate;
    }
  }
  return WalkTopology::kNoCell;
}

uint32_t RayWalker::HullCell(const std::vector<uint32_t>& star) const {
  // The direction leaves the convex hull at the vertex.
  uint32_t fallback = WalkTopology::kNoCell;
  for (const uint32_t candidate : star) {
    if (!topology_.IsInfinite(candidate)) continue;
    fallback = candidate;
    const int infinite_idx =
        topology_.IndexOfVertex(candidate, WalkTopology::kInfinite);
    if (OrientationWithReplaced(candidate, infinite_idx, *target_) ==
        CGAL::POSITIVE) {
      return candidate;
    }
  }
  return fallback;
}

void RayWalker::SetFacet(uint32_t cell, int k) {
  for (int i = 0, j = 0; i < 4; ++i) {
    if (i != k) facet_[j++] = topology_.Vertex(cell, i);
  }
  for (int i = 0; i < 3; ++i) facet_relative_[i] = MakeRelative(facet_[i]);
  for (int i = 0; i < 3; ++i) {
    const int next = (i + 1) % 3;
    facet_side_[i] = Side(facet_[i], facet_relative_[i], facet_[next],
                          facet_relative_[next], &facet_value_[i]);
  }
}

}  // namespace colmap_lidar
