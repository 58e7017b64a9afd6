// Sharpening of the mesh along the creases that the 3D line segments found.
//
// The paper (Amblard et al., Sec. III-E) adds samples of the 3D segments to
// the Delaunay meshing and expects the mesh to be more precise where lines
// were found. Measured on the benchmark matrix it was not (near the creases
// precision with line samples minus without -0.001 to +0.001 at 0.05 m): the
// samples give the surface a vertex on the crease, but the vertices around
// it keep the noise of the fused depths and LIDAR voxels, and the facets
// between them round the corner off. A validated segment (line_validation.h)
// knows more than its samples: the two faces that meet at it, fitted to the
// surface points around it. Here every mesh vertex near such a crease moves
// onto the nearest point of that measured wedge (one of the two half-planes,
// or the crease itself), when that point is close: the wedge is a local
// two-plane fit of the same points, so this is the plane projection the
// LIDAR denoising does on flat voxels, applied across the crease.
//
// Scales come from the data: s is the line validation's point spacing; the
// region around a crease is the validation's support cylinder, and a vertex
// moves at most max_move_factor * s (farther ones belong to other structure:
// a window frame, a thin post). The wedge's half-planes are fitted over the
// whole cylinder, so they can be wrong in part of it (a kerb's low side face
// extended under the road, a face that bends): a vertex moves only where the
// surface points around it lie on the wedge too (median distance within the
// validation's plane band).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "src/mesh/triangle_mesh.h"

namespace colmap_lidar {

// A crease of the measured surface, world frame, metres: the segment
// start-end and the unit directions, orthogonal to it, along which its two
// faces leave it (ValidatedLine::face_directions).
struct MeshCrease {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
  std::array<Eigen::Vector3d, 2> face_directions = {
      Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  // The half width of the line validation's plane band around the faces,
  // metres (LineValidator::plane_tolerance(): wider than 0.3 s on noisy
  // points); 0: max_local_offset_factor * s alone.
  double plane_band_m = 0;
};

struct CreaseSnappingOptions {
  // Vertices within this many s of a crease (orthogonally, within the
  // segment's extent) are candidates, > 0 (the line validation's support
  // radius, 5 s, by default).
  double radius_factor = 5.0;
  // Largest move of a vertex onto the wedge, in s, > 0.
  double max_move_factor = 1.0;
  // A vertex moves only when the surface points within local_radius_factor
  // * s of it lie on the wedge: at least min_local_points of them, at a
  // median distance of at most max_local_offset_factor * s (the line
  // validation's plane band, 0.3 s) or the crease's plane_band_m where
  // that is wider. Both factors > 0, count >= 1.
  double local_radius_factor = 1.0;
  double max_local_offset_factor = 0.3;
  int min_local_points = 3;

  bool Check() const;
};

struct CreaseSnappingSummary {
  size_t num_creases = 0;
  // Vertices moved (those already on a wedge, e.g. the line samples, are
  // not counted).
  size_t num_vertices_moved = 0;
  // Vertices within reach of a wedge left in place because the surface
  // points around them do not lie on it.
  size_t num_vertices_off_wedge = 0;
  // Median and largest move of the moved vertices, metres.
  double median_move_m = 0;
  double max_move_m = 0;
};

// Moves each vertex of `mesh` that lies within radius_factor * spacing_m of
// a crease onto the nearest point of that crease's wedge, when the move is
// at most max_move_factor * spacing_m and the `surface_points` (the meshing
// input's positions, world frame; its line samples are among them and lie
// on their crease, so within s of a crease they lean the check towards
// snapping, where the validation has placed the crease) around the vertex
// lie on that wedge; a
// vertex near several creases goes to the nearest wedge. The faces are
// unchanged. spacing_m > 0 (the line validation's s). Throws
// colmap_lidar::Error on invalid options, a non-positive spacing or a
// crease whose face directions are not unit vectors orthogonal to it.
CreaseSnappingSummary SnapMeshToCreases(
    const CreaseSnappingOptions& options,
    const std::vector<MeshCrease>& creases,
    const std::vector<Eigen::Vector3d>& surface_points, double spacing_m,
    TriangleMesh* mesh);

}  // namespace colmap_lidar
