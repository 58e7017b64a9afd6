#include "src/eval/mesh_sampling.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include <Eigen/Geometry>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"

namespace colmap_lidar {

std::vector<Eigen::Vector3i> TriangulatePolygons(
    const std::vector<std::vector<uint32_t>>& polygons, size_t num_vertices,
    const std::string& path_for_errors) {
  std::vector<Eigen::Vector3i> triangles;
  triangles.reserve(polygons.size());
  for (size_t f = 0; f < polygons.size(); ++f) {
    const std::vector<uint32_t>& polygon = polygons[f];
    for (const uint32_t index : polygon) {
      THROW_CHECK(index < num_vertices,
                  "Face " << f << " of " << path_for_errors
                          << " refers to vertex " << index << " but there are "
                          << num_vertices << " vertices");
    }
    for (size_t k = 2; k < polygon.size(); ++k) {
      triangles.emplace_back(polygon[0], polygon[k - 1], polygon[k]);
    }
  }
  return triangles;
}

namespace {

double TriangleArea(const std::vector<Eigen::Vector3d>& vertices,
                    const Eigen::Vector3i& triangle) {
  return 0.5 * (vertices[triangle[1]] - vertices[triangle[0]])
                   .cross(vertices[triangle[2]] - vertices[triangle[0]])
                   .norm();
}

// More samples than fit in memory (24 bytes each): a unit error in the
// density or a mesh far larger than a scene.
constexpr double kMaxSamples = 1e9;

// The seed of a triangle's samples: the sampling seed and the bits of its
// three vertices' coordinates (in order), mixed by SplitMix64.
uint64_t TriangleSeed(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                      const Eigen::Vector3d& c, uint64_t seed) {
  const auto mix = [](uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
  };
  uint64_t state = mix(seed);
  for (const Eigen::Vector3d* vertex : {&a, &b, &c}) {
    for (int k = 0; k < 3; ++k) {
      uint64_t bits = 0;
      const double value = (*vertex)[k];
      std::memcpy(&bits, &value, sizeof(bits));
      state = mix(state ^ bits);
    }
  }
  return state;
}

}  // namespace

EvaluationMesh ReadEvaluationMesh(const std::string& path,
                                  const std::string& what) {
  CheckFileExists(path, what);
  EvaluationMesh mesh;
  {
    const PlyData data = ReadPly(path);
    THROW_CHECK(data.NumVertices() > 0,
                what << " " << path << " has no vertices");
    mesh.vertices = data.Positions(path);
    mesh.triangles =
        TriangulatePolygons(data.faces, mesh.vertices.size(), path);
    mesh.has_faces = !data.faces.empty();
  }
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    THROW_CHECK(mesh.vertices[i].allFinite(),
                what << " " << path << ": vertex " << i
                     << " has a non-finite coordinate");
  }
  return mesh;
}

double TriangleMeshArea(const std::vector<Eigen::Vector3d>& vertices,
                        const std::vector<Eigen::Vector3i>& triangles) {
  double area = 0.0;
  for (const Eigen::Vector3i& triangle : triangles) {
    area += TriangleArea(vertices, triangle);
  }
  return area;
}

std::vector<Eigen::Vector3d> SampleTriangleMesh(
    const std::vector<Eigen::Vector3d>& vertices,
    const std::vector<Eigen::Vector3i>& triangles, double density_per_m2,
    uint64_t seed) {
  THROW_CHECK(density_per_m2 > 0.0,
              "SampleTriangleMesh: density must be positive, got "
                  << density_per_m2);
  std::vector<Eigen::Vector3d> samples;
  const double expected_total =
      TriangleMeshArea(vertices, triangles) * density_per_m2;
  THROW_CHECK(!(expected_total > kMaxSamples),
              "SampleTriangleMesh: " << expected_total
                  << " samples asked (area x density); at most "
                  << kMaxSamples);
  if (expected_total > 0) {
    // Each triangle rounds its share up or down at random: the total
    // exceeds its expectation by a sum of triangles.size() terms of at most
    // 1/2 standard deviation each. Eight of the sum's standard deviations
    // of headroom, so that the array is not reallocated (and doubled) half
    // of the time.
    const double headroom =
        4.0 * std::sqrt(static_cast<double>(triangles.size())) + 1.0;
    samples.reserve(static_cast<size_t>(expected_total + headroom));
  }
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  size_t largest = triangles.size();
  double largest_area = 0.0;
  for (size_t t = 0; t < triangles.size(); ++t) {
    const Eigen::Vector3d& a = vertices[triangles[t][0]];
    const Eigen::Vector3d& b = vertices[triangles[t][1]];
    const Eigen::Vector3d& c = vertices[triangles[t][2]];
    const double area = TriangleArea(vertices, triangles[t]);
    if (!(area > 0.0)) continue;
    if (area > largest_area) {
      largest_area = area;
      largest = t;
    }
    std::mt19937_64 generator(TriangleSeed(a, b, c, seed));
    // floor(area * density) samples, one more with the probability of the
    // fractional part: area * density in expectation.
    const double expected = area * density_per_m2;
    double whole = 0.0;
    const double fraction = std::modf(expected, &whole);
    const size_t count =
        static_cast<size_t>(whole) + (uniform(generator) < fraction ? 1 : 0);
    for (size_t i = 0; i < count; ++i) {
      const double r1 = std::sqrt(uniform(generator));
      const double r2 = uniform(generator);
      samples.push_back((1.0 - r1) * a + r1 * (1.0 - r2) * b +
                        r1 * r2 * c);
    }
  }
  // A mesh of positive area gets at least one sample: the centroid of its
  // largest triangle.
  if (samples.empty() && largest < triangles.size()) {
    samples.push_back((vertices[triangles[largest][0]] +
                       vertices[triangles[largest][1]] +
                       vertices[triangles[largest][2]]) /
                      3.0);
  }
  return samples;
}

}  // namespace colmap_lidar
