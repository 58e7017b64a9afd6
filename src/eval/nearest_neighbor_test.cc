#include "src/eval/nearest_neighbor.h"

#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

TEST(NearestNeighbor, PointTriangleDistanceRegions) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_DOUBLE_EQ(PointTriangleDistance({0.2, 0.2, 0.5}, a, b, c), 0.5);
  EXPECT_DOUBLE_EQ(PointTriangleDistance({-3, -4, 0}, a, b, c), 5.0);
  EXPECT_DOUBLE_EQ(PointTriangleDistance({0.5, -2, 0}, a, b, c), 2.0);
  EXPECT_NEAR(PointTriangleDistance({1, 1, 0}, a, b, c), std::sqrt(0.5),
              1e-15);
  EXPECT_DOUBLE_EQ(PointTriangleDistance({2, 0, 0}, a, b, c), 1.0);
  // Degenerate triangle: a segment.
  EXPECT_DOUBLE_EQ(PointTriangleDistance({0.5, 1, 0}, a, b, b), 1.0);
  EXPECT_DOUBLE_EQ(PointSegmentDistance({2, 1, 0}, a, b), std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(PointSegmentDistance({0.5, 1, 0}, a, b), 1.0);
  EXPECT_DOUBLE_EQ(PointSegmentDistance({3, 4, 0}, a, a), 5.0);
}

TEST(NearestNeighbor, KdTreeMatchesBruteForceFarFromTheOrigin) {
  std::mt19937 generator(1);
  std::uniform_real_distribution<double> uniform(0.0, 10.0);
  // UTM-like offset: float coordinates would lose the millimetres.
  const Eigen::Vector3d offset(500000.0, 5400000.0, 300.0);
  std::vector<Eigen::Vector3d> points, queries;
  for (int i = 0; i < 2000; ++i) {
    points.push_back(offset + Eigen::Vector3d(uniform(generator),
                                              uniform(generator),
                                              uniform(generator)));
  }
  for (int i = 0; i < 3000; ++i) {
    queries.push_back(offset + Eigen::Vector3d(uniform(generator),
                                               uniform(generator),
                                               uniform(generator)));
  }
  const PointCloudIndex index(points);
  const std::vector<double> distances = index.NearestDistances(queries);
  for (size_t q = 0; q < queries.size(); ++q) {
    double brute = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& p : points) {
      brute = std::min(brute, (p - queries[q]).norm());
    }
    EXPECT_NEAR(distances[q], brute, 1e-6) << q;
  }
  EXPECT_THROW(PointCloudIndex(std::vector<Eigen::Vector3d>()), Error);
}

TEST(NearestNeighbor, MeshDistanceMatchesBruteForce) {
  std::mt19937 generator(2);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const Eigen::Vector3d offset(1000.0, -2000.0, 50.0);
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  for (int i = 0; i < 300; ++i) {
    for (int k = 0; k < 3; ++k) {
      vertices.push_back(offset + Eigen::Vector3d(uniform(generator),
                                                  uniform(generator),
                                                  uniform(generator)));
    }
    triangles.emplace_back(3 * i, 3 * i + 1, 3 * i + 2);
  }
  std::vector<Eigen::Vector3d> queries;
  for (int i = 0; i < 2000; ++i) {
    queries.push_back(offset + 1.5 * Eigen::Vector3d(uniform(generator),
                                                     uniform(generator),
                                                     uniform(generator)));
  }
  const TriangleMeshIndex index(vertices, triangles);
  const std::vector<double> distances = index.NearestDistances(queries);
  for (size_t q = 0; q < queries.size(); ++q) {
    double brute = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3i& t : triangles) {
      brute = std::min(brute, PointTriangleDistance(queries[q], vertices[t[0]],
                                                    vertices[t[1]],
                                                    vertices[t[2]]));
    }
    EXPECT_NEAR(distances[q], brute, 1e-6) << q;
  }
  EXPECT_THROW(TriangleMeshIndex(vertices, {Eigen::Vector3i(0, 1, 900)}),
               Error);
}

}  // namespace
}  // namespace colmap_lidar
