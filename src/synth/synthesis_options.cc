#include "src/synth/synthesis_options.h"

#include <cmath>

#include <glog/logging.h>

#include "src/synth/lidar_simulator.h"
#include "src/synth/scene_presets.h"
#include "src/synth/synthesize.h"

namespace colmap_lidar {

#define SYNTH_CHECK_OPTION(condition)                                  \
  if (!(condition)) {                                                  \
    LOG(ERROR) << "Invalid Synthesis option: check failed: " #condition; \
    return false;                                                      \
  }

bool SynthesisOptions::Check() const {
  if (!IsKnownScenePreset(preset)) {
    LOG(ERROR) << "Synthesis.preset must be " << ScenePresetNamesText()
               << ", got '" << preset << "'";
    return false;
  }
  SYNTH_CHECK_OPTION(num_frames >= 1);
  SYNTH_CHECK_OPTION(path_fraction > 0.0 && path_fraction <= 1.0);
  SYNTH_CHECK_OPTION(std::isfinite(length_factor) && length_factor >= 1.0);
  if (length_factor != 1.0 && preset != "street_bent") {
    LOG(ERROR) << "Synthesis.length_factor must be 1 for the preset '"
               << preset << "' (only street_bent can be made longer)";
    return false;
  }
  SYNTH_CHECK_OPTION(image_width >= 8 && image_height >= 8);
  SYNTH_CHECK_OPTION(horizontal_fov_deg > 0.0 && horizontal_fov_deg < 170.0);
  SYNTH_CHECK_OPTION(supersampling >= 1 && supersampling <= 8);
  const std::string camera_problem = SynthCameraProblem(*this);
  if (!camera_problem.empty()) {
    LOG(ERROR) << "Invalid Synthesis option: " << camera_problem;
    return false;
  }
  SYNTH_CHECK_OPTION(image_noise_stddev >= 0.0);
  SYNTH_CHECK_OPTION(sun_elevation_deg > 0.0 && sun_elevation_deg <= 90.0);
  if (!IsKnownLidarModel(lidar_model)) {
    LOG(ERROR) << "Synthesis.lidar_model must be one of " << LidarModelNames()
               << ", got '" << lidar_model << "'";
    return false;
  }
  if (lidar_model != "custom") {
    const SynthesisOptions defaults;
    if (lidar_rings != defaults.lidar_rings ||
        lidar_columns != defaults.lidar_columns ||
        lidar_vertical_fov_min_deg != defaults.lidar_vertical_fov_min_deg ||
        lidar_vertical_fov_max_deg != defaults.lidar_vertical_fov_max_deg) {
      LOG(ERROR) << "Synthesis.lidar_rings / lidar_columns / "
                    "lidar_vertical_fov_min_deg / _max_deg only apply to "
                    "--Synthesis.lidar_model custom; lidar_model "
                 << lidar_model << " has its own layout (got rings "
                 << lidar_rings << ", columns " << lidar_columns
                 << ", vertical FOV [" << lidar_vertical_fov_min_deg << ", "
                 << lidar_vertical_fov_max_deg << "] deg)";
      return false;
    }
  }
  SYNTH_CHECK_OPTION(lidar_rings >= 1 && lidar_columns >= 1);
  SYNTH_CHECK_OPTION(lidar_vertical_fov_min_deg >= -90.0 &&
                     lidar_vertical_fov_max_deg <= 90.0 &&
                     lidar_vertical_fov_min_deg < lidar_vertical_fov_max_deg);
  SYNTH_CHECK_OPTION(lidar_range_noise_m >= 0.0);
  SYNTH_CHECK_OPTION(lidar_dropout_probability >= 0.0 &&
                     lidar_dropout_probability < 1.0);
  SYNTH_CHECK_OPTION(lidar_grazing_dropout >= 0.0 &&
                     lidar_grazing_dropout <= 1.0);
  SYNTH_CHECK_OPTION(lidar_min_range_m >= 0.0 &&
                     lidar_min_range_m < lidar_max_range_m);
  SYNTH_CHECK_OPTION(prior_translation_sigma_m >= 0.0);
  SYNTH_CHECK_OPTION(prior_rotation_sigma_deg >= 0.0 &&
                     prior_rotation_sigma_deg <= 90.0);
  SYNTH_CHECK_OPTION(survey_num_stations >= 0);
  SYNTH_CHECK_OPTION(survey_height_m > 0.0);
  SYNTH_CHECK_OPTION(survey_angular_step_deg >= 0.01 &&
                     survey_angular_step_deg <= 10.0);
  SYNTH_CHECK_OPTION(survey_range_noise_m >= 0.0);
  SYNTH_CHECK_OPTION(survey_voxel_size_m > 0.0);
  SYNTH_CHECK_OPTION(survey_max_points >= 1);
  return true;
}

#undef SYNTH_CHECK_OPTION

}  // namespace colmap_lidar
