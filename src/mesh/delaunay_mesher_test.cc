#include "src/mesh/delaunay_mesher.h"

#include <algorithm>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/mvs/workspace.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"
#include "src/mesh/synthetic_box_scene.h"

namespace colmap_lidar {
namespace {

// Boundary and non-manifold edges whose midpoint lies near the box.
size_t NumOpenEdgesNearBox(const TriangleMesh& mesh) {
  const MeshEdgeStats stats = ComputeMeshEdgeStats(mesh);
  size_t count = 0;
  for (const auto* edges : {&stats.boundary_edges, &stats.non_manifold_edges}) {
    for (const auto& edge : *edges) {
      const Eigen::Vector3d middle =
          0.5 * (mesh.vertices[edge[0]] + mesh.vertices[edge[1]]);
      if (std::abs(middle.x()) < 1.2 && std::abs(middle.y()) < 1.0) {
        ++count;
        LOG(INFO) << (edges == &stats.boundary_edges ? "Boundary" : "Non-manifold")
                  << " edge at " << middle.transpose();
      }
    }
  }
  return count;
}

DelaunayMeshingOptions TestOptions() {
  DelaunayMeshingOptions options;
  options.num_threads = 2;
  return options;
}

// Free space carved along whole rays and with a short length cap (the cameras
// are 2-3 m from the box; 5 sigma is about 0.2 m): both give the box.
class BoxOnGround : public ::testing::TestWithParam<double> {};

TEST_P(BoxOnGround, IsAccurateClosedAndComplete) {
  SyntheticBoxSceneOptions scene_options;
  scene_options.noise_m = 0.001;
  const SyntheticBoxScene scene(scene_options);
  const SyntheticPoints points = scene.SampleVisualPoints();
  const MeshingInput input = MakeVisualMeshingInput(scene, points);
  DelaunayMeshingOptions options = TestOptions();
  options.max_free_space_length_factor = GetParam();
  DelaunayMeshingSummary summary;
  const TriangleMesh mesh = DelaunayMeshing(options, input, &summary);
  ASSERT_GT(mesh.faces.size(), 1000u);
  EXPECT_EQ(summary.num_failed_walks, 0u);
  const std::vector<double> distances = FaceDistancesToSurface(scene, mesh);
  const double p50 = Percentile(distances, 50);
  const double p95 = Percentile(distances, 95);
  const double p99 = Percentile(distances, 99);
  LOG(INFO) << "Face distances: median " << p50 << " p95 " << p95 << " p99 "
            << p99 << " max " << Percentile(distances, 100);
  EXPECT_LT(p50, 0.002);
  EXPECT_LT(p95, 0.005);
  double max_vertex_distance = 0;
  for (const Eigen::Vector3d& vertex : mesh.vertices) {
    max_vertex_distance =
        std::max(max_vertex_distance, scene.DistanceToSurface(vertex));
  }
  EXPECT_LT(max_vertex_distance, 0.006);
  const double coverage = SurfaceCoverage(scene, mesh, 0.01);
  LOG(INFO) << "Coverage at 1 cm: " << coverage;
  EXPECT_GT(coverage, 0.95);
  EXPECT_EQ(NumOpenEdgesNearBox(mesh), 0u);
  // Orientation: faces near the box top point up, faces on the +x side +x.
  int num_up = 0, num_top = 0, num_out = 0, num_side = 0;
  for (size_t i = 0; i < mesh.faces.size(); ++i) {
    const Eigen::Vector3d centroid =
        (mesh.vertices[mesh.faces[i][0]] + mesh.vertices[mesh.faces[i][1]] +
         mesh.vertices[mesh.faces[i][2]]) / 3;
    const Eigen::Vector3d normal = mesh.FaceNormal(i);
    if (std::abs(centroid.z() - 0.8) < 0.003 && std::abs(centroid.x()) < 0.5 &&
        std::abs(centroid.y()) < 0.3) {
      ++num_top;
      num_up += normal.z() > 0.9 ? 1 : 0;
    }
    if (std::abs(centroid.x() - 0.6) < 0.003 && std::abs(centroid.y()) < 0.3 &&
        centroid.z() > 0.1 && centroid.z() < 0.7) {
      ++num_side;
      num_out += normal.x() > 0.9 ? 1 : 0;
    }
  }
  EXPECT_GT(num_top, 100);
  EXPECT_GT(num_side, 100);
  EXPECT_GE(num_up, 0.98 * num_top);
  EXPECT_GE(num_out, 0.98 * num_side);

  // Faces in canonical order (each from its smallest vertex, sorted), so
  // that a run with threads gives the same file as any other.
  EXPECT_TRUE(std::is_sorted(mesh.faces.begin(), mesh.faces.end()));
  for (const std::array<uint32_t, 3>& face : mesh.faces) {
    ASSERT_LT(face[0], face[1]);
    ASSERT_LT(face[0], face[2]);
  }
  // A second run (2 threads, as the first).
  const TriangleMesh again = DelaunayMeshing(options, input);
  EXPECT_EQ(again.faces, mesh.faces);
  EXPECT_EQ(again.vertices, mesh.vertices);
}

INSTANTIATE_TEST_SUITE_P(FreeSpaceLength, BoxOnGround,
                         ::testing::Values(0.0, 5.0));

TEST(DelaunayMesher, FreeSpaceCarvingRemovesOutliers) {
  SyntheticBoxSceneOptions scene_options;
  scene_options.noise_m = 0.001;
  const SyntheticBoxScene scene(scene_options);
  SyntheticPoints points = scene.SampleVisualPoints();
  // Outliers floating in front of the surfaces, each seen by two cameras.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Vector3d> outliers;
  while (outliers.size() < 300) {
    const Eigen::Vector3d point(2.0 * uniform(rng), 2.0 * uniform(rng),
                                0.75 + 0.6 * uniform(rng));
    if (scene.DistanceToSurface(point) < 0.1) continue;
    std::vector<uint32_t> cameras;
    for (uint32_t i = 0; i < scene.Model().images.size(); ++i) {
      const Eigen::Vector3d center =
          scene.Model().images[i].ProjectionCenter();
      if (!scene.SegmentHitsBox(center, point) && rng() % 3 == 0) {
        cameras.push_back(i);
      }
      if (cameras.size() == 2) break;
    }
    if (cameras.size() < 2) continue;
    outliers.push_back(point);
    points.positions.push_back(point);
    points.normals.push_back(Eigen::Vector3d::UnitZ());
    points.visibility.push_back(cameras);
  }
  const MeshingInput input = MakeVisualMeshingInput(scene, points);
  const TriangleMesh mesh = DelaunayMeshing(TestOptions(), input);
  ASSERT_GT(mesh.faces.size(), 1000u);
  size_t num_outliers_in_mesh = 0;
  for (const Eigen::Vector3d& vertex : mesh.vertices) {
    if (scene.DistanceToSurface(vertex) > 0.05) ++num_outliers_in_mesh;
  }
  EXPECT_EQ(num_outliers_in_mesh, 0u);
  EXPECT_LT(Percentile(FaceDistancesToSurface(scene, mesh), 95), 0.005);
  EXPECT_GT(SurfaceCoverage(scene, mesh, 0.01), 0.95);
}

TEST(DelaunayMesher, LidarOnlyInputGivesTheSurface) {
  SyntheticBoxSceneOptions scene_options;
  const SyntheticBoxScene scene(scene_options);
  const SyntheticBoxScene::LidarVoxels lidar = scene.SimulateLidar(
      scene_options.num_cameras, /*angular_step_deg=*/1.0,
      /*voxel_size_m=*/0.03, /*range_noise_m=*/0.003);
  MeshingInput input;
  AddCameraSensors(scene.Model(), &input);
  std::vector<Eigen::Vector3d> origins;
  for (int i = 0; i < scene_options.num_cameras; ++i) {
    origins.push_back(scene.LidarOrigin(i));
  }
  AddLidarPoints(MeshingInputOptions(), lidar.positions, lidar.counts,
                 lidar.frames, origins,
                 std::vector<bool>(origins.size(), true), "test", &input);
  ASSERT_EQ(input.NumPoints(MeshingPointSource::kVisual), 0u);
  ASSERT_GT(input.NumPoints(MeshingPointSource::kLidar), 5000u);
  const TriangleMesh mesh = DelaunayMeshing(TestOptions(), input);
  ASSERT_GT(mesh.faces.size(), 1000u);
  const std::vector<double> distances = FaceDistancesToSurface(scene, mesh);
  LOG(INFO) << "LIDAR-only face distances: median "
            << Percentile(distances, 50) << " p95 "
            << Percentile(distances, 95);
  EXPECT_LT(Percentile(distances, 50), 0.005);
  EXPECT_LT(Percentile(distances, 95), 0.015);
  // The box is seen by the scanners from all sides.
  const double coverage = SurfaceCoverage(scene, mesh, 0.02);
  LOG(INFO) << "LIDAR-only coverage at 2 cm: " << coverage;
  EXPECT_GT(coverage, 0.9);
  EXPECT_EQ(NumOpenEdgesNearBox(mesh), 0u);
}

// Mean distance of samples on the visible top edges of the box to the mesh.
double TopEdgeDistance(const SyntheticBoxScene& scene,
                       const TriangleMesh& mesh) {
  const MeshDistance distance(mesh);
  double sum = 0;
  int count = 0;
  for (const Line3D& line : scene.BoxEdgeLines()) {
    if (line.start_in_world.z() < 0.5 || line.end_in_world.z() < 0.5) {
      continue;
    }
    for (int k = 1; k < 20; ++k) {
      const Eigen::Vector3d point =
          line.start_in_world +
          k / 20.0 * (line.end_in_world - line.start_in_world);
      sum += distance.Distance(point);
      ++count;
    }
  }
  return sum / std::max(count, 1);
}

TEST(DelaunayMesher, LineSamplesSharpenTheBoxEdges) {
  SyntheticBoxSceneOptions scene_options;
  scene_options.box_spacing_m = 0.05;
  scene_options.noise_m = 0.001;
  const SyntheticBoxScene scene(scene_options);
  const SyntheticPoints points = scene.SampleVisualPoints();
  const MeshingInput visual_input = MakeVisualMeshingInput(scene, points);
  const TriangleMesh visual_mesh =
      DelaunayMeshing(TestOptions(), visual_input);

  MeshingInput line_input = visual_input;
  Reconstruction lines_model;
  line3D_t line3D_id = 1;
  for (const Line3D& line : scene.BoxEdgeLines()) {
    lines_model.lines3D[line3D_id++] = line;
  }
  ASSERT_GE(lines_model.lines3D.size(), 8u);
  AddLineSamples(MeshingInputOptions(), scene.Model(), lines_model,
                 /*observations=*/nullptr, &line_input);
  ASSERT_GT(line_input.NumPoints(MeshingPointSource::kLine), 100u);
  const TriangleMesh line_mesh = DelaunayMeshing(TestOptions(), line_input);

  const double visual_distance = TopEdgeDistance(scene, visual_mesh);
  const double line_distance = TopEdgeDistance(scene, line_mesh);
  LOG(INFO) << "Mean top-edge distance: " << visual_distance
            << " m without lines, " << line_distance << " m with lines";
  EXPECT_GT(visual_distance, 0.004);
  EXPECT_LT(line_distance, 0.5 * visual_distance);
  EXPECT_LT(line_distance, 0.002);
  EXPECT_LT(Percentile(FaceDistancesToSurface(scene, line_mesh), 95), 0.01);
}

// Distances to the true surface of the mesh's vertices within `radius` of
// a box edge (orthogonally, within the edge's extent).
std::vector<double> NearEdgeVertexDistances(const SyntheticBoxScene& scene,
                                            const TriangleMesh& mesh,
                                            double radius) {
  std::vector<double> distances;
  for (const Eigen::Vector3d& vertex : mesh.vertices) {
    for (const Line3D& line : scene.BoxEdgeLines()) {
      const Eigen::Vector3d axis = line.end_in_world - line.start_in_world;
      const double t =
          (vertex - line.start_in_world).dot(axis) / axis.squaredNorm();
      if (t < 0 || t > 1) continue;
      if ((line.start_in_world + t * axis - vertex).norm() <= radius) {
        distances.push_back(scene.DistanceToSurface(vertex));
        break;
      }
    }
  }
  return distances;
}

TEST(DelaunayMesher, CreaseSnappingPutsTheVerticesAtTheEdgesOnTheFaces) {
  // 1 cm of noise on the points: the line validation fits the box's faces
  // at each edge, and the vertices around it move onto them.
  SyntheticBoxSceneOptions scene_options;
  scene_options.box_spacing_m = 0.03;
  scene_options.noise_m = 0.01;
  const SyntheticBoxScene scene(scene_options);
  MeshingInput input =
      MakeVisualMeshingInput(scene, scene.SampleVisualPoints());
  Reconstruction lines_model;
  line3D_t line3D_id = 1;
  for (const Line3D& line : scene.BoxEdgeLines()) {
    lines_model.lines3D[line3D_id++] = line;
  }
  AddLineSamples(MeshingInputOptions(), scene.Model(), lines_model,
                 /*observations=*/nullptr, &input);
  ASSERT_GE(input.creases.size(), 4u);
  ASSERT_GT(input.crease_spacing_m, 0);

  DelaunayMeshingOptions options = TestOptions();
  options.snap_to_creases = false;
  const TriangleMesh plain = DelaunayMeshing(options, input);
  options.snap_to_creases = true;
  DelaunayMeshingSummary summary;
  const TriangleMesh snapped = DelaunayMeshing(options, input, &summary);
  EXPECT_EQ(summary.crease_snapping.num_creases, input.creases.size());
  EXPECT_GT(summary.crease_snapping.num_vertices_moved, 50u);
  // Same faces; only vertices near the creases moved.
  ASSERT_EQ(snapped.faces, plain.faces);
  const double radius = options.crease_snapping.radius_factor *
                        input.crease_spacing_m;
  size_t num_moved = 0;
  for (size_t v = 0; v < plain.vertices.size(); ++v) {
    if (snapped.vertices[v] == plain.vertices[v]) continue;
    ++num_moved;
    EXPECT_LE((snapped.vertices[v] - plain.vertices[v]).norm(),
              options.crease_snapping.max_move_factor *
                      input.crease_spacing_m + 1e-9);
  }
  EXPECT_EQ(num_moved, summary.crease_snapping.num_vertices_moved);
  const std::vector<double> before =
      NearEdgeVertexDistances(scene, plain, radius);
  const std::vector<double> after =
      NearEdgeVertexDistances(scene, snapped, radius);
  LOG(INFO) << "Vertices near the box edges: " << before.size()
            << ", distance to the surface median " << Percentile(before, 50)
            << " -> " << Percentile(after, 50) << " m, p90 "
            << Percentile(before, 90) << " -> " << Percentile(after, 90);
  ASSERT_GT(before.size(), 50u);
  EXPECT_LT(Percentile(after, 50), 0.5 * Percentile(before, 50));
  EXPECT_LT(Percentile(after, 90), Percentile(before, 90));
}

TEST(DelaunayMesher, WorkspaceWithLidarToPly) {
  SyntheticBoxSceneOptions scene_options;
  scene_options.box_spacing_m = 0.04;
  scene_options.ground_spacing_m = 0.1;
  scene_options.noise_m = 0.001;
  const SyntheticBoxScene scene(scene_options);
  const SyntheticPoints points = scene.SampleVisualPoints();
  const SyntheticBoxScene::LidarVoxels lidar =
      scene.SimulateLidar(4, 1.0, 0.03, 0.003);
  const std::string workspace = testing::CreateTestDir();
  scene.WriteWorkspace(workspace, points, &lidar);
  const std::string output_path = JoinPaths(workspace, "meshed-lidar.ply");
  const DelaunayMeshingSummary summary =
      MeshDenseWorkspace(TestOptions(), MeshingInputOptions(), workspace, "",
                         output_path);
  EXPECT_EQ(summary.num_input_points,
            points.positions.size() + lidar.positions.size());
  EXPECT_GT(summary.peak_memory_bytes, 0u);
  // Read back with the generic PLY reader: triangles with valid indices.
  const PlyData ply = ReadPly(output_path);
  ASSERT_GT(ply.faces.size(), 1000u);
  EXPECT_EQ(ply.faces.size(), summary.num_faces);
  EXPECT_EQ(ply.NumVertices(), summary.num_mesh_vertices);
  for (const auto& face : ply.faces) {
    ASSERT_EQ(face.size(), 3u);
    for (const uint32_t idx : face) ASSERT_LT(idx, ply.NumVertices());
  }
  const TriangleMesh mesh = ReadMeshPly(output_path);
  EXPECT_LT(Percentile(FaceDistancesToSurface(scene, mesh), 95), 0.01);
  // Also readable as a point cloud (the fused.ply reader of colmap_ext).
  EXPECT_EQ(ReadPlyPoints(output_path).size(), mesh.vertices.size());
}

TEST(DelaunayMesher, MemoryGuardDecimates) {
  SyntheticBoxSceneOptions scene_options;
  scene_options.noise_m = 0.001;
  const SyntheticBoxScene scene(scene_options);
  const MeshingInput input =
      MakeVisualMeshingInput(scene, scene.SampleVisualPoints());
  DelaunayMeshingOptions options = TestOptions();
  // Room for about 5000 points.
  options.max_memory_gb = 5000 * kEstimatedBytesPerPoint / (1ull << 30);
  DelaunayMeshingSummary summary;
  const TriangleMesh mesh = DelaunayMeshing(options, input, &summary);
  EXPECT_GT(summary.decimation_voxel_size_m, 0);
  EXPECT_LE(summary.num_vertices, 5000u);
  EXPECT_GT(mesh.faces.size(), 1000u);
  EXPECT_LT(Percentile(FaceDistancesToSurface(scene, mesh), 95), 0.01);
}

TEST(DelaunayMesher, RejectsBadOptionsAndTinyInput) {
  DelaunayMeshingOptions options;
  options.max_depth_dist = 2;
  EXPECT_FALSE(options.Check());
  options = DelaunayMeshingOptions();
  options.max_memory_gb = 0;
  EXPECT_FALSE(options.Check());
  options.max_memory_gb = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(options.Check());
  MeshingInput input;
  input.sensors.emplace_back();
  input.AddPoint(Eigen::Vector3d::Zero(), MeshingPointSource::kVisual, 1, {0});
  EXPECT_THROW(DelaunayMeshing(DelaunayMeshingOptions(), input), Error);
}

}  // namespace
}  // namespace colmap_lidar
