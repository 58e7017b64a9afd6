#include "src/matching/line_matching_options.h"

#include <algorithm>
#include <cmath>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

bool CheckPositive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    LOG(ERROR) << "LineMatching." << name << " must be > 0, got " << value;
    return false;
  }
  return true;
}

bool CheckNonNegative(double value, const char* name) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    LOG(ERROR) << "LineMatching." << name << " must be >= 0, got " << value;
    return false;
  }
  return true;
}

}  // namespace

bool LineMatchingOptions::Check() const {
  bool ok = true;
  ok &= CheckPositive(t_theta_deg, "t_theta_deg");
  if (t_theta_deg > 90.0) {
    LOG(ERROR) << "LineMatching.t_theta_deg must be <= 90, got "
               << t_theta_deg;
    ok = false;
  }
  ok &= CheckPositive(t_dP_px, "t_dP_px");
  ok &= CheckPositive(t_dO_m, "t_dO_m");
  ok &= CheckPositive(t_LBD, "t_LBD");
  if (!(min_overlap >= 0.0 && min_overlap <= 1.0)) {
    LOG(ERROR) << "LineMatching.min_overlap must be in [0, 1], got "
               << min_overlap;
    ok = false;
  }
  if (!(max_rival_score_ratio > 0.0 && max_rival_score_ratio <= 1.0)) {
    LOG(ERROR) << "LineMatching.max_rival_score_ratio must be in (0, 1], got "
               << max_rival_score_ratio;
    ok = false;
  }
  ok &= CheckNonNegative(pose_sigma_t_m, "pose_sigma_t_m");
  ok &= CheckNonNegative(pose_sigma_r_deg, "pose_sigma_r_deg");
  ok &= CheckNonNegative(pose_uncertainty_scale, "pose_uncertainty_scale");
  if (relative_pose_min_inliers < 2) {
    LOG(ERROR) << "LineMatching.relative_pose_min_inliers must be >= 2, got "
               << relative_pose_min_inliers;
    ok = false;
  }
  ok &= CheckPositive(relative_pose_inlier_angle_deg,
                      "relative_pose_inlier_angle_deg");
  ok &= CheckPositive(relative_pose_inlier_distance_m,
                      "relative_pose_inlier_distance_m");
  if (num_visibility_samples < 2) {
    LOG(ERROR) << "LineMatching.num_visibility_samples must be >= 2, got "
               << num_visibility_samples;
    ok = false;
  }
  if (!(min_visible_fraction > 0.0 && min_visible_fraction <= 1.0)) {
    LOG(ERROR) << "LineMatching.min_visible_fraction must be in (0, 1], got "
               << min_visible_fraction;
    ok = false;
  }
  ok &= CheckPositive(min_depth_m, "min_depth_m");
  if (visibility_cell_px < 1) {
    LOG(ERROR) << "LineMatching.visibility_cell_px must be >= 1, got "
               << visibility_cell_px;
    ok = false;
  }
  ok &= CheckNonNegative(visibility_relative_tolerance,
                         "visibility_relative_tolerance");
  ok &= CheckNonNegative(visibility_absolute_tolerance_m,
                         "visibility_absolute_tolerance_m");
  if (min_track_length < 2) {
    LOG(ERROR) << "LineMatching.min_track_length must be >= 2, got "
               << min_track_length;
    ok = false;
  }
  if (!clear.Check()) {
    LOG(ERROR) << "LineMatching.clear_* options are invalid (see above)";
    ok = false;
  }
  return ok;
}

MatchingThresholds EffectiveThresholds(const LineMatchingOptions& options,
                                       const double depth_m,
                                       const double focal_length_px) {
  // Two independent pose errors: the relative pose error has sqrt(2) times
  // the standard deviation of one.
  const double k = options.pose_uncertainty_scale * std::sqrt(2.0);
  const double sigma_r = options.pose_sigma_r_deg * M_PI / 180.0;
  const double sigma_t = options.pose_sigma_t_m;
  const double depth = std::max(depth_m, options.min_depth_m);
  MatchingThresholds thresholds;
  thresholds.theta_deg =
      std::min(90.0, options.t_theta_deg + k * options.pose_sigma_r_deg);
  thresholds.dP_px = options.t_dP_px +
                     k * focal_length_px * (sigma_r + sigma_t / depth);
  thresholds.dO_m = options.t_dO_m + k * (sigma_t + depth * sigma_r);
  thresholds.LBD = options.t_LBD;
  thresholds.visibility_absolute_m =
      options.visibility_absolute_tolerance_m + k * (sigma_t + depth * sigma_r);
  return thresholds;
}

}  // namespace colmap_lidar
