#include "src/mesh/triangle_mesh.h"

#include <limits>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

// A closed tetrahedron (outward faces) plus, far away, one loose triangle.
TriangleMesh TetrahedronAndTriangle() {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1},
                   {10, 0, 0}, {11, 0, 0}, {10, 1, 0}};
  mesh.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {4, 5, 6}};
  return mesh;
}

TEST(TriangleMesh, EdgeStatsAndNormals) {
  const TriangleMesh mesh = TetrahedronAndTriangle();
  const MeshEdgeStats stats = ComputeMeshEdgeStats(mesh);
  EXPECT_EQ(stats.num_edges, 9u);
  EXPECT_EQ(stats.boundary_edges.size(), 3u);
  EXPECT_TRUE(stats.non_manifold_edges.empty());
  EXPECT_TRUE(mesh.FaceNormal(0).isApprox(Eigen::Vector3d(0, 0, -1)));
  EXPECT_GT(mesh.FaceNormal(3).dot(Eigen::Vector3d(1, 1, 1)), 0);
}

TEST(TriangleMesh, RemoveNonFiniteFaces) {
  TriangleMesh mesh = TetrahedronAndTriangle();
  mesh.vertices[3].z() = std::numeric_limits<double>::quiet_NaN();
  mesh.vertices[6].x() = std::numeric_limits<double>::infinity();
  // Faces 1, 2, 3 use vertex 3, face 4 uses vertex 6.
  EXPECT_EQ(RemoveNonFiniteFaces(&mesh), 4u);
  ASSERT_EQ(mesh.faces.size(), 1u);
  EXPECT_EQ(mesh.vertices.size(), 3u);
  for (const Eigen::Vector3d& vertex : mesh.vertices) {
    EXPECT_TRUE(vertex.allFinite());
  }
  EXPECT_TRUE(mesh.FaceNormal(0).isApprox(Eigen::Vector3d(0, 0, -1)));
  EXPECT_EQ(RemoveNonFiniteFaces(&mesh), 0u);
}

TEST(TriangleMesh, CleanupRemovesSmallComponentsAndLongEdges) {
  TriangleMesh mesh = TetrahedronAndTriangle();
  MeshCleanupOptions options;
  options.max_edge_length_factor = 0;
  options.min_component_faces = 2;
  MeshCleanupSummary summary = CleanupMesh(options, &mesh);
  EXPECT_EQ(summary.num_small_component_faces_removed, 1u);
  EXPECT_EQ(summary.num_components_removed, 1u);
  EXPECT_EQ(mesh.faces.size(), 4u);
  EXPECT_EQ(mesh.vertices.size(), 4u);

  mesh = TetrahedronAndTriangle();
  mesh.vertices[3] = Eigen::Vector3d(0, 0, 50);  // Three faces get long.
  options.max_edge_length_factor = 5;
  options.min_component_faces = 0;
  summary = CleanupMesh(options, &mesh);
  EXPECT_EQ(summary.num_long_edge_faces_removed, 3u);
  EXPECT_EQ(mesh.faces.size(), 2u);
  EXPECT_EQ(mesh.vertices.size(), 6u);
  mesh.CheckIndices();

  options.min_component_faces = -1;
  EXPECT_FALSE(options.Check());
}

TEST(TriangleMesh, PlyRoundTripAndErrors) {
  const TriangleMesh mesh = TetrahedronAndTriangle();
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "mesh.ply");
  WriteMeshPly(path, mesh);
  const std::string header = ReadTextFile(path).substr(0, 300);
  EXPECT_NE(header.find("element face 5"), std::string::npos);
  EXPECT_NE(header.find("property list uchar int vertex_indices"),
            std::string::npos);
  const TriangleMesh read = ReadMeshPly(path);
  ASSERT_EQ(read.vertices.size(), mesh.vertices.size());
  EXPECT_EQ(read.faces, mesh.faces);
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    EXPECT_TRUE(read.vertices[i].isApprox(mesh.vertices[i]));
  }

  TriangleMesh bad = mesh;
  bad.faces.push_back({0, 1, 99});
  EXPECT_THROW(WriteMeshPly(path, bad), Error);
  PlyData quads;
  quads.AddColumn("x", PlyScalarType::kFloat32, {0, 1, 1, 0});
  quads.AddColumn("y", PlyScalarType::kFloat32, {0, 0, 1, 1});
  quads.AddColumn("z", PlyScalarType::kFloat32, {0, 0, 0, 0});
  quads.faces = {{0, 1, 2, 3}};
  const std::string quad_path = JoinPaths(dir, "quad.ply");
  WritePly(quad_path, quads);
  try {
    ReadMeshPly(quad_path);
    FAIL() << "no throw";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("quad.ply"), std::string::npos);
  }
  EXPECT_THROW(ReadMeshPly(JoinPaths(dir, "missing.ply")), Error);
}

}  // namespace
}  // namespace colmap_lidar
