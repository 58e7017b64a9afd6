#include "src/mesh/tiled_meshing.h"

#include <algorithm>
#include <limits>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"
#include "src/mesh/synthetic_box_scene.h"

namespace colmap_lidar {
namespace {

// The budget of max_memory_gb in points.
double MemoryForPoints(size_t num_points) {
  return num_points * kEstimatedBytesPerPoint / (1ull << 30);
}

// Midpoints of the edges used by one face or by more than two, within
// `half_size` of the scene's centre in x and y (the ground's outer rim is
// open in any mesh).
std::vector<Eigen::Vector3d> OpenEdges(const TriangleMesh& mesh,
                                       double half_size) {
  const MeshEdgeStats stats = ComputeMeshEdgeStats(mesh);
  std::vector<Eigen::Vector3d> middles;
  for (const auto* edges : {&stats.boundary_edges, &stats.non_manifold_edges}) {
    for (const auto& edge : *edges) {
      const Eigen::Vector3d middle =
          0.5 * (mesh.vertices[edge[0]] + mesh.vertices[edge[1]]);
      if (std::abs(middle.x()) < half_size &&
          std::abs(middle.y()) < half_size) {
        middles.push_back(middle);
      }
    }
  }
  return middles;
}

// Distance of a position to the nearest seam between two tiles, in the
// tiles' plane.
double DistanceToSeam(const MeshingTiles& tiles,
                      const Eigen::Vector3d& position) {
  const Eigen::Vector3d offset = position - tiles.origin;
  double distance = std::numeric_limits<double>::infinity();
  for (int i = 1; i < tiles.num_u; ++i) {
    distance = std::min(distance, std::abs(tiles.axis_u.dot(offset) -
                                           tiles.u_min - i * tiles.size_m));
  }
  for (int j = 1; j < tiles.num_v; ++j) {
    distance = std::min(distance, std::abs(tiles.axis_v.dot(offset) -
                                           tiles.v_min - j * tiles.size_m));
  }
  return distance;
}

class TiledMeshing : public ::testing::Test {
 protected:
  TiledMeshing() : scene_(SceneOptions()) {
    input_ = MakeVisualMeshingInput(scene_, scene_.SampleVisualPoints());
    options_.num_threads = 2;
    // Free space carved 5 sigma (about 0.2 m) in front of the points: the
    // margin of 0.5 m holds the rays that shape a core's edge.
    options_.max_free_space_length_factor = 5.0;
    options_.tile_margin_m = 0.5;
  }

  static SyntheticBoxSceneOptions SceneOptions() {
    SyntheticBoxSceneOptions options;
    options.noise_m = 0.001;
    // A ground wide enough for tiles of a few metres.
    options.ground_half_size_m = 6.0;
    options.ring_radius_m = 4.0;
    return options;
  }

