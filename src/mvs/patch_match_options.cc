#include "src/mvs/patch_match_options.h"

#include <cmath>

#include <glog/logging.h>

namespace colmap_lidar {
namespace {

bool Fail(const char* message) {
  LOG(ERROR) << "LidarPatchMatch." << message;
  return false;
}

}  // namespace

bool LidarPatchMatchOptions::Check() const {
  if (init != "lidar" && init != "random") {
    return Fail("init must be 'lidar' or 'random'");
  }
  if (max_num_src_images < 1 || max_num_src_images > 64) {
    return Fail("max_num_src_images must be in [1, 64]");
  }
  if (!(min_triangulation_angle_deg >= 0)) {
    return Fail("min_triangulation_angle_deg must be >= 0");
  }
  if (!(lidar_covisibility_weight >= 0)) {
    return Fail("lidar_covisibility_weight must be >= 0");
  }
  if (num_iterations < 1) return Fail("num_iterations must be >= 1");
  if (num_geom_iterations < 1) return Fail("num_geom_iterations must be >= 1");
  if (!(geom_consistency_regularizer >= 0)) {
    return Fail("geom_consistency_regularizer must be >= 0");
  }
  if (!(geom_consistency_max_cost > 0)) {
    return Fail("geom_consistency_max_cost must be > 0");
  }
  if (window_radius < 1) return Fail("window_radius must be >= 1");
  if (window_step < 1) return Fail("window_step must be >= 1");
  if (!(sigma_color > 0)) return Fail("sigma_color must be > 0");
  if (!(best_views_fraction > 0 && best_views_fraction <= 1)) {
    return Fail("best_views_fraction must be in (0, 1]");
  }
  if (!(lidar_prior_weight >= 0)) return Fail("lidar_prior_weight must be >= 0");
  if (!(lidar_prior_tolerance > 0)) {
    return Fail("lidar_prior_tolerance must be > 0");
  }
  if (occlusion_window_radius < 0) {
    return Fail("occlusion_window_radius must be >= 0");
  }
  if (!(lidar_own_scan_min_incidence_deg >= 0 &&
        lidar_own_scan_min_incidence_deg <= 90)) {
    return Fail("lidar_own_scan_min_incidence_deg must be in [0, 90]");
  }
  if (!(occlusion_relative_tolerance >= 0)) {
    return Fail("occlusion_relative_tolerance must be >= 0");
  }
  if (!(interpolation_max_edge_factor >= 0) ||
      !std::isfinite(interpolation_max_edge_factor)) {
    return Fail("interpolation_max_edge_factor must be >= 0");
  }
  if (!(interpolation_max_depth_ratio > 1)) {
    return Fail("interpolation_max_depth_ratio must be > 1");
  }
  if (!(min_depth > 0)) return Fail("min_depth must be > 0");
  if (!(filter_max_cost > 0 && filter_max_cost <= 2)) {
    return Fail("filter_max_cost must be in (0, 2]");
  }
  if (filter_min_num_consistent < 0) {
    return Fail("filter_min_num_consistent must be >= 0");
  }
  if (!(filter_max_reproj_error > 0)) {
    return Fail("filter_max_reproj_error must be > 0");
  }
  if (!(filter_max_relative_depth_error > 0)) {
    return Fail("filter_max_relative_depth_error must be > 0");
  }
  if (!(filter_lidar_max_relative_depth_error > 0)) {
    return Fail("filter_lidar_max_relative_depth_error must be > 0");
  }
  return true;
}

}  // namespace colmap_lidar
