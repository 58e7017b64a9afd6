// Options of the synthetic camera + LIDAR dataset generator (issue 3): the
// scene preset, the rig (by default a PINHOLE camera like the Intel
// RealSense D435i of the Newer College Dataset and an Ouster-OS1-64-like
// LIDAR; optionally radial/tangential distortion and other LIDAR units), the
// trajectory, the noise models and the survey that gives reference.ply.
//
// Prior-pose noise model (Amblard et al., Sec. IV-A: "random translational
// (Sigma_T = 0.5 m) and rotational noise (Sigma_R = 5 deg)"; the paper does
// not spell out the distribution, so we fix it as follows). For each frame,
// independently, with the camera pose world_from_cam = (R, c):
//   c_prior = c + e,  e ~ N(0, prior_translation_sigma_m^2 * I_3)
//     (independent Gaussian noise per world axis x, y, z);
//   R_prior = Exp(theta * a) * R,  a uniform on the unit sphere,
//     theta ~ N(0, (prior_rotation_sigma_deg * pi / 180)^2)
//     (a rotation about a uniformly random axis through the camera centre,
//     expressed in the world frame, with a zero-mean Gaussian angle).
// Hence E[|e|^2] = 3 sigma_T^2 and E[theta^2] = sigma_R^2.
#pragma once

#include <string>

namespace colmap_lidar {

struct SynthesisOptions {
  // Scene preset: "quad" (Newer-College-like courtyard, 30 x 20 m, enclosed
  // by buildings), "street" (a straight 12 m wide street canyon),
  // "corridor" (a 6 m wide alley walked straight down the middle),
  // "street_bent" (a street canyon with a 28 deg bend, kerbs, road paint,
  // protruding window frames) or "square" (an open 50 x 40 m square with
  // few facades); scene_presets.h.
  std::string preset = "quad";
  // Number of frames (image + scan) along the trajectory.
  int num_frames = 60;
  // Share of the preset's walk path covered by the frames, from its start,
  // in (0, 1]. Below 1 the path is walked as an open path up to that arc
  // length: fewer frames then still overlap (small test scenes).
  double path_fraction = 1.0;
  // street_bent only: both legs of the street, and the walk along them,
  // this many times as long (scene_presets.h), >= 1; num_frames then
  // samples the longer walk (the scale benchmark, issue 19: 60 frames at
  // 1, 200 at 200 / 60). Other presets take 1 only.
  double length_factor = 1.0;
  // Seed of every random quantity (trajectory jitter, LIDAR, prior noise,
  // image noise, survey). The scene geometry itself is fixed per preset.
  int seed = 0;
  // Worker threads; <= 0 uses all cores.
  int num_threads = -1;
  // Replace an existing non-empty output folder.
  bool overwrite = false;

  // Camera: principal point at the image centre, square pixels, focal
  // length from horizontal_fov_deg (that of the undistorted pinhole;
  // distortion then widens (k1 < 0) or narrows (k1 > 0) the real field of
  // view). Sizes from 640 x 480 to 1280 x 720 are the benchmark's.
  int image_width = 848;
  int image_height = 480;
  // Horizontal field of view in degrees, (0, 170).
  double horizontal_fov_deg = 90.0;
  // COLMAP camera model: "PINHOLE" (no distortion), "SIMPLE_RADIAL" (k1),
  // "RADIAL" (k1, k2) or "OPENCV" (k1, k2, p1, p2; fx = fy). Coefficients a
  // model does not have must stay 0. The image is rendered DISTORTED (each
  // ray is the model's undistortion of its pixel sample).
  std::string camera_model = "PINHOLE";
  // Radial and tangential coefficients on normalised coordinates (COLMAP's
  // formulas, camera_models.h). Check() requires the distortion to be
  // invertible (monotonic in the radius) over the whole image.
  double camera_k1 = 0.0;
  double camera_k2 = 0.0;
  double camera_p1 = 0.0;
  double camera_p2 = 0.0;
  // Rays per pixel = supersampling^2 (box-filter anti-aliasing), >= 1.
  int supersampling = 3;
  // Gaussian sensor noise added to the 8-bit image, in grey levels.
  double image_noise_stddev = 1.0;
  // Sun elevation and azimuth (from +x towards +y) in degrees.
  double sun_elevation_deg = 40.0;
  double sun_azimuth_deg = 35.0;

  // LIDAR unit: "VLP-16", "HDL-32E", "OS1-64", "HDL-64E", "OS1-128" (ring
  // elevations and column counts of the real units, lidar_simulator.h
  // LidarModelGeometry) or "custom": lidar_rings rings uniformly spaced over
  // [lidar_vertical_fov_min_deg, _max_deg] and lidar_columns columns, whose
  // defaults are the OS1-64's (so "custom" and "OS1-64" give identical
  // scans by default). With a named model the four custom fields must keep
  // their defaults (Check() fails otherwise instead of ignoring them).
  std::string lidar_model = "custom";
  int lidar_rings = 64;
  int lidar_columns = 1024;
  double lidar_vertical_fov_min_deg = -16.6;
  double lidar_vertical_fov_max_deg = 16.6;
  // Standard deviation of the Gaussian range noise, metres (>= 0).
  double lidar_range_noise_m = 0.015;
  // Probability, in [0, 1), that a return is lost (dark or specular
  // surfaces), independently per beam, seeded by (seed, frame, beam).
  double lidar_dropout_probability = 0.0;
  // Extra loss at grazing incidence, in [0, 1]: a return survives the
  // dropout with probability (1 - lidar_dropout_probability) *
  // (1 - lidar_grazing_dropout * (1 - |cos incidence|)); 0 disables it.
  double lidar_grazing_dropout = 0.0;
  // Returns closer than min or farther than max range are dropped, metres.
  double lidar_min_range_m = 0.5;
  double lidar_max_range_m = 100.0;

  // Prior-pose noise (see the model above).
  double prior_translation_sigma_m = 0.5;
  double prior_rotation_sigma_deg = 5.0;

  // Survey (reference.ply): tripod stations inside the scene at
  // survey_height_m, spherical scans with this angular step, Gaussian range
  // noise, then one point per voxel of survey_voxel_size_m, at most
  // survey_max_points (random subsample beyond).
  int survey_num_stations = 4;
  double survey_height_m = 1.5;
  double survey_angular_step_deg = 0.1;
  double survey_range_noise_m = 0.002;
  double survey_voxel_size_m = 0.02;
  int survey_max_points = 3000000;

  // Also write ground_truth/depth_maps/<frame>.bin.
  bool write_depth_maps = true;

  bool Check() const;
};

}  // namespace colmap_lidar
