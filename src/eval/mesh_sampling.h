// Uniform, area-weighted point sampling of a triangle mesh, used to turn an
// estimated mesh into the point set whose precision is evaluated
// (Knapitsch et al. 2017, "Tanks and Temples", Sec. 4: reconstructions are
// compared as point sets).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {

// Splits polygons into triangles by a fan around their first vertex;
// polygons with fewer than 3 vertices are skipped. Throws
// colmap_lidar::Error naming `path_for_errors` when an index is out of range.
std::vector<Eigen::Vector3i> TriangulatePolygons(
    const std::vector<std::vector<uint32_t>>& polygons, size_t num_vertices,
    const std::string& path_for_errors = "");

// A mesh (or a point cloud: no faces) as the evaluators use it.
struct EvaluationMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  // Whether the file had a face element with polygons (of any size).
  bool has_faces = false;
};

// Reads `path`'s positions and fan-triangulated polygons; the file's own
// columns and polygon lists (about 56 bytes per face) are released before
// returning, so that a large mesh is held once. Throws colmap_lidar::Error
// naming `what` and the path when the file is missing or unreadable, has no
// vertex or a non-finite one, or a polygon indexes past the vertices.
EvaluationMesh ReadEvaluationMesh(const std::string& path,
                                  const std::string& what);

double TriangleMeshArea(const std::vector<Eigen::Vector3d>& vertices,
                        const std::vector<Eigen::Vector3i>& triangles);

// Draws about area * density_per_m2 points, uniformly over the surface (at
// least 1 when the area is positive, none for a zero-area mesh): each
// triangle gets floor(its area * density) points, one more with the
// probability of the fractional part, each uniform inside it (barycentric
// square-root method). A triangle's points depend only on the seed and its
// three vertices' coordinates, so a triangle that two meshes share gets the
// same points in both: an A/B of two meshes that differ in a region
// differs in that region's samples only (a global draw redrew every sample
// whenever the total area changed, +-0.0005 of precision near the creases
// between meshes that differ in 2 % of their vertices). Deterministic for a
// given seed. Throws colmap_lidar::Error when more than 1e9 samples are
// asked.
std::vector<Eigen::Vector3d> SampleTriangleMesh(
    const std::vector<Eigen::Vector3d>& vertices,
    const std::vector<Eigen::Vector3i>& triangles, double density_per_m2,
    uint64_t seed);

}  // namespace colmap_lidar