  SyntheticBoxScene scene_;
  MeshingInput input_;
  DelaunayMeshingOptions options_;
};

TEST_F(TiledMeshing, TilesHoldTheBudgetAndPartitionThePoints) {
  const size_t budget = input_.NumPoints() / 3;
  const MeshingTiles tiles = ChooseMeshingTiles(input_, budget, 0.5);
  ASSERT_GT(tiles.NumTiles(), 1);
  EXPECT_LE(tiles.max_tile_points, budget);
  EXPECT_GE(tiles.size_m, 2 * 0.5);  // Never below two margins.
  std::vector<size_t> num_core(tiles.NumTiles(), 0);
  for (const Eigen::Vector3d& position : input_.positions) {
    const int tile = tiles.TileOf(position);
    ASSERT_GE(tile, 0);
    ASSERT_LT(tile, tiles.NumTiles());
    ++num_core[tile];
    // Its core holds it, no other core does.
    for (int other = 0; other < tiles.NumTiles(); ++other) {
      EXPECT_EQ(tiles.Contains(other, position, 0.0), other == tile);
    }
  }
  size_t num_nonempty = 0;
  const std::vector<size_t> counts = tiles.CountPoints(input_.positions);
  const std::vector<std::vector<uint32_t>> points =
      tiles.PointsPerTile(input_.positions);
  for (int tile = 0; tile < tiles.NumTiles(); ++tile) {
    for (size_t i = 0; i < input_.NumPoints(); ++i) {
      EXPECT_EQ(std::binary_search(points[tile].begin(), points[tile].end(),
                                   static_cast<uint32_t>(i)),
                tiles.Contains(tile, input_.positions[i], tiles.margin_m));
    }
    const MeshingInput part =
        TileMeshingInput(input_, points[tile], tiles, tile);
    EXPECT_EQ(part.NumPoints(), counts[tile]);
    EXPECT_LE(part.NumPoints(), budget);
    EXPECT_GE(part.NumPoints(), num_core[tile]);
    EXPECT_NO_THROW(part.Check());
    num_nonempty += num_core[tile] > 0;
  }
  EXPECT_GT(num_nonempty, 1u);
  // Within the budget: one tile, which holds everything.
  const MeshingTiles one = ChooseMeshingTiles(input_, input_.NumPoints(), 0.5);
  EXPECT_EQ(one.NumTiles(), 1);
  EXPECT_EQ(one.TileOf(input_.positions.front()), 0);
  EXPECT_TRUE(one.Contains(0, input_.positions.back(), 0.0));
  EXPECT_EQ(one.CountPoints(input_.positions),
            std::vector<size_t>{input_.NumPoints()});
}

TEST_F(TiledMeshing, WithinTheBudgetIsTheMesherItself) {
  options_.max_memory_gb = MemoryForPoints(input_.NumPoints() + 1);
  DelaunayMeshingSummary summary;
  const TriangleMesh tiled = TiledDelaunayMeshing(options_, input_, &summary);
  EXPECT_EQ(summary.num_tiles, 1);
  const TriangleMesh whole = DelaunayMeshing(options_, input_);
  EXPECT_EQ(tiled.faces, whole.faces);
  EXPECT_EQ(tiled.vertices, whole.vertices);
}

TEST_F(TiledMeshing, TilesGiveTheSurfaceClosedAcrossTheSeams) {
  const TriangleMesh whole = DelaunayMeshing(options_, input_);
  // A budget of a third of the points (and the held input's share).
  options_.max_memory_gb = MemoryForPoints(input_.NumPoints() / 3);
  DelaunayMeshingSummary summary;
  const TriangleMesh tiled = TiledDelaunayMeshing(options_, input_, &summary);
  const MeshingTiles tiles = ChooseMeshingTiles(
      input_, MaxTilePointsForBudget(options_, input_.NumPoints()),
      options_.tile_margin_m);
  LOG(INFO) << summary.num_tiles << " tiles of " << summary.tile_size_m
            << " m: " << tiled.faces.size() << " faces (one piece "
            << whole.faces.size() << ")";
  ASSERT_GT(summary.num_tiles, 1);
  EXPECT_EQ(summary.num_tiles, tiles.NumTiles());
  EXPECT_EQ(summary.tile_size_m, tiles.size_m);
  EXPECT_EQ(summary.decimation_voxel_size_m, 0.0);
  EXPECT_EQ(summary.num_input_points, input_.NumPoints());
  tiled.CheckIndices();
  // As accurate and as complete as the mesh in one piece.
  const std::vector<double> distances = FaceDistancesToSurface(scene_, tiled);
  EXPECT_LT(Percentile(distances, 50), 0.002);
  EXPECT_LT(Percentile(distances, 95), 0.005);
  const double coverage = SurfaceCoverage(scene_, tiled, 0.01);
  const double whole_coverage = SurfaceCoverage(scene_, whole, 0.01);
  LOG(INFO) << "Coverage at 1 cm: tiles " << coverage << ", one piece "
            << whole_coverage;
  EXPECT_GT(coverage, whole_coverage - 0.01);
  // The seams cross the ground (every seam) and the box's surroundings: no
  // edge opens along them (the box's top edges may open in any mesh, as
  // the one piece's does).
  const double inner = scene_.Options().ground_half_size_m - 0.3;
  const std::vector<Eigen::Vector3d> open = OpenEdges(tiled, inner);
  for (const Eigen::Vector3d& middle : open) {
    EXPECT_GT(DistanceToSeam(tiles, middle), 0.2)
        << "open edge at " << middle.transpose() << " on a seam";
  }
  EXPECT_LE(open.size(), OpenEdges(whole, inner).size() + 3);
  // No face twice, every vertex used.
  std::vector<std::array<uint32_t, 3>> faces = tiled.faces;
  for (auto& face : faces) std::sort(face.begin(), face.end());
  std::sort(faces.begin(), faces.end());
  EXPECT_EQ(std::adjacent_find(faces.begin(), faces.end()), faces.end());
  std::vector<bool> used(tiled.vertices.size(), false);
  for (const auto& face : tiled.faces) {
    for (const uint32_t vertex : face) used[vertex] = true;
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
  EXPECT_TRUE(std::is_sorted(tiled.faces.begin(), tiled.faces.end()));
  for (const std::array<uint32_t, 3>& face : tiled.faces) {
    ASSERT_LT(face[0], face[1]);
    ASSERT_LT(face[0], face[2]);
  }
  // Deterministic: a second run gives the same mesh.
  const TriangleMesh again = TiledDelaunayMeshing(options_, input_);
  EXPECT_EQ(again.faces, tiled.faces);
  EXPECT_EQ(again.vertices, tiled.vertices);
}

TEST_F(TiledMeshing, RejectsABadMargin) {
  options_.tile_margin_m = -1.0;
  EXPECT_FALSE(options_.Check());
  EXPECT_THROW(TiledDelaunayMeshing(options_, input_), Error);
}

}  // namespace
}  // namespace colmap_lidar
