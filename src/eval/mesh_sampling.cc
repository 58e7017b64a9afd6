#include "src/eval/mesh_sampling.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <Eigen/Geometry>

#include "colmap_ext/util/logging.h"

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

}  // namespace

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
  std::vector<double> cumulative_area(triangles.size());
  double area = 0.0;
  for (size_t i = 0; i < triangles.size(); ++i) {
    area += TriangleArea(vertices, triangles[i]);
    cumulative_area[i] = area;
  }
  std::vector<Eigen::Vector3d> samples;
  if (area <= 0.0) {
    return samples;
  }
  const size_t num_samples = std::max<size_t>(
      1, static_cast<size_t>(std::llround(area * density_per_m2)));
  samples.reserve(num_samples);
  std::mt19937_64 generator(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (size_t i = 0; i < num_samples; ++i) {
    const double target = uniform(generator) * area;
    const size_t t = std::min<size_t>(
        triangles.size() - 1,
        std::upper_bound(cumulative_area.begin(), cumulative_area.end(),
                         target) -
            cumulative_area.begin());
    const double r1 = std::sqrt(uniform(generator));
    const double r2 = uniform(generator);
    const Eigen::Vector3d& a = vertices[triangles[t][0]];
    const Eigen::Vector3d& b = vertices[triangles[t][1]];
    const Eigen::Vector3d& c = vertices[triangles[t][2]];
    samples.push_back((1.0 - r1) * a + r1 * (1.0 - r2) * b + r1 * r2 * c);
  }
  return samples;
}

}  // namespace colmap_lidar
