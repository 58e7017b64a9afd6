// Lifting 2D line segments to 3D with LIDAR edge points (section III-B):
//  1. edge points that the camera sees (ProjectScan's z-buffer) are matched
//     to a 2D segment when their pixel lies within max_point_distance_px of
//     the segment and within its extent (plus the same margin); with ring
//     neighbours, each is moved along its ring onto the segment's viewing
//     plane (the crease point of that ring), and dropped when that is too
//     far (max_refine_move_steps);
//  2. RANSAC fits a 3D line to the matched points; only inliers are kept,
//     and they must cover min_inlier_coverage of the segment; the line is
//     refitted to the inliers within the segment's viewing plane;
//  3. the 3D line is reprojected and compared with the 2D segment: angle
//     and the distances of the segment's endpoints to the reprojected line;
//  4. the 2D segment is clipped to its LIDAR support (max_extrapolation)
//     and the 3D endpoints are the back-projections of its endpoints onto
//     the 3D line (the closest point of the line to each viewing ray);
//  5. texture-only lines and silhouettes of curved or thin objects
//     (texture_rejection.h) are discarded.
// Everything is in the camera frame of the view.
#pragma once

#include <optional>
#include <vector>

#include "colmap_ext/scene/camera.h"
#include "src/lines/lidar_edges.h"
#include "src/lines/line_ransac.h"
#include "src/lines/line_types.h"
#include "src/lines/scan_projection.h"
#include "src/lines/texture_rejection.h"

namespace colmap_lidar {

struct EdgeAssociationOptions {
  // An edge point joins a segment within this pixel distance.
  double max_point_distance_px = 6.0;
  LineRansacOptions ransac;
  // Move each edge point along its ring to where the ring crosses the 2D
  // segment's viewing plane (linear interpolation between two ring
  // neighbours on one surface): the crease point of that ring, more precise
  // than the nearest LIDAR sample (one azimuth step is 6 cm at 10 m). Needs
  // ring neighbours (ring edge method); across a range jump the nearer
  // point is kept.
  bool refine_along_rings = true;
  // Search at most this many ring steps from the edge point.
  int max_refine_steps = 3;
  // Edge points that this refinement moves by more than this many ring
  // steps (distance to a ring neighbour) are dropped: they belong to another
  // crease near the segment (e.g. a shadow or frame line a few centimetres
  // from a recess corner). 0: keep all.
  double max_refine_move_steps = 2.5;
  // Ring neighbours whose ranges differ by more than this are across an
  // occluding contour (not interpolated), metres ...
  double refine_max_range_jump = 0.3;
  // ... or by more than this fraction of the nearer range, when that is
  // smaller (0: off); as LidarEdgeOptions::occlusion_range_ratio.
  double refine_range_jump_ratio = 0.02;
  // Refit the 3D line to the inliers projected onto the 2D segment's
  // viewing plane (the image fixes that plane more precisely than the
  // LIDAR's angular sampling fixes the edge points).
  bool fit_in_viewing_plane = true;
  // The inliers' projections must span this fraction of the 2D segment.
  double min_inlier_coverage = 0.2;
  // The 2D segment is clipped to the stretch its inliers span, extended on
  // each side by this fraction of that stretch (negative: not clipped).
  // The 3D endpoints are the 2D endpoints back-projected onto the fitted
  // line; far beyond the LIDAR support (e.g. a wall edge rising above the
  // LIDAR's field of view) they rest on an extrapolated line, where a small
  // tilt becomes a large error. 0: the segment spans exactly the stretch
  // the LIDAR supports (extending it by half an inlier spacing, where the
  // crease most likely ends, already put 10 more of ~750 segments of the
  // default synthetic scene beyond 5 cm; 0.25 put 20 more).
  double max_extrapolation = 0.0;
  // Reprojection check of the fitted line against the 2D segment.
  double max_reprojection_angle_deg = 3.0;
  double max_reprojection_distance_px = 4.0;
  // Endpoint back-projection: minimum angle between the viewing ray and the
  // 3D line, degrees (also the plane lifting's limit for a plane seen
  // edge-on). 3 rather than 5: the wall/ground creases of a corridor and a
  // street run along the view; on 5 cells (corridor VLP-16 and OS1-64,
  // street_bent, street HDL-32E, quad OS1-64; ground-truth poses,
  // scripts/bench_lines.sh) 3 deg added segments on four cells and crease
  // recall on three and changed nothing on the quad; the share of segments
  // within 5 cm of a crease rose on three and fell by 0.2 points on the
  // corridor OS1-64 (docs/benchmarks/lines.md, seventh round).
  double min_ray_line_angle_deg = 3.0;
  // 3D endpoints must be within this range of the camera, metres.
  double max_endpoint_range = 120.0;
  TextureRejectionOptions texture;

  bool Check() const;
};

// Why a 2D segment was not lifted (for statistics and tests).
enum class LiftResult {
  kLifted,
  kTooFewPoints,
  kRansacFailed,
  kLowCoverage,
  kReprojection,
  kBackProjection,
  // Rejected by the surface test (texture_rejection.h): a texture line, a
  // silhouette, or (unless kept) an occluding contour or unknown surface.
  kTexture,
};

// Lifts one segment. edge_grid holds the indices (into `projected`) of the
// visible edge points. On kLifted, *lifted has the 2D segment, the 3D
// endpoints and the inlier indices (no descriptor).
// ring_neighbors may be null or empty (no refinement along rings).
// surface, when given, receives the surface test's verdict when the
// segment reached it (lifted, or kTexture), else is reset.
LiftResult LiftSegment(const LineSegment2D& segment, const Camera& camera,
                       const ProjectedScan& projected,
                       const PixelGrid& edge_grid,
                       const EdgeAssociationOptions& options,
                       ViewLineSegment* lifted,
                       const RingNeighbors* ring_neighbors = nullptr,
                       std::optional<LineSurfaceType>* surface = nullptr);

// Lifts every segment; returns the lifted ones in input order. counts, when
// given, receives the number of segments per LiftResult (indexed by the
// enum value); not_lifted, when given, the segments that were not lifted;
// results, when given, the outcome of every segment (same order as
// segments); surfaces, when given, the surface test's verdict of every
// segment that reached it (same order).
std::vector<ViewLineSegment> LiftSegments(
    const std::vector<LineSegment2D>& segments, const Camera& camera,
    const ProjectedScan& projected, const std::vector<int>& edge_point_idxs,
    const EdgeAssociationOptions& options, std::vector<int>* counts = nullptr,
    const RingNeighbors* ring_neighbors = nullptr,
    std::vector<LineSegment2D>* not_lifted = nullptr,
    std::vector<LiftResult>* results = nullptr,
    std::vector<std::optional<LineSurfaceType>>* surfaces = nullptr);

// A short name of the outcome ("lifted", "too_few_points", ...).
const char* LiftResultName(LiftResult result);

}  // namespace colmap_lidar
