// Options of the 3D/3D line association (paper section III-C): the
// thresholds of Algorithm 1, the candidate view / visibility test, the
// tolerances derived from the prior pose uncertainty, and CLEAR.
#pragma once

#include "src/matching/clear.h"

namespace colmap_lidar {

struct LineMatchingOptions {
  // ---- Algorithm 1 thresholds (t_theta, t_dP, t_dO, t_LBD). A candidate
  // segment must be strictly below all four; the score is the sum of the
  // four ratios value / threshold, and the match in a view is the candidate
  // with the smallest score.
  // Angle between the reprojected segment and the detected one, degrees.
  double t_theta_deg = 4.0;
  // Pixel distance between projected endpoints: the mean distance of the
  // four endpoints to the other segment's 2D line, pixels.
  double t_dP_px = 12.0;
  // Orthogonal distance: the midpoint difference projected perpendicularly
  // to the segment's 3D direction (world frame), metres.
  double t_dO_m = 0.25;
  // Hamming distance between the 256-bit LBD descriptors, bits. 256 (the
  // maximum + 0) disables the criterion, e.g. when the extractor stored no
  // descriptors.
  double t_LBD = 256.0;
  // Optional fifth criterion (not in the paper): the overlap of the two
  // segments along the reprojected line, as a fraction of the shorter one,
  // must be at least this. 0 disables it (Algorithm 1 as written). On the
  // quad scene it separates collinear edges (the tops of a row of windows),
  // which the four line-based criteria cannot: track precision 85% -> 96%.
  double min_overlap = 0.2;
  // Optional rival test (not in the paper): the best match in a view is
  // dropped when a second segment lying side by side with it scores less
  // than best / this, i.e. best >= ratio * second, (0, 1]; 1 disables it.
  // Edges a few centimetres apart (window lips, frames and wall edges)
  // otherwise go to whichever the noise favours.
  double max_rival_score_ratio = 0.8;

  // ---- Pose uncertainty. The thresholds above hold for exact poses; with
  // priors whose centres are off by sigma_t per axis and rotations by
  // sigma_r, each threshold grows by pose_uncertainty_scale times the error
  // the relative pose of the two views causes at the segment's depth
  // (sqrt(2) sigma for two independent poses): t_theta + k * sqrt(2) *
  // sigma_r, t_dP + k * f * sqrt(2) * (sigma_r + sigma_t / depth), t_dO + k
  // * sqrt(2) * (sigma_t + depth * sigma_r). 0 = exact poses.
  double pose_sigma_t_m = 0.0;
  double pose_sigma_r_deg = 0.0;
  double pose_uncertainty_scale = 2.0;

  // ---- Registration on the segments (relative_line_pose.h, pose_graph.h).
  // With a pose uncertainty (pose_sigma_* > 0), every pair of views the
  // priors make overlap is first registered on its 3D segments (the
  // uncertainty-grown thresholds above only gate the candidate
  // correspondences), a robust pose graph over the priors and the
  // registrations corrects the poses, and Algorithm 1 runs on the corrected
  // poses with the exact-pose thresholds between views that consistent
  // registrations connect (the grown thresholds between the others). Off:
  // Algorithm 1 with the grown thresholds under the prior poses.
  bool refine_relative_poses = true;
  // Inlier segments a registration needs (and segments of one view the
  // prior must place in the other to try), >= 2.
  int relative_pose_min_inliers = 6;
  // A correspondence is an inlier when (angle / this)^2 + (mean endpoint to
  // line distance / relative_pose_inlier_distance_m)^2 < 1, degrees, > 0.
  double relative_pose_inlier_angle_deg = 2.0;
  // Metres, > 0.
  double relative_pose_inlier_distance_m = 0.1;

  // ---- Candidate views (the "field of view" test of Algorithm 1).
  // Points sampled along a 3D segment for the visibility test, >= 2.
  int num_visibility_samples = 9;
  // A view is a candidate when at least this fraction of the samples
  // projects in front of the camera, inside the image and not hidden,
  // (0, 1].
  double min_visible_fraction = 0.3;
  // Samples nearer than this along the optical axis are not visible, metres.
  double min_depth_m = 0.2;
  // Hide samples behind the LIDAR surface of the candidate view (its scan
  // from ext_lidar_scans) when the scan is available.
  bool use_lidar_visibility = true;
  // Cell of the coarse LIDAR depth image, pixels, >= 1.
  int visibility_cell_px = 8;
  // A sample is hidden when its depth exceeds the nearest LIDAR depth of its
  // cell (and of the 8 cells around it) by relative * depth + absolute
  // (plus the pose uncertainty, as for t_dO).
  double visibility_relative_tolerance = 0.1;
  double visibility_absolute_tolerance_m = 0.3;

  // ---- Pairwise matching.
  // Keep a pair only when each segment is the other's best match in its
  // view (Algorithm 1 run from both sides). Off: the union of both sides.
  bool cross_check = false;
  // Worker threads; <= 0: all cores.
  int num_threads = -1;

  // ---- Multi-view consistency.
  // Run CLEAR on the match graph; off, tracks are the connected components
  // of the pairwise matches with inconsistent ones dropped.
  bool use_clear = true;
  ClearOptions clear;
  // Tracks with fewer observations are discarded, >= 2.
  int min_track_length = 2;

  bool Check() const;
  // refine_relative_poses and a non-zero pose uncertainty.
  bool RegistersPairs() const {
    return refine_relative_poses &&
           (pose_sigma_t_m > 0.0 || pose_sigma_r_deg > 0.0);
  }
};

// The thresholds of Algorithm 1 for a segment at `depth_m` in the candidate
// view of focal length `focal_length_px`, after the pose uncertainty.
struct MatchingThresholds {
  double theta_deg = 0.0;
  double dP_px = 0.0;
  double dO_m = 0.0;
  double LBD = 0.0;
  double visibility_absolute_m = 0.0;
};

MatchingThresholds EffectiveThresholds(const LineMatchingOptions& options,
                                       double depth_m, double focal_length_px);

}  // namespace colmap_lidar
