#include "src/mesh/crease_snapping.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "colmap_ext/util/logging.h"
#include "src/mesh/radius_grid.h"

namespace colmap_lidar {
namespace {

// Tolerance of the unit-length and orthogonality checks of a crease.
constexpr double kDirectionTolerance = 1e-6;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A crease in the frame the snapping works in.
struct Wedge {
  Eigen::Vector3d start;
  Eigen::Vector3d axis;  // unit, start -> end
  double length = 0;
  std::array<Eigen::Vector3d, 2> face_directions;
  double plane_band_m = 0;

  // The move of `point` onto the nearest point of the wedge (one of its
  // half-planes, or the crease), for a point within the segment's extent
  // and within `radius` of the crease; false outside that cylinder.
  bool MoveOnto(const Eigen::Vector3d& point, double radius,
                Eigen::Vector3d* move) const {
    const Eigen::Vector3d p = point - start;
    const double t = p.dot(axis);
    if (t < 0 || t > length) return false;
    // The point relative to the crease, in the plane orthogonal to it.
    const Eigen::Vector3d q = p - t * axis;
    if (q.squaredNorm() > radius * radius) return false;
    double best = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& direction : face_directions) {
      const Eigen::Vector3d target =
          std::max(0.0, q.dot(direction)) * direction;
      const double distance = (q - target).squaredNorm();
      if (distance < best) {
        best = distance;
        *move = target - q;
      }
    }
    return true;
  }
};

}  // namespace

bool CreaseSnappingOptions::Check() const {
  if (!(radius_factor > 0) || !std::isfinite(radius_factor)) {
    LOG(ERROR) << "Crease snapping radius_factor must be > 0";
    return false;
  }
  if (!(max_move_factor > 0) || !std::isfinite(max_move_factor)) {
    LOG(ERROR) << "Crease snapping max_move_factor must be > 0";
    return false;
  }
  if (!(local_radius_factor > 0) || !std::isfinite(local_radius_factor) ||
      !(max_local_offset_factor > 0) ||
      !std::isfinite(max_local_offset_factor)) {
    LOG(ERROR) << "Crease snapping local_radius_factor and "
                  "max_local_offset_factor must be > 0";
    return false;
  }
  if (min_local_points < 1) {
    LOG(ERROR) << "Crease snapping min_local_points must be >= 1";
    return false;
  }
  return true;
}

CreaseSnappingSummary SnapMeshToCreases(
    const CreaseSnappingOptions& options,
    const std::vector<MeshCrease>& creases,
    const std::vector<Eigen::Vector3d>& surface_points,
    const double spacing_m, TriangleMesh* mesh) {
  THROW_CHECK(options.Check(), "Invalid crease snapping options");
  THROW_CHECK(spacing_m > 0 && std::isfinite(spacing_m),
              "Crease snapping: the point spacing must be > 0, got "
                  << spacing_m);
  CreaseSnappingSummary summary;
  summary.num_creases = creases.size();
  std::vector<Wedge> wedges;
  for (size_t c = 0; c < creases.size(); ++c) {
    const MeshCrease& crease = creases[c];
    Wedge wedge;
    wedge.start = crease.start;
    wedge.length = (crease.end - crease.start).norm();
    if (!(wedge.length > 0)) continue;
    wedge.axis = (crease.end - crease.start) / wedge.length;
    wedge.face_directions = crease.face_directions;
    THROW_CHECK(crease.plane_band_m >= 0 && std::isfinite(crease.plane_band_m),
                "Crease snapping: crease "
                    << c << " has a plane band that is not >= 0");
    wedge.plane_band_m = crease.plane_band_m;
    for (const Eigen::Vector3d& direction : crease.face_directions) {
      THROW_CHECK(std::abs(direction.norm() - 1) < kDirectionTolerance &&
                      std::abs(direction.dot(wedge.axis)) <
                          kDirectionTolerance,
                  "Crease snapping: crease " << c
                      << " has a face direction that is not a unit vector "
                         "orthogonal to it");
    }
    wedges.push_back(wedge);
  }
  if (wedges.empty() || mesh->vertices.empty()) return summary;
  const double radius = options.radius_factor * spacing_m;
  const double max_move = options.max_move_factor * spacing_m;

  // Per vertex: the nearest wedge within reach and the move onto it.
  constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  std::vector<double> best_distance(mesh->vertices.size(),
                                    std::numeric_limits<double>::infinity());
  std::vector<uint32_t> best_wedge(mesh->vertices.size(), kNone);
  std::vector<Eigen::Vector3d> moves(mesh->vertices.size(),
                                     Eigen::Vector3d::Zero());
  const RadiusGrid vertex_grid(mesh->vertices, radius);
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(radius);
  for (size_t w = 0; w < wedges.size(); ++w) {
    const Wedge& wedge = wedges[w];
    const Eigen::Vector3d end = wedge.start + wedge.length * wedge.axis;
    vertex_grid.ForEachInBox(
        wedge.start.cwiseMin(end) - margin, wedge.start.cwiseMax(end) + margin,
        [&](uint32_t v) {
          Eigen::Vector3d move = Eigen::Vector3d::Zero();
          if (!wedge.MoveOnto(mesh->vertices[v], radius, &move)) return;
          const double distance = move.norm();
          if (distance < best_distance[v]) {
            best_distance[v] = distance;
            best_wedge[v] = static_cast<uint32_t>(w);
            moves[v] = move;
          }
        });
  }

  // The local check: the surface points around a vertex lie on its wedge.
  const double local_radius = options.local_radius_factor * spacing_m;
  const double max_local_offset = options.max_local_offset_factor * spacing_m;
  const RadiusGrid point_grid(surface_points, local_radius);
  std::vector<double> offsets;
  std::vector<double> moved;
  for (size_t v = 0; v < mesh->vertices.size(); ++v) {
    // Vertices on the wedge already (the line samples) do not move.
    if (!(best_distance[v] <= max_move) || best_distance[v] == 0) continue;
    const Wedge& wedge = wedges[best_wedge[v]];
    offsets.clear();
    point_grid.ForEachNear(mesh->vertices[v], [&](uint32_t i) {
      if ((surface_points[i] - mesh->vertices[v]).squaredNorm() >
          local_radius * local_radius) {
        return;
      }
      Eigen::Vector3d move = Eigen::Vector3d::Zero();
      if (wedge.MoveOnto(surface_points[i], kInfinity, &move)) {
        offsets.push_back(move.norm());
      }
    });
    if (offsets.size() < static_cast<size_t>(options.min_local_points)) {
      ++summary.num_vertices_off_wedge;
      continue;
    }
    std::nth_element(offsets.begin(), offsets.begin() + offsets.size() / 2,
                     offsets.end());
    if (offsets[offsets.size() / 2] >
        std::max(max_local_offset, wedge.plane_band_m)) {
      ++summary.num_vertices_off_wedge;
      continue;
    }
    mesh->vertices[v] += moves[v];
    moved.push_back(best_distance[v]);
  }
  summary.num_vertices_moved = moved.size();
  if (!moved.empty()) {
    summary.max_move_m = *std::max_element(moved.begin(), moved.end());
    std::nth_element(moved.begin(), moved.begin() + moved.size() / 2,
                     moved.end());
    summary.median_move_m = moved[moved.size() / 2];
  }
  return summary;
}

}  // namespace colmap_lidar
