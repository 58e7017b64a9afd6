#include "src/eval/mesh_sampling.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

TEST(MeshSampling, TriangulatesPolygonsAsFans) {
  const std::vector<Eigen::Vector3i> triangles =
      TriangulatePolygons({{0, 1, 2, 3, 4}, {1, 2}, {4, 3, 2}}, 5);
  ASSERT_EQ(triangles.size(), 4u);
  EXPECT_EQ(triangles[0], Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(triangles[2], Eigen::Vector3i(0, 3, 4));
  EXPECT_EQ(triangles[3], Eigen::Vector3i(4, 3, 2));
  EXPECT_THROW(TriangulatePolygons({{0, 1, 5}}, 5, "m.ply"), Error);
}

// Two triangles of areas 2 and 0.5: the sample count follows the area, the
// split between them the area ratio, and the samples lie inside.
TEST(MeshSampling, AreaWeightedAndDeterministic) {
  const std::vector<Eigen::Vector3d> vertices = {
      {0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {5, 0, 1}, {6, 0, 1}, {5, 1, 1}};
  const std::vector<Eigen::Vector3i> triangles = {{0, 1, 2}, {3, 4, 5}};
  EXPECT_DOUBLE_EQ(TriangleMeshArea(vertices, triangles), 2.5);
  const std::vector<Eigen::Vector3d> samples =
      SampleTriangleMesh(vertices, triangles, 4000, 7);
  ASSERT_EQ(samples.size(), 10000u);
  int in_small = 0;
  for (const Eigen::Vector3d& p : samples) {
    if (p.x() > 4.0) {
      ++in_small;
      EXPECT_NEAR(p.z(), 1.0, 1e-12);
      EXPECT_GE(p.x(), 5.0);
      EXPECT_GE(p.y(), 0.0);
      EXPECT_LE(p.x() - 5.0 + p.y(), 1.0 + 1e-12);
    } else {
      EXPECT_EQ(p.z(), 0.0);  // Exact: all three vertices have z = 0.
      EXPECT_GE(p.x(), 0.0);
      EXPECT_GE(p.y(), 0.0);
      EXPECT_LE(p.x() + p.y(), 2.0 + 1e-12);
    }
  }
  EXPECT_NEAR(in_small / 10000.0, 0.2, 0.02);
  // Uniform inside a triangle: the mean is the centroid.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  int count = 0;
  for (const Eigen::Vector3d& p : samples) {
    if (p.x() < 4.0) {
      mean += p;
      ++count;
    }
  }
  EXPECT_NEAR(mean.x() / count, 2.0 / 3.0, 0.02);
  EXPECT_NEAR(mean.y() / count, 2.0 / 3.0, 0.02);
  EXPECT_EQ(SampleTriangleMesh(vertices, triangles, 4000, 7), samples);
  EXPECT_NE(SampleTriangleMesh(vertices, triangles, 4000, 8), samples);
  // Zero area: no samples.
  EXPECT_TRUE(SampleTriangleMesh(vertices, {{0, 0, 1}}, 100, 1).empty());
}

}  // namespace
}  // namespace colmap_lidar
