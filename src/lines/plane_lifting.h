// Lifting 2D segments with the LIDAR surfaces on each side of them (issue
// 15), for the segments that no LIDAR edge point supports. A ring-scanning
// LIDAR crosses a horizontal crease (a kerb, a facade/ground crease, the top
// of a window frame) only a few times, and its edge points are sparse on any
// crease of a 16- or 32-ring scan; but the two faces of the crease are
// sampled densely. Section III-B lifts a segment with edge points only;
// here the image fixes where the edge is and the faces fix its depth:
//  1. the visible LIDAR points whose pixels lie within the segment's extent,
//     farther than band_gap_px from it on each side, form the side's band;
//     the band is as narrow as it can be and still hold a plane (it widens
//     up to max_band_fraction of the image diagonal);
//  2. a plane is fitted to each band by RANSAC (inlier distance from the
//     measured range noise, see range_noise_m) and refined by PCA; a plane
//     needs min_side_points inliers spread across the band (a single ring,
//     nearly a line, fixes no plane);
//  3. the planes meet at an angle of at least min_crease_angle_deg: the
//     3D line is their intersection (a crease), accepted when it reprojects
//     onto the 2D segment (the association's angle and distance checks);
//     the planes are parallel but their depths along the segment's rays
//     differ by more than the step threshold: the nearer plane's boundary
//     (an occluding or step edge, e.g. a protruding window frame), the
//     3D points are the segment's rays cut with that plane (scaled to the
//     depth of the near points right next to the segment), when those
//     points agree that the step is there; parallel at the same depth: a
//     texture line on one surface, rejected;
//  4. as for edge points, the 2D segment is clipped to the stretch both
//     bands support (the near band alone for an occluding edge) and the 3D
//     endpoints are its endpoints back-projected onto the 3D line.
// Everything is in the camera frame of the view.
#pragma once

#include <vector>

#include "colmap_ext/scene/camera.h"
#include "src/lines/line_types.h"
#include "src/lines/scan_projection.h"

namespace colmap_lidar {

struct PlaneLiftingOptions {
  // Lift the segments that edge points did not lift (creases; occluding
  // edges only with keep_occlusions). On since the matrix's 10 cells gained
  // segments (+11 to +63 %) and crease recall on every cell, and the worst
  // cell's poses held (docs/benchmarks/lines.md, sixth round); not in the
  // paper (configs/paper.ini turns it off).
  bool enabled = true;
  // Points nearer than this to the segment in the image belong to neither
  // side (the camera-LIDAR calibration and the edge's blur), pixels.
  double band_gap_px = 1.5;
  // The band reaches at most this far from the segment, as a fraction of
  // the image diagonal (0.06: 48 px at 640x480, 58 at 848x480, 88 at
  // 1280x720; several ring spacings of a 16- to 128-ring LIDAR there).
  double max_band_fraction = 0.06;
  // At most this many points of each side (spread evenly over its band).
  int max_side_points = 96;
  // A side's plane needs this many inliers, >= 3.
  int min_side_points = 8;
  // Range noise of the LIDAR (standard deviation, metres); 0: estimated
  // from the scan (src/lidar/sensor_estimation.h). The plane inlier
  // distance is 2.5 sigma, at least 1 cm.
  double range_noise_m = 0.0;
  // Both in-plane spreads of a side's inliers (square roots of the two
  // larger PCA eigenvalues) must reach this many inlier distances: one ring
  // alone is nearly a line.
  double min_plane_spread = 3.0;
  // Two sides whose normals differ by at least this make a crease, degrees
  // (as TextureRejectionOptions::min_normal_change_deg).
  double min_crease_angle_deg = 30.0;
  // Parallel sides whose depths along the segment's rays differ by more
  // than this many range-noise sigmas (at least 4 cm) make a step edge.
  double min_step_sigmas = 3.0;
  // The supported stretch must cover this fraction of the segment, [0, 1].
  // The lifted segment is that stretch, so a long crease whose near part
  // lies outside the LIDAR's field (a corridor's wall/ground crease below
  // a 16-ring scan's lowest ring) is kept for its supported part: 0.15
  // rather than 0.3 lifted more of them on both corridors and changed
  // nothing elsewhere (docs/benchmarks/lines.md, seventh round).
  double min_coverage = 0.15;
  // Keep occluding / step edges (the nearer plane's boundary). Off: with
  // the boundary test and the snap below they keep the edge points'
  // precision on the 64-ring quad (89.0 vs 90.6 % of all segments within
  // 5 cm of a crease, recall 48.6 vs 32.5 %) but cost 1 point on the
  // 32-ring bent street and 18 on the 16-ring corridor
  // (docs/benchmarks/lines.md, fourth round).
  bool keep_occlusions = false;
  // An occluding / step edge is kept only when the LIDAR points within this
  // fraction of the band's reach (max_band_fraction) agree that the step is
  // at the segment: on its near side they lie on the near plane, on its far
  // side behind it (0.25: 12 px at 640x480, 22 at 1280x720).
  double boundary_band_fraction = 0.25;
  // ... with at most this fraction of the points of a side disagreeing,
  // [0, 1). 0: with snap_to_near_points, the share of occluding edges
  // within 5 cm of a true crease rose from 22 % (no test) to 62 % on
  // street_bent, and that of all segments from 72 to 89 % on the quad; 0.1
  // and 0.2 kept more of the wrong ones (docs/benchmarks/lines.md).
  double max_boundary_violations = 0.0;
  // Place an occluding edge at the depth of the near side's points within
  // twice band_gap_px of it (the median ratio of their depths to the near
  // plane's) rather than on the plane, which may be a surface behind them.
  bool snap_to_near_points = true;

  bool Check() const;
};

enum class PlaneLiftResult {
  kCrease,
  kOcclusion,
  kNoPlanes,      // fewer than two sides with a plane (one for occlusions)
  kTexture,       // the same surface on both sides
  kReprojection,  // the planes' intersection does not project onto the segment
  kLowCoverage,
  kBackProjection,
  kBoundary,      // a step, but not at the segment (the points next to it)
  kOutOfRange,    // lifted, but an endpoint beyond max_endpoint_range
  kNotTried,      // plane lifting off, or the edge points lifted it
};

// A short name of the outcome ("crease", "no_planes", ...).
const char* PlaneLiftResultName(PlaneLiftResult result);

// Lifts one segment; on kCrease / kOcclusion *lifted has the clipped 2D
// segment and its 3D endpoints (no inliers, no descriptor). range_noise_m
// is the sigma to use (options.range_noise_m resolved by the caller).
// max_reprojection_* and min_ray_line_angle_deg are the edge association's
// thresholds.
PlaneLiftResult LiftSegmentByPlanes(const LineSegment2D& segment,
                                    const Camera& camera,
                                    const ProjectedScan& projected,
                                    const PlaneLiftingOptions& options,
                                    double range_noise_m,
                                    double max_reprojection_angle_deg,
                                    double max_reprojection_distance_px,
                                    double min_ray_line_angle_deg,
                                    ViewLineSegment* lifted);

}  // namespace colmap_lidar
