// Edge points of a LIDAR scan (paper section III-B: "we retrieve edge points
// from LIDAR scans based on a smoothness score as described in LeGO-LOAM").
//
// Ring method (organised scans, the default): the points of each laser ring
// are ordered by azimuth and every point gets the smoothness
//   c_i = |sum_{j in S, j != i} (r_j - r_i)| / (|S| * r_i),
// S = the num_neighbors points on each side along the ring, r = range. A
// point is a candidate only when its window is contiguous (no azimuth gap,
// i.e. no missing returns) and does not cross a seam (consecutive points
// whose elevations differ by more than max_elevation_step_deg while their
// ranges differ by less than occlusion_range_gap belong to different lasers,
// e.g. where an estimated ring switches lasers). With
// edges_at_gaps, a point whose window is cut
// by a gap right next to it while its other side is contiguous (an object
// seen against the sky or beyond the range) is an occluding contour and gets
// the score 1, above any threshold. As LeGO-LOAM does, points on the far side of a
// depth jump (occluded, unreliable) and points on surfaces nearly parallel to
// the beam (both range differences to the neighbours large) are excluded;
// each ring is split into num_sectors sectors of equal point count and in
// each sector the sharpest candidates above the threshold are taken, at most
// max_edges_per_sector, skipping the neighbours of points already taken.
//
// PCA method (fallback for unorganised clouds, no rings): the surface
// variation l0 / (l0 + l1 + l2) of the covariance of the neighbours within
// pca_radius (eigenvalues l0 <= l1 <= l2) measures how much the normal turns
// around the point; points above the threshold are edges.
//
// Ring indices come from the scan's ring channel, else from the point order
// (EstimateRingsFromScanOrder), else from the elevation angle
// (EstimateRingsFromElevation over the scan's elevation range). With method
// "auto" a cloud whose rings do not look like scan lines is treated as
// unorganised: a spinning LIDAR samples each ring at a regular azimuth step,
// so most steps between azimuth neighbours are within [0.5, 1.5] x the
// ring's median step; for scattered points (steps roughly exponentially
// distributed) only about a third are. Below min_regular_step_fraction of
// regular steps the PCA method is used.
#pragma once

#include <string>
#include <vector>

#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {

struct LidarEdgeOptions {
  // "ring" (LeGO-LOAM smoothness), "pca" (surface variation) or "auto".
  std::string method = "auto";
  // Number of lasers, used to estimate rings when the scan has no ring
  // channel.
  int num_rings = 64;
  // Neighbours on each side along the ring in the smoothness window
  // (LeGO-LOAM: 5).
  int num_neighbors = 5;
  // Points next to missing returns are occluding contours (see above).
  bool edges_at_gaps = true;
  // Smoothness above which a point is an edge (dimensionless).
  double smoothness_threshold = 0.004;
  // Sectors per ring for the count limit (LeGO-LOAM: 6).
  int num_sectors = 6;
  // At most this many edge points per ring and sector.
  int max_edges_per_sector = 60;
  // Range jump between azimuth neighbours that marks an occlusion boundary,
  // metres (LeGO-LOAM: 0.3).
  double occlusion_range_gap = 0.3;
  // ... or this fraction of the nearer range, when that is smaller (0:
  // off). LeGO-LOAM's fixed 0.3 m is a long-range rule: at 5 m a 16 cm
  // window recess is an occlusion too, and the recessed points next to it
  // (on the glass, beside the lip) are edge points of no crease. The same
  // fraction as parallel_beam_ratio: a range step that large between two
  // azimuth neighbours is either a surface nearly parallel to the beam (a
  // step on both sides, excluded below) or an occluding contour.
  double occlusion_range_ratio = 0.02;
  // A point whose range differs from both neighbours by more than this
  // fraction of its range is on a surface parallel to the beam (LeGO-LOAM:
  // 0.02).
  double parallel_beam_ratio = 0.02;
  // Consecutive points of a ring whose elevation differs by more than this
  // are not neighbours (a seam between two lasers), degrees.
  double max_elevation_step_deg = 0.2;
  // Consecutive points of a ring more than this many median azimuth steps
  // apart are not contiguous (missing returns in between).
  double max_azimuth_gap_steps = 3.0;
  // Points outside [min_range, max_range] are ignored, metres.
  double min_range = 1.0;
  double max_range = 120.0;
  // "auto": organised-scan test, see the file comment.
  double min_regular_step_fraction = 0.6;
  // PCA method: neighbourhood radius (metres), minimum neighbours, and the
  // surface variation threshold (0 .. 1/3).
  double pca_radius = 0.3;
  int pca_min_neighbors = 8;
  double pca_min_surface_variation = 0.06;

  bool Check() const;
};

// Smoothness of each point of one ring, given the ranges in azimuth order
// and whether consecutive points are contiguous (contiguous[i] refers to the
// pair i, i+1; size n - 1). seams (empty or size n - 1) marks the breaks
// that are seams rather than missing returns. Points whose window is
// incomplete or crosses a break get -1, except, with edges_at_gaps, points
// right next to a missing-returns gap (score 1).
std::vector<double> ComputeRingSmoothness(const std::vector<double>& ranges,
                                          const std::vector<bool>& contiguous,
                                          int num_neighbors,
                                          bool edges_at_gaps = false,
                                          const std::vector<bool>& seams = {});

// The range jump between azimuth neighbours that marks an occlusion
// boundary at `range` (the nearer of the two), metres.
double OcclusionRangeGap(const LidarEdgeOptions& options, double range);

// Positions (into `ranges`) of the edge points of one ring: the occlusion /
// parallel-beam exclusion and the per-sector selection described above.
std::vector<int> SelectRingEdges(const std::vector<double>& ranges,
                                 const std::vector<bool>& contiguous,
                                 const LidarEdgeOptions& options,
                                 const std::vector<bool>& seams = {});

// For every scan point, its previous and next point along its ring (indices
// into scan.points), or -1 at a ring end, a gap or a seam. Empty for the PCA
// method.
struct RingNeighbors {
  std::vector<int> prev;
  std::vector<int> next;
  bool empty() const { return prev.empty(); }
};

// Indices into scan.points of the edge points, increasing. ring_neighbors,
// when given, receives the ring order used (empty with the PCA method).
std::vector<int> DetectLidarEdges(const LidarScan& scan,
                                  const LidarEdgeOptions& options,
                                  RingNeighbors* ring_neighbors = nullptr);

// The PCA fallback on its own (indices, increasing).
std::vector<int> DetectLidarEdgesPca(const LidarScan& scan,
                                     const LidarEdgeOptions& options);

}  // namespace colmap_lidar
