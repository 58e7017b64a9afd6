// Option and summary parts of line_bundle_adjustment.h: loss and gauge
// names, LineBundleAdjustmentOptions::Check, the summary's text.
#include "src/optim/line_bundle_adjustment.h"

#include <sstream>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

LineBALossType LineBALossTypeFromName(const std::string& name) {
  if (name == "TRIVIAL") return LineBALossType::kTrivial;
  if (name == "HUBER") return LineBALossType::kHuber;
  if (name == "SOFT_L1") return LineBALossType::kSoftL1;
  if (name == "CAUCHY") return LineBALossType::kCauchy;
  THROW_ERROR("Unknown loss type '" << name
                                    << "' (TRIVIAL, HUBER, SOFT_L1, CAUCHY)");
}

std::string LineBALossTypeName(LineBALossType loss_type) {
  switch (loss_type) {
    case LineBALossType::kTrivial:
      return "TRIVIAL";
    case LineBALossType::kHuber:
      return "HUBER";
    case LineBALossType::kSoftL1:
      return "SOFT_L1";
    case LineBALossType::kCauchy:
      return "CAUCHY";
  }
  return "INVALID";
}

LineBAGauge LineBAGaugeFromName(const std::string& name) {
  if (name == "FIX_FIRST_POSE") return LineBAGauge::kFixFirstPose;
  if (name == "POSE_PRIORS") return LineBAGauge::kPosePriors;
  THROW_ERROR("Unknown gauge '" << name << "' (FIX_FIRST_POSE, POSE_PRIORS)");
}

std::string LineBAGaugeName(LineBAGauge gauge) {
  switch (gauge) {
    case LineBAGauge::kFixFirstPose:
      return "FIX_FIRST_POSE";
    case LineBAGauge::kPosePriors:
      return "POSE_PRIORS";
  }
  return "INVALID";
}

bool LineBundleAdjustmentOptions::Check() const {
#define LINE_BA_CHECK(condition, option)                                 \
  if (!(condition)) {                                                    \
    LOG(ERROR) << "Invalid LineBundleAdjustmentOptions." << #option      \
               << ": must satisfy " << #condition;                       \
    return false;                                                        \
  }
  LINE_BA_CHECK(lambda_R >= 0.0, lambda_R);
  LINE_BA_CHECK(lambda_L >= 0.0, lambda_L);
  LINE_BA_CHECK(lambda_lidar >= 0.0, lambda_lidar);
  LINE_BA_CHECK(lambda_R > 0.0 || lambda_L > 0.0 || lambda_lidar > 0.0,
                lambda_R);
  LINE_BA_CHECK(lidar_sigma_m > 0.0, lidar_sigma_m);
  LINE_BA_CHECK(point_loss_scale > 0.0, point_loss_scale);
  LINE_BA_CHECK(line_loss_scale > 0.0, line_loss_scale);
  LINE_BA_CHECK(lidar_loss_scale > 0.0, lidar_loss_scale);
  LINE_BA_CHECK(lidar_edge_weight >= 0.0, lidar_edge_weight);
  LINE_BA_CHECK(lidar_edge_loss_scale > 0.0, lidar_edge_loss_scale);
  LINE_BA_CHECK(lidar_point_weight >= 0.0, lidar_point_weight);
  LINE_BA_CHECK(lidar_point_loss_scale > 0.0, lidar_point_loss_scale);
  LINE_BA_CHECK(prior_position_sigma_m >= 0.0, prior_position_sigma_m);
  LINE_BA_CHECK(prior_rotation_sigma_deg >= 0.0, prior_rotation_sigma_deg);
  LINE_BA_CHECK((prior_position_sigma_m > 0.0) ==
                    (prior_rotation_sigma_deg > 0.0),
                prior_rotation_sigma_deg);
  LINE_BA_CHECK(gauge != LineBAGauge::kPosePriors || prior_position_sigma_m > 0.0,
                gauge);
  LINE_BA_CHECK(min_point_track_length >= 1, min_point_track_length);
  LINE_BA_CHECK(retriangulation_max_error_px >= 0.0,
                retriangulation_max_error_px);
  LINE_BA_CHECK(min_constraints_per_image >= 0, min_constraints_per_image);
  LINE_BA_CHECK(max_num_iterations >= 0, max_num_iterations);
  LINE_BA_CHECK(function_tolerance >= 0.0, function_tolerance);
  LINE_BA_CHECK(gradient_tolerance >= 0.0, gradient_tolerance);
  LINE_BA_CHECK(parameter_tolerance >= 0.0, parameter_tolerance);
  LINE_BA_CHECK(num_threads == -1 || num_threads >= 1, num_threads);
#undef LINE_BA_CHECK
  return true;
}

std::string LineBundleAdjustmentSummary::ToString() const {
  std::ostringstream stream;
  stream << "images " << num_images << " (" << num_fixed_images << " fixed, "
         << unconstrained_image_ids.size() << " unconstrained), points "
         << num_points << ", lines " << num_lines << " (" << num_skipped_lines
         << " skipped); residuals: point " << num_point_residuals << ", line "
         << num_line_residuals << ", lidar " << num_lidar_residuals
         << ", prior " << num_pose_prior_residuals << ", lidar edge "
         << num_lidar_edge_residuals << ", lidar point "
         << num_lidar_point_residuals << "; cost " << initial_cost << " -> "
         << final_cost << " in " << num_iterations << " iterations, "
         << solve_time_s << " s, " << num_retriangulated_points
         << " points re-triangulated; mean point error " << mean_point_error_px
         << " px, mean line error " << mean_line_error_px
         << " px, rms lidar distance " << rms_lidar_distance_m
         << " m, mean whitened lidar edge error " << mean_lidar_edge_error
         << ", rms lidar point distance " << rms_lidar_point_distance_m << " m";
  return stream.str();
}

}  // namespace colmap_lidar
