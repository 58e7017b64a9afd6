#include "src/mesh/visibility_integration.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <gtest/gtest.h>

#include "src/mesh/synthetic_box_scene.h"

namespace colmap_lidar {
namespace {

// The box on the ground, sparsely sampled, seen by the ring of cameras.
SyntheticBoxSceneOptions SparseBoxOptions() {
  SyntheticBoxSceneOptions options;
  options.box_spacing_m = 0.04;
  options.ground_spacing_m = 0.1;
  options.noise_m = 0.001;
  return options;
}

class VisibilityIntegrationTest : public ::testing::Test {
 protected:
  VisibilityIntegrationTest()
      : scene_options(SparseBoxOptions()),
        scene(scene_options),
        input(MakeVisualMeshingInput(scene, scene.SampleVisualPoints())) {
    BuildMeshingTriangulation(DelaunayTriangulationOptions(), input,
                              &triangulation);
  }

  const SyntheticBoxSceneOptions scene_options;
  const SyntheticBoxScene scene;
  const MeshingInput input;
  MeshingTriangulation triangulation;
};

TEST_F(VisibilityIntegrationTest, CameraCellsOutsideBoxCellsInside) {
  VisibilityIntegrationOptions options;
  options.num_threads = 2;
  options.max_free_space_length_factor = 0;  // Whole rays.
  const CellGraphWeights weights =
      IntegrateVisibility(options, input, triangulation);
  EXPECT_EQ(weights.num_failed_walks, 0u);
  EXPECT_GT(weights.distance_sigma, 0.005);
  EXPECT_LT(weights.distance_sigma, 0.1);
  ASSERT_EQ(weights.facet_in.size(), 4 * triangulation.NumCells());
  // Total source and sink weight each equal the summed ray weights.
  double total_ray_weight = 0;
  for (size_t i = 0; i < input.NumPoints(); ++i) {
    total_ray_weight += input.ray_weights[i] * input.visibility[i].size();
  }
  const double total_source =
      std::accumulate(weights.source.begin(), weights.source.end(), 0.0);
  const double total_sink =
      std::accumulate(weights.sink.begin(), weights.sink.end(), 0.0);
  EXPECT_NEAR(total_source, total_ray_weight, 1e-3 * total_ray_weight);
  EXPECT_NEAR(total_sink, total_ray_weight, 1e-3 * total_ray_weight);
  // Cells whose centroid is inside the box get inside weight only; cells
  // crossed by free-space rays are in front of the surfaces.
  double inside_sink = 0, inside_source = 0, inside_free = 0;
  for (const MeshCellHandle& cell : triangulation.cells) {
    if (triangulation.delaunay.is_infinite(cell)) continue;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) centroid += ToEigen(cell->vertex(k)->point()) / 4;
    const bool in_box = (centroid.array() > scene_options.box_min.array() + 0.05).all() &&
                        (centroid.array() < scene_options.box_max.array() - 0.05).all();
    if (!in_box) continue;
    inside_sink += weights.sink[cell->info()];
    inside_source += weights.source[cell->info()];
    for (int k = 0; k < 4; ++k) {
      inside_free += weights.facet_in[4 * cell->info() + k];
    }
  }
  EXPECT_EQ(inside_source, 0.0);
  EXPECT_EQ(inside_free, 0.0);
  EXPECT_GT(inside_sink, 0.0);
  options.distance_sigma_factor = 0;
  EXPECT_FALSE(options.Check());
  options.distance_sigma_factor = 1;
  options.max_free_space_length_factor = -1;
  EXPECT_FALSE(options.Check());
}

// With a length cap, the outside weight of a ray lands where the carving
// stops in front of the point instead of where the ray reaches the sensor
// (3 m from the box, far beyond the cap); the totals are unchanged and less
// free space is carved.
TEST_F(VisibilityIntegrationTest, LengthCapMovesOutsideWeightNearTheSurface) {
  VisibilityIntegrationOptions options;
  options.num_threads = 2;
  options.max_free_space_length_factor = 0;
  const CellGraphWeights whole = IntegrateVisibility(options, input,
                                                     triangulation);
  options.max_free_space_length_factor = 5;
  const CellGraphWeights capped = IntegrateVisibility(options, input,
                                                      triangulation);
  EXPECT_EQ(capped.num_failed_walks, 0u);
  const double cap_m = 5 * capped.distance_sigma;
  ASSERT_LT(cap_m, 1.0);  // The cameras are >= 2 m from every point.

  // The cameras are above the convex hull of the box and the ground: whole
  // rays put all outside weight into infinite cells, capped rays from the
  // ground near the box stop inside the hull.
  auto finite_source = [&](const CellGraphWeights& weights) {
    double sum = 0;
    for (const MeshCellHandle& cell : triangulation.cells) {
      if (!triangulation.delaunay.is_infinite(cell)) {
        sum += weights.source[cell->info()];
      }
    }
    return sum;
  };
  EXPECT_EQ(finite_source(whole), 0.0);
  EXPECT_GT(finite_source(capped), 0.0);

  auto total = [](const std::vector<float>& values) {
    return std::accumulate(values.begin(), values.end(), 0.0);
  };
  EXPECT_NEAR(total(capped.source), total(whole.source),
              1e-4 * total(whole.source));
  EXPECT_NEAR(total(capped.sink), total(whole.sink), 1e-4 * total(whole.sink));
  EXPECT_LT(total(capped.facet_in), total(whole.facet_in));
}

// The weights are the same on one thread and on three (fixed-point sums,
// per-thread facet arrays), and sigma is the lower quartile of all finite
// edges (on a scene this small every edge is sampled).
TEST_F(VisibilityIntegrationTest, SameWeightsOnAnyThreadCountAndExactSigma) {
  VisibilityIntegrationOptions options;
  options.num_threads = 1;
  const CellGraphWeights one = IntegrateVisibility(options, input,
                                                   triangulation);
  options.num_threads = 3;
  const CellGraphWeights three = IntegrateVisibility(options, input,
                                                     triangulation);
  EXPECT_EQ(one.source, three.source);
  EXPECT_EQ(one.sink, three.sink);
  EXPECT_EQ(one.facet_in, three.facet_in);
  EXPECT_EQ(one.distance_sigma, three.distance_sigma);

  std::vector<double> lengths;
  const MeshDelaunay& delaunay = triangulation.delaunay;
  for (auto edge = delaunay.finite_edges_begin();
       edge != delaunay.finite_edges_end(); ++edge) {
    lengths.push_back(std::sqrt(CGAL::squared_distance(
        edge->first->vertex(edge->second)->point(),
        edge->first->vertex(edge->third)->point())));
  }
  ASSERT_LT(triangulation.NumVertices(), 150000u);
  auto quartile = lengths.begin() + lengths.size() / 4;
  std::nth_element(lengths.begin(), quartile, lengths.end());
  EXPECT_EQ(LowerQuartileEdgeLength(triangulation, 1), *quartile);
  EXPECT_EQ(LowerQuartileEdgeLength(triangulation, 2), *quartile);
}

}  // namespace
}  // namespace colmap_lidar
