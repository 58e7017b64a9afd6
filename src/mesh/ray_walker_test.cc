#include "src/mesh/ray_walker.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "src/mesh/synthetic_box_scene.h"

namespace colmap_lidar {
namespace {

class RayWalkerTest : public ::testing::Test {
 protected:
  RayWalkerTest() {
    SyntheticBoxSceneOptions scene_options;
    scene_options.box_spacing_m = 0.04;
    scene_options.ground_spacing_m = 0.1;
    scene_options.noise_m = 0.001;
    const SyntheticBoxScene scene(scene_options);
    BuildMeshingTriangulation(
        DelaunayTriangulationOptions(),
        MakeVisualMeshingInput(scene, scene.SampleVisualPoints()),
        &triangulation);
    topology = BuildWalkTopology(triangulation);
    walk_vertex.resize(topology.NumVertices());
    for (size_t w = 0; w < topology.NumVertices(); ++w) {
      walk_vertex[topology.vertex_source[w]] = static_cast<uint32_t>(w);
    }
  }

  // The triangulation cells the walk enters from `vertex` to `target`, the
  // last one returned by the walk (a null handle if none).
  std::vector<MeshCellHandle> WalkedCells(RayWalker* walker,
                                          const MeshVertexHandle& vertex,
                                          const MeshPoint& target,
                                          bool stay_finite) {
    std::vector<MeshCellHandle> cells;
    double last_t = -1;
    const uint32_t start = walk_vertex[vertex->info()];
    std::vector<uint32_t> star;
    CollectStar(topology, start, &star);
    const uint32_t last = walker->Walk(
        start, star, target, stay_finite,
        [&](uint32_t cell, int k, double t) {
          const MeshCellHandle handle =
              triangulation.cells[topology.cell_source[cell]];
          EXPECT_TRUE(cells.empty() || cells.back() != handle);
          cells.push_back(handle);
          // The crossing's parameter: that of the facet's plane.
          Eigen::Vector3d p[3];
          for (int i = 0, j = 0; i < 4; ++i) {
            if (i != k) p[j++] = ToEigen(handle->vertex(i)->point());
          }
          const Eigen::Vector3d origin = ToEigen(vertex->point());
          const Eigen::Vector3d direction = ToEigen(target) - origin;
          const Eigen::Vector3d normal = (p[1] - p[0]).cross(p[2] - p[0]);
          const double expected_t =
              normal.dot(p[0] - origin) / normal.dot(direction);
          if (!std::isnan(t)) {
            EXPECT_NEAR(t, expected_t, 1e-9);
            EXPECT_GE(t, last_t - 1e-12);
            last_t = t;
            ++num_parameters;
          }
          EXPECT_FALSE(topology.IsInfinite(cell));
          EXPECT_GE(k, 0);
          EXPECT_LT(k, 4);
        });
    cells.push_back(last == WalkTopology::kNoCell
                        ? MeshCellHandle()
                        : triangulation.cells[topology.cell_source[last]]);
    return cells;
  }

  MeshingTriangulation triangulation;
  WalkTopology topology;
  size_t num_parameters = 0;  // Crossings with a known parameter.
  std::vector<uint32_t> walk_vertex;  // By triangulation vertex.
};

// The compact copy holds the triangulation: same vertices, neighbours and
// positions under the renumbering, each cell and vertex once.
TEST_F(RayWalkerTest, TopologyMatchesTheTriangulation) {
  const MeshDelaunay& delaunay = triangulation.delaunay;
  ASSERT_EQ(topology.NumCells(), triangulation.NumCells());
  ASSERT_EQ(topology.NumVertices(), triangulation.NumVertices());
  std::vector<uint32_t> walk_cell(topology.NumCells(), WalkTopology::kNoCell);
  for (size_t c = 0; c < topology.NumCells(); ++c) {
    ASSERT_EQ(walk_cell[topology.cell_source[c]], WalkTopology::kNoCell);
    walk_cell[topology.cell_source[c]] = static_cast<uint32_t>(c);
  }
  for (size_t c = 0; c < topology.NumCells(); ++c) {
    const MeshCellHandle& cell = triangulation.cells[topology.cell_source[c]];
    EXPECT_EQ(topology.IsInfinite(c), delaunay.is_infinite(cell));
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(topology.Neighbor(c, k), walk_cell[cell->neighbor(k)->info()]);
      const uint32_t vertex = topology.Vertex(c, k);
      if (delaunay.is_infinite(cell->vertex(k))) {
        EXPECT_EQ(vertex, WalkTopology::kInfinite);
      } else {
        EXPECT_EQ(vertex, walk_vertex[cell->vertex(k)->info()]);
        EXPECT_EQ(topology.points[vertex], cell->vertex(k)->point());
      }
    }
  }
  for (size_t w = 0; w < topology.NumVertices(); ++w) {
    const int k = topology.IndexOfVertex(topology.vertex_cell[w],
                                         static_cast<uint32_t>(w));
    EXPECT_EQ(topology.Vertex(topology.vertex_cell[w], k), w);
  }
}

// Walks from vertices to points strictly inside random finite cells give
// the cells of CGAL's own segment traverser (started a hair along the ray,
// so that it does not start on the vertex).
TEST_F(RayWalkerTest, SameCellsAsCgalSegmentTraverser) {
  const MeshDelaunay& delaunay = triangulation.delaunay;
  std::vector<MeshCellHandle> finite_cells;
  for (const MeshCellHandle& cell : triangulation.cells) {
    if (!delaunay.is_infinite(cell)) finite_cells.push_back(cell);
  }
  ASSERT_GT(finite_cells.size(), 1000u);
  std::mt19937 rng(7);
  std::uniform_int_distribution<size_t> pick_cell(0, finite_cells.size() - 1);
  std::uniform_int_distribution<size_t> pick_vertex(
      0, triangulation.NumVertices() - 1);
  RayWalker walker(topology);
  size_t total_cells = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const MeshVertexHandle vertex = triangulation.vertices[pick_vertex(rng)];
    const MeshCellHandle target_cell = finite_cells[pick_cell(rng)];
    Eigen::Vector3d target = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) {
      target += ToEigen(target_cell->vertex(k)->point()) / 4;
    }
    const std::vector<MeshCellHandle> walked =
        WalkedCells(&walker, vertex, ToCgal(target), /*stay_finite=*/false);
    const Eigen::Vector3d origin = ToEigen(vertex->point());
    std::vector<MeshCellHandle> expected;
    for (auto it = delaunay.segment_traverser_cells_begin(
             ToCgal(origin + 1e-7 * (target - origin)), ToCgal(target));
         it != delaunay.segment_traverser_cells_end(); ++it) {
      expected.push_back(it);
    }
    // Both ends lie in the convex hull, and so does the segment.
    EXPECT_EQ(walked.back(), target_cell);
    EXPECT_EQ(walked, expected) << "trial " << trial;
    total_cells += walked.size();
  }
  EXPECT_GT(total_cells, 500u * 5);  // The walks are not trivial.
  // The filter decides almost every side: parameters are known.
  EXPECT_GT(num_parameters, total_cells - 500u - total_cells / 100);
}

