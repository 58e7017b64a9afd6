#include "src/eval/mesh_sampling.h"

#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"

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
  // More samples than fit in memory (a density in points per mm^2): an error.
  EXPECT_THROW(SampleTriangleMesh(vertices, triangles, 1e9, 7), Error);
}

// Two meshes that share a triangle and differ in another: the shared
// triangle gets the same points in both (whatever its index), so an A/B of
// the two compares the changed region only; the expected count holds for
// fractional areas too.
TEST(MeshSampling, SharedTrianglesGetTheSamePoints) {
  const std::vector<Eigen::Vector3d> vertices = {
      {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 1}, {6, 0, 1}, {5, 1, 1}};
  std::vector<Eigen::Vector3d> moved = vertices;
  moved[5] = Eigen::Vector3d(5, 3, 1);  // the second triangle grows
  const std::vector<Eigen::Vector3d> a =
      SampleTriangleMesh(vertices, {{0, 1, 2}, {3, 4, 5}}, 1000, 3);
  // The shared triangle listed second in the other mesh.
  const std::vector<Eigen::Vector3d> b =
      SampleTriangleMesh(moved, {{3, 4, 5}, {0, 1, 2}}, 1000, 3);
  const auto in_first = [](const std::vector<Eigen::Vector3d>& samples) {
    std::vector<Eigen::Vector3d> out;
    for (const Eigen::Vector3d& p : samples) {
      if (p.z() == 0.0) out.push_back(p);
    }
    return out;
  };
  ASSERT_EQ(in_first(a).size(), 500u);
  EXPECT_EQ(in_first(a), in_first(b));
  EXPECT_EQ(a.size() - 500, 500u);
  EXPECT_EQ(b.size() - 500, 1500u);
  // 0.3 expected samples per triangle over many triangles: the count
  // follows the area (a strip of 2000 triangles of 0.5 mm^2 at 0.6 / mm^2).
  std::vector<Eigen::Vector3d> strip;
  std::vector<Eigen::Vector3i> strip_triangles;
  for (int i = 0; i < 2000; ++i) {
    const double x = 0.001 * i;
    strip.emplace_back(x, 0, 0);
    strip.emplace_back(x + 0.001, 0, 0);
    strip.emplace_back(x, 0.001, 0);
    strip_triangles.emplace_back(3 * i, 3 * i + 1, 3 * i + 2);
  }
  const size_t count =
      SampleTriangleMesh(strip, strip_triangles, 6e5, 5).size();
  EXPECT_NEAR(static_cast<double>(count), 600.0, 75.0);  // 3.5 sigma
  // Far below one sample per mesh: still one.
  EXPECT_EQ(SampleTriangleMesh(vertices, {{0, 1, 2}}, 1e-6, 1).size(), 1u);
}

// Many small triangles, each rounding its share of samples at random: the
// samples fit the array reserved up front (a reallocation would double it).
TEST(MeshSampling, SamplesFitTheirReservation) {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  for (int i = 0; i < 200; ++i) {
    for (int j = 0; j < 200; ++j) {
      const int base = static_cast<int>(vertices.size());
      vertices.emplace_back(0.1 * i, 0.1 * j, 0.0);
      vertices.emplace_back(0.1 * i + 0.1, 0.1 * j, 0.0);
      vertices.emplace_back(0.1 * i, 0.1 * j + 0.1, 0.0);
      triangles.emplace_back(base, base + 1, base + 2);
    }
  }
  // 0.005 m2 per triangle at 1100 per m2: 5.5 samples each.
  for (uint64_t seed = 0; seed < 4; ++seed) {
    const std::vector<Eigen::Vector3d> samples =
        SampleTriangleMesh(vertices, triangles, 1100.0, seed);
    EXPECT_NEAR(static_cast<double>(samples.size()), 220000.0, 2000.0);
    EXPECT_LT(static_cast<double>(samples.capacity()),
              1.01 * static_cast<double>(samples.size()));
  }
}

// The message of the colmap_lidar::Error that `function` throws; "" when
// it throws none.
template <typename Function>
std::string ErrorOf(const Function& function) {
  try {
    function();
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(MeshSampling, ReadsMeshesAndNamesBadFiles) {
  const std::string dir = testing::CreateTestDir();
  PlyData quad;
  quad.AddColumn("x", PlyScalarType::kFloat32, {0, 1, 1, 0});
  quad.AddColumn("y", PlyScalarType::kFloat32, {0, 0, 1, 1});
  quad.AddColumn("z", PlyScalarType::kFloat32, {0, 0, 0, 0});
  quad.faces = {{0, 1, 2, 3}};
  const std::string mesh_path = JoinPaths(dir, "quad.ply");
  WritePly(mesh_path, quad);
  const EvaluationMesh mesh = ReadEvaluationMesh(mesh_path, "Estimate");
  EXPECT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.triangles.size(), 2u);
  EXPECT_TRUE(mesh.has_faces);
  EXPECT_EQ(mesh.vertices[2], Eigen::Vector3d(1, 1, 0));

  quad.faces.clear();
  const std::string cloud_path = JoinPaths(dir, "cloud.ply");
  WritePly(cloud_path, quad);
  const EvaluationMesh cloud = ReadEvaluationMesh(cloud_path, "Estimate");
  EXPECT_FALSE(cloud.has_faces);
  EXPECT_TRUE(cloud.triangles.empty());

  quad.FindColumn("z")->values[3] = std::nan("");
  const std::string nan_path = JoinPaths(dir, "nan.ply");
  WritePly(nan_path, quad);
  const std::string nan_error =
      ErrorOf([&] { ReadEvaluationMesh(nan_path, "Estimate"); });
  for (const std::string& part : {nan_path, std::string("vertex 3"),
                                  std::string("non-finite")}) {
    EXPECT_THAT(nan_error, ::testing::HasSubstr(part));
  }
  PlyData empty;
  empty.AddColumn("x", PlyScalarType::kFloat32, {});
  const std::string empty_path = JoinPaths(dir, "empty.ply");
  WritePly(empty_path, empty);
  const std::string empty_error =
      ErrorOf([&] { ReadEvaluationMesh(empty_path, "Reference"); });
  EXPECT_THAT(empty_error, ::testing::HasSubstr("Reference " + empty_path +
                                                " has no vertices"));
  EXPECT_THAT(ErrorOf([&] {
                ReadEvaluationMesh(JoinPaths(dir, "missing.ply"), "Estimate");
              }),
              ::testing::HasSubstr("missing.ply"));
}

}  // namespace
}  // namespace colmap_lidar
