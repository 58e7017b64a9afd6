#include "src/mesh/delaunay_triangulation.h"

#include <algorithm>
#include <set>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"
#include "src/mesh/synthetic_box_scene.h"

namespace colmap_lidar {
namespace {

TEST(DelaunayTriangulation, IndicesAndMergingByPixelDistance) {
  SyntheticBoxSceneOptions scene_options;
  scene_options.noise_m = 0.001;
  const SyntheticBoxScene scene(scene_options);
  const MeshingInput input =
      MakeVisualMeshingInput(scene, scene.SampleVisualPoints());
  DelaunayTriangulationOptions options;
  options.max_proj_dist_px = 0;
  MeshingTriangulation all;
  BuildMeshingTriangulation(options, input, &all);
  EXPECT_EQ(all.NumVertices(), input.NumPoints());
  EXPECT_TRUE(all.delaunay.is_valid());
  for (size_t i = 0; i < all.NumVertices(); ++i) {
    ASSERT_EQ(all.vertices[i]->info(), i);
  }
  // Cells numbered by their first (smallest) finite vertex, each once.
  uint32_t previous_first = 0;
  std::set<MeshCellHandle> distinct;
  for (size_t i = 0; i < all.NumCells(); ++i) {
    ASSERT_EQ(all.cells[i]->info(), i);
    uint32_t first = UINT32_MAX;
    for (int k = 0; k < 4; ++k) {
      if (!all.delaunay.is_infinite(all.cells[i]->vertex(k))) {
        first = std::min(first, all.cells[i]->vertex(k)->info());
      }
    }
    EXPECT_GE(first, previous_first);
    previous_first = first;
    distinct.insert(all.cells[i]);
  }
  EXPECT_EQ(all.NumCells(), all.delaunay.number_of_cells());
  EXPECT_EQ(distinct.size(), all.NumCells());

  options.max_proj_dist_px = 5;
  MeshingTriangulation merged;
  BuildMeshingTriangulation(options, input, &merged);
  EXPECT_LT(merged.NumVertices(), 0.8 * input.NumPoints());
  EXPECT_GT(merged.NumVertices(), 0.1 * input.NumPoints());
  // A merged point's vertex projects within 5 px in all its images.
  for (size_t i = 0; i < input.NumPoints(); i += 37) {
    const Eigen::Vector3d vertex =
        ToEigen(merged.vertices[merged.point_to_vertex[i]]->point());
    for (const uint32_t sensor : input.visibility[i]) {
      const Eigen::Matrix3x4d& proj = input.sensors[sensor].proj_matrix;
      const Eigen::Vector2d a = (proj * input.positions[i].homogeneous()).hnormalized();
      const Eigen::Vector2d b = (proj * vertex.homogeneous()).hnormalized();
      EXPECT_LE((a - b).norm(), 5.0 + 1e-9);
    }
  }
}

TEST(DelaunayTriangulation, LinesAreNeverMergedAndDegenerateInputThrows) {
  MeshingInput input;
  MeshingSensor sensor;
  sensor.position_in_world = Eigen::Vector3d(0, 0, 10);
  input.sensors.push_back(sensor);
  for (int i = 0; i < 5; ++i) {
    input.AddPoint(Eigen::Vector3d(i, 0, 0), MeshingPointSource::kLine, 1, {0});
  }
  MeshingTriangulation triangulation;
  // Collinear points span no volume.
  EXPECT_THROW(BuildMeshingTriangulation(DelaunayTriangulationOptions(), input,
                                         &triangulation),
               Error);
  input.AddPoint(Eigen::Vector3d(0, 1, 0), MeshingPointSource::kLine, 1, {0});
  input.AddPoint(Eigen::Vector3d(0, 0, 1), MeshingPointSource::kLine, 1, {0});
  // A LIDAR point 1 mm from a vertex merges at 1 cm.
  input.AddPoint(Eigen::Vector3d(0.3, 0.3, 0.301), MeshingPointSource::kLidar, 1, {0});
  input.AddPoint(Eigen::Vector3d(0.3, 0.3, 0.3), MeshingPointSource::kLine, 1, {0});
  DelaunayTriangulationOptions options;
  options.min_lidar_vertex_distance_m = 0.01;
  BuildMeshingTriangulation(options, input, &triangulation);
  EXPECT_EQ(triangulation.NumVertices(), input.NumPoints() - 1);
  EXPECT_EQ(triangulation.point_to_vertex[7], triangulation.point_to_vertex[8]);
  EXPECT_EQ(triangulation.vertex_sources[triangulation.point_to_vertex[8]],
            MeshingPointSource::kLine);
}

}  // namespace
}  // namespace colmap_lidar
