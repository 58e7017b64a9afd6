// Texture-only line rejection (section III-B: "we discard lines
// corresponding to flat surfaces (i.e. only corresponding to changes in
// texture), and instead focus ... on edges (i.e. lines that correspond to
// changes in the local surface normal)").
//
// The LIDAR points around a lifted 3D segment (within `radius` of it, not
// beyond its ends) are split into the two sides of its viewing plane (the
// plane through the camera centre and the segment). Each side's face is
// modelled as a half-plane hinged on the 3D line itself: a point's offset
// perpendicular to the line has an angle about the line, and the side's face
// angle is the median of its points' angles. Anchoring the faces on the line
// tests for a normal change *at* the line: a texture line a few centimetres
// from a real crease (a plank joint next to a door reveal, a window frame
// next to the recess corner) has the same face on both sides (the median
// ignores the minority of points beyond the nearby crease), while two planes
// fitted freely to each side would see the nearby crease. A side's residual
// is the median distance of its points to its face.
//  * Both sides have a face: the normal change is 180 deg minus the angle
//    between the two faces; a crease when it reaches min_normal_change_deg,
//    else texture.
//  * One side has a face and the other (almost) no points within the radius:
//    a silhouette of a curved or thin object (tree trunk, pole, bollard),
//    whose position depends on the viewpoint and which is no crease
//    (kSilhouette), unless the face is planar (residual at most
//    max_face_residual) and extends at least min_face_extent from the line.
//    Then the LIDAR rays that pass the empty side of the line (beyond the
//    radius, crossing the band at the line) decide, by where they end
//    against the face's plane extended past the line:
//     - behind it: open space, an occluding contour (kOcclusion; the
//       boundary of a planar face is a crease whose second face is hidden,
//       a box or building corner against the background);
//     - on it: the face goes on past a gap of the scan (kTexture). A
//       ring-scanning LIDAR leaves such gaps: on the ground the rings lie
//       r^2 dtheta / h apart, a metre at 10 m for a 32-ring unit, so a
//       paving joint there has the ground on one side and nothing within
//       the radius on the other;
//     - neither (no ray, e.g. sky, or rays stopped in front): kUnknown.
//    A side needs min_open_space_points rays for a verdict (0: an empty
//    side is always open space, the rule before; not in the paper).
//  * Otherwise (too few points) the LIDAR cannot tell (kUnknown).
#pragma once

#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {

struct TextureRejectionOptions {
  // Discard texture-only lines (and silhouettes, unknown lines, see below).
  bool enabled = true;
  // Points within this distance of the segment are its neighbours, metres.
  double radius = 0.3;
  // Points nearer than this to the line belong to neither side, metres ...
  double exclusion_distance = 0.02;
  // ... nor those nearer than this many range-noise sigmas, at most a
  // quarter of the radius: a point d from the line has an angle about it
  // uncertain by sigma / d, so the points of the ring that the line was
  // fitted to, a few cm from it, have angles of noise only (a ground line
  // along a 2 cm-noise ring read as a 100 deg crease). The cap keeps a
  // band for scans whose measured noise includes more than the range
  // noise (KITTI's HDL-64E measures 5-8 cm: half the radius lost a third of
  // its segments, the edges of thin plates among them). 0: off. Not in the
  // paper.
  double exclusion_noise_sigmas = 3.0;
  // The scan's range noise (standard deviation, metres), set by the caller
  // per scan (LineExtraction measures it, or takes plane_range_noise_m);
  // 0: unknown, exclusion_distance only.
  double range_noise_m = 0.0;
  // A side needs this many points for a face.
  int min_side_points = 6;
  // Normal change between the two faces of an edge, degrees. Man-made
  // creases are mostly right angles; 30 (rather than 15) also rejects the
  // facet edges of polygonal approximations of curved surfaces (36 deg for
  // a 10-sided trunk still passes) and lines whose faces are noisy.
  double min_normal_change_deg = 30.0;
  // Keep occluding contours of planar faces (kOcclusion).
  bool keep_occlusions = true;
  // Occluding contour: the face's residual at most this (metres; the LIDAR
  // range noise is ~1.5 cm) ...
  double max_face_residual = 0.02;
  // ... and its points reach at least this far from the line, metres.
  double min_face_extent = 0.2;
  // Occluding contour: rays past the empty side that end behind the face's
  // extended plane (open space) or on it (the face continues: texture), at
  // least this many for either verdict; else unknown. 0: off (an empty side
  // is open space). Not in the paper.
  int min_open_space_points = 3;
  // Keep lines the LIDAR cannot classify (too few points on both sides, or
  // one face and no ray past the other).
  bool keep_unknown = false;

  bool Check() const;
};

enum class LineSurfaceType {
  kCrease,      // the normal turns across the line
  kOcclusion,   // a planar face on one side only (crease, other face hidden)
  kSilhouette,  // a curved or thin surface on one side only
  kTexture,     // one face on both sides
  kUnknown,     // too few points, or one face and no ray past the other
};

// A short name of the type ("crease", "occlusion", ...).
const char* LineSurfaceTypeName(LineSurfaceType type);

// Whether lines of this type are kept by the texture test.
bool IsKeptSurfaceType(LineSurfaceType type,
                       const TextureRejectionOptions& options);

// start/end and the points are in the camera frame (camera centre at the
// origin). `points` may contain any points: those within the radius of the
// segment make the faces; those beyond it whose rays cross the band at the
// line tell open space from a gap of the scan (see above).
LineSurfaceType ClassifyLineSurface(const Eigen::Vector3d& start,
                                    const Eigen::Vector3d& end,
                                    const std::vector<Eigen::Vector3d>& points,
                                    const TextureRejectionOptions& options);

}  // namespace colmap_lidar