// A start-cell hint changes nothing but the search: the same cells, and
// the hint then holds the cell the walk started in.
TEST_F(RayWalkerTest, HintedWalksGiveTheSameCells) {
  std::vector<MeshCellHandle> finite_cells;
  for (const MeshCellHandle& cell : triangulation.cells) {
    if (!triangulation.delaunay.is_infinite(cell)) finite_cells.push_back(cell);
  }
  std::mt19937 rng(11);
  std::uniform_int_distribution<size_t> pick_cell(0, finite_cells.size() - 1);
  RayWalker walker(topology);
  std::vector<uint32_t> star;
  for (size_t v = 0; v < triangulation.NumVertices(); v += 97) {
    const uint32_t start = walk_vertex[v];
    CollectStar(topology, start, &star);
    uint32_t hint = WalkTopology::kNoCell;
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::Vector3d target = Eigen::Vector3d::Zero();
      const MeshCellHandle target_cell = finite_cells[pick_cell(rng)];
      for (int k = 0; k < 4; ++k) {
        target += ToEigen(target_cell->vertex(k)->point()) / 4;
      }
      std::vector<std::pair<uint32_t, int>> plain, hinted;
      const uint32_t plain_end = walker.Walk(
          start, star, ToCgal(target), /*stay_finite=*/false,
          [&](uint32_t cell, int k, double) { plain.emplace_back(cell, k); });
      const uint32_t hinted_end = walker.Walk(
          start, star, ToCgal(target), /*stay_finite=*/false,
          [&](uint32_t cell, int k, double) { hinted.emplace_back(cell, k); },
          &hint);
      EXPECT_EQ(plain_end, hinted_end);
      EXPECT_EQ(plain, hinted);
      EXPECT_EQ(hint, plain.empty() ? plain_end : plain.front().first);
    }
  }
}

// A walk from a vertex out of the convex hull stops at the first infinite
// cell, or with stay_finite at the last finite one; a step limit gives a
// null handle.
TEST_F(RayWalkerTest, LeavesTheHullAndStopsAtTheStepLimit) {
  const MeshDelaunay& delaunay = triangulation.delaunay;
  RayWalker walker(topology);
  // The vertex farthest along +x, walked further along +x.
  MeshVertexHandle extreme = triangulation.vertices[0];
  for (const MeshVertexHandle& vertex : triangulation.vertices) {
    if (vertex->point().x() > extreme->point().x()) extreme = vertex;
  }
  const MeshPoint beyond(extreme->point().x() + 10, extreme->point().y(),
                         extreme->point().z());
  EXPECT_TRUE(delaunay.is_infinite(
      WalkedCells(&walker, extreme, beyond, /*stay_finite=*/false).back()));
  // From the opposite extreme through the whole scene.
  MeshVertexHandle opposite = triangulation.vertices[0];
  for (const MeshVertexHandle& vertex : triangulation.vertices) {
    if (vertex->point().x() < opposite->point().x()) opposite = vertex;
  }
  const MeshPoint across(extreme->point().x() + 10, opposite->point().y(),
                         opposite->point().z() + 0.01);
  const std::vector<MeshCellHandle> crossed =
      WalkedCells(&walker, opposite, across, /*stay_finite=*/true);
  ASSERT_GT(crossed.size(), 3u);
  EXPECT_FALSE(delaunay.is_infinite(crossed.back()));
  const uint32_t start = walk_vertex[opposite->info()];
  std::vector<uint32_t> star;
  CollectStar(topology, start, &star);
  EXPECT_EQ(walker.Walk(start, star, across, /*stay_finite=*/true,
                        [](uint32_t, int, double) {},
                        /*first_cell_hint=*/nullptr, /*max_steps=*/2),
            WalkTopology::kNoCell);
}

}  // namespace
}  // namespace colmap_lidar
