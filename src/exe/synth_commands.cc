// Subcommands about synthetic data: synthesize.
#include <cstdlib>
#include <iostream>
#include <string>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/exe/commands.h"
#include "src/exe/option_manager.h"
#include "src/exe/option_sections.h"
#include "src/synth/synthesize.h"

namespace colmap_lidar {

// Section [Synthesis]; keep configs/synthesize.ini in step.
void AddSynthesisOptions(SynthesisOptions* synth, OptionManager* options) {
  options->AddOption("Synthesis.preset", &synth->preset,
                     "Scene: quad (Newer-College-like 30 x 20 m courtyard) "
                     "| street (80 m street canyon) | corridor (64 m walk down a "
                     "6 m alley) | street_bent (street canyon with a 28 deg "
                     "bend, kerbs, road paint, protruding window frames) | "
                     "square (open 50 x 40 m square, few facades).");
  options->AddOption("Synthesis.num_frames", &synth->num_frames,
                     "Frames (image + LIDAR scan) along the walk, >= 1.");
  options->AddOption("Synthesis.path_fraction", &synth->path_fraction,
                     "Share of the preset's walk path the frames cover, "
                     "from its start, (0, 1]; below 1 gives a short, densely "
                     "sampled walk (small test scenes).");
  options->AddOption("Synthesis.length_factor", &synth->length_factor,
                     "street_bent only: both legs of the street, and the "
                     "walk along them, this many times as long (facades, "
                     "paint, furniture and survey stations follow), >= 1; "
                     "the scale benchmark (scripts/bench_scale.sh).");
  options->AddOption("Synthesis.seed", &synth->seed,
                     "Seed of all noise (trajectory jitter, LIDAR, priors, "
                     "image noise, survey); the scene is fixed per preset.");
  options->AddOption("Synthesis.num_threads", &synth->num_threads,
                     "Worker threads; <= 0 uses all cores.");
  options->AddOption("Synthesis.overwrite", &synth->overwrite,
                     "Replace a non-empty output folder.");
  options->AddOption("Synthesis.image_width", &synth->image_width,
                     "Image width in pixels, >= 8.");
  options->AddOption("Synthesis.image_height", &synth->image_height,
                     "Image height in pixels, >= 8.");
  options->AddOption("Synthesis.horizontal_fov_deg",
                     &synth->horizontal_fov_deg,
                     "Horizontal field of view of the undistorted pinhole "
                     "that gives the focal length f = (width / 2) / "
                     "tan(hfov / 2), degrees in (0, 170).");
  options->AddOption("Synthesis.camera_model", &synth->camera_model,
                     "Camera model, rendered distorted: PINHOLE | "
                     "SIMPLE_RADIAL (k1) | RADIAL (k1, k2) | OPENCV (k1, k2, "
                     "p1, p2); principal point at the image centre.");
  options->AddOption("Synthesis.camera_k1", &synth->camera_k1,
                     "Radial distortion k1 (COLMAP formula on normalised "
                     "coordinates, e.g. -0.3..0.3; < 0 barrel); 0 for "
                     "PINHOLE; must keep the distortion invertible over the "
                     "image.");
  options->AddOption("Synthesis.camera_k2", &synth->camera_k2,
                     "Radial distortion k2 (RADIAL, OPENCV; else 0).");
  options->AddOption("Synthesis.camera_p1", &synth->camera_p1,
                     "Tangential distortion p1 (OPENCV only; else 0).");
  options->AddOption("Synthesis.camera_p2", &synth->camera_p2,
                     "Tangential distortion p2 (OPENCV only; else 0).");
  options->AddOption("Synthesis.supersampling", &synth->supersampling,
                     "Anti-aliasing: supersampling^2 rays per pixel, 1..8.");
  options->AddOption("Synthesis.image_noise_stddev",
                     &synth->image_noise_stddev,
                     "Gaussian image noise, grey levels (of 255), >= 0.");
  options->AddOption("Synthesis.sun_elevation_deg", &synth->sun_elevation_deg,
                     "Sun elevation, degrees in (0, 90].");
  options->AddOption("Synthesis.sun_azimuth_deg", &synth->sun_azimuth_deg,
                     "Sun azimuth from +x towards +y, degrees.");
  options->AddOption("Synthesis.lidar_model", &synth->lidar_model,
                     "LIDAR unit: VLP-16 (16 rings, -15..15 deg, 1800 "
                     "columns) | HDL-32E (32, -30.67..10.67, 2172) | OS1-64 "
                     "(64, -16.6..16.6, 1024) | HDL-64E (64 in two blocks, "
                     "-24.9..-8.87 and -8.33..2, 2048) | OS1-128 (128, "
                     "-22.5..22.5, 1024) | custom (the four lidar_rings.. "
                     "options below, defaults = OS1-64).");
  options->AddOption("Synthesis.lidar_rings", &synth->lidar_rings,
                     "lidar_model custom only: LIDAR beams (rings), "
                     "uniformly over the vertical FOV, >= 1.");
  options->AddOption("Synthesis.lidar_columns", &synth->lidar_columns,
                     "lidar_model custom only: LIDAR azimuth steps per "
                     "revolution, >= 1.");
  options->AddOption("Synthesis.lidar_vertical_fov_min_deg",
                     &synth->lidar_vertical_fov_min_deg,
                     "lidar_model custom only: elevation of the lowest "
                     "beam, degrees in [-90, max).");
  options->AddOption("Synthesis.lidar_vertical_fov_max_deg",
                     &synth->lidar_vertical_fov_max_deg,
                     "lidar_model custom only: elevation of the highest "
                     "beam, degrees in (min, 90].");
  options->AddOption("Synthesis.lidar_range_noise_m",
                     &synth->lidar_range_noise_m,
                     "Std of the Gaussian LIDAR range noise, metres, >= 0 "
                     "(real units: 0.01-0.03).");
  options->AddOption("Synthesis.lidar_dropout_probability",
                     &synth->lidar_dropout_probability,
                     "Probability that a LIDAR return is lost, independently "
                     "per beam (seeded), [0, 1).");
  options->AddOption("Synthesis.lidar_grazing_dropout",
                     &synth->lidar_grazing_dropout,
                     "Extra loss at grazing incidence, [0, 1]: a return is "
                     "kept with probability (1 - dropout_probability) * (1 - "
                     "this * (1 - |cos incidence|)); 0 = off.");
  options->AddOption("Synthesis.lidar_min_range_m", &synth->lidar_min_range_m,
                     "LIDAR returns closer than this are dropped, metres.");
  options->AddOption("Synthesis.lidar_max_range_m", &synth->lidar_max_range_m,
                     "LIDAR returns farther than this are dropped, metres.");
  options->AddOption("Synthesis.prior_translation_sigma_m",
                     &synth->prior_translation_sigma_m,
                     "Prior poses: std of the Gaussian noise per world axis "
                     "on the camera centre, metres.");
  options->AddOption("Synthesis.prior_rotation_sigma_deg",
                     &synth->prior_rotation_sigma_deg,
                     "Prior poses: std of the Gaussian rotation angle about a "
                     "uniformly random axis, degrees in [0, 90].");
  options->AddOption("Synthesis.survey_num_stations",
                     &synth->survey_num_stations,
                     "Survey tripod stations for reference.ply; 0 writes no "
                     "reference.");
  options->AddOption("Synthesis.survey_height_m", &synth->survey_height_m,
                     "Height of the survey scanner above the ground, metres.");
  options->AddOption("Synthesis.survey_angular_step_deg",
                     &synth->survey_angular_step_deg,
                     "Survey azimuth/elevation step, degrees in [0.01, 10].");
  options->AddOption("Synthesis.survey_range_noise_m",
                     &synth->survey_range_noise_m,
                     "Std of the survey range noise, metres, >= 0.");
  options->AddOption("Synthesis.survey_voxel_size_m",
                     &synth->survey_voxel_size_m,
                     "reference.ply keeps one point per voxel of this size, "
                     "metres.");
  options->AddOption("Synthesis.survey_max_points", &synth->survey_max_points,
                     "Random subsample of reference.ply to at most this many "
                     "points.");
  options->AddOption("Synthesis.write_depth_maps", &synth->write_depth_maps,
                     "Write ground_truth/depth_maps/<frame>.bin (COLMAP Mat "
                     "z-depth).");
  options->AddCheck([synth] { return synth->Check(); });
}

int RunSynthesize(int argc, char** argv) {
  std::string output_path;
  SynthesisOptions synthesis_options;

  OptionManager options;
  options.AddRequiredOption("output_path", &output_path,
                            "Dataset folder to create (rig layout of "
                            "docs/dataset-format.md plus ground_truth/).");
  AddSynthesisOptions(&synthesis_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }

  if (ExistsFile(output_path) && !ExistsDir(output_path)) {
    LOG(ERROR) << "--output_path " << output_path << " is a file";
    return EXIT_FAILURE;
  }
  const SynthesisSummary summary =
      SynthesizeDataset(synthesis_options, output_path);
  std::cout << "Synthesised " << summary.num_frames << " frames ("
            << summary.num_lidar_points << " LIDAR points), "
            << summary.num_reference_points << " reference points, "
            << summary.num_crease_edges << " crease edges in "
            << summary.seconds << " s into " << output_path << std::endl;
  return EXIT_SUCCESS;
}

}  // namespace colmap_lidar
