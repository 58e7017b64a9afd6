#include "src/mesh/visibility_integration.h"

#include <numeric>

#include <gtest/gtest.h>

#include "src/mesh/synthetic_box_scene.h"

namespace colmap_lidar {
namespace {

TEST(VisibilityIntegration, CameraCellsOutsideBoxCellsInside) {
  SyntheticBoxSceneOptions scene_options;
  scene_options.box_spacing_m = 0.04;
  scene_options.ground_spacing_m = 0.1;
  scene_options.noise_m = 0.001;
  const SyntheticBoxScene scene(scene_options);
  const MeshingInput input =
      MakeVisualMeshingInput(scene, scene.SampleVisualPoints());
  MeshingTriangulation triangulation;
  BuildMeshingTriangulation(DelaunayTriangulationOptions(), input,
                            &triangulation);
  VisibilityIntegrationOptions options;
  options.num_threads = 2;
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
}

}  // namespace
}  // namespace colmap_lidar
