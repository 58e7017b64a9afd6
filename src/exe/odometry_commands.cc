// Subcommand lidar_odometry: prior poses from LIDAR odometry for a
// workspace whose recording has none (src/lidar/lidar_prior_poses.h).
#include <cstdlib>
#include <iostream>
#include <string>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/exe/commands.h"
#include "src/exe/option_manager.h"
#include "src/lidar/lidar_prior_poses.h"

namespace colmap_lidar {
namespace {

// Section [LidarOdometry]; keep configs/lidar_odometry.ini in step.
void AddLidarOdometryOptions(LidarOdometryOptions* o,
                             LidarPriorPosesOptions* p,
                             OptionManager* options) {
  const std::string s = "LidarOdometry.";
  options->AddOption(s + "method", &o->method,
                     "Registration: gicp (Generalized-ICP) | ndt.");
  options->AddOption(s + "voxel_size_m", &o->voxel_size_m,
                     "Voxel grid that downsamples each scan, metres, > 0.");
  options->AddOption(s + "min_range_m", &o->min_range_m,
                     "Points nearer to the sensor are dropped, metres, >= 0.");
  options->AddOption(s + "max_range_m", &o->max_range_m,
                     "Points farther from the sensor are dropped, metres.");
  options->AddOption(s + "local_map_num_scans", &o->local_map_num_scans,
                     "Local map: the last K registered scans, >= 1.");
  options->AddOption(s + "max_correspondence_distance_m",
                     &o->max_correspondence_distance_m,
                     "Correspondence and overlap distance, metres, > 0.");
  options->AddOption(s + "max_iterations", &o->max_iterations,
                     "Registration iterations at most, >= 1.");
  options->AddOption(s + "transformation_epsilon",
                     &o->transformation_epsilon,
                     "Convergence: pose update below this (metres / "
                     "radians), > 0.");
  options->AddOption(s + "gicp_num_neighbors", &o->gicp_num_neighbors,
                     "GICP: neighbours per point covariance, >= 3.");
  options->AddOption(s + "ndt_resolution_m", &o->ndt_resolution_m,
                     "NDT: cell size, metres, > 0.");
  options->AddOption(s + "ndt_step_size", &o->ndt_step_size,
                     "NDT: maximum line-search step, > 0.");
  options->AddOption(s + "min_overlap", &o->min_overlap,
                     "Registration fails below this fraction of scan points "
                     "near the map, [0, 1].");
  options->AddOption(s + "abort_on_failure", &o->abort_on_failure,
                     "On a failed registration: 1 stop with an error, 0 warn "
                     "and keep the constant-velocity prediction.");
  options->AddOption(s + "num_threads", &o->num_threads,
                     "Threads; <= 0: all cores.");
  options->AddOption(s + "overwrite_priors", &p->overwrite_priors,
                     "Replace existing priors; 0: only images without a "
                     "prior get one.");
  options->AddCheck([o, p] { return o->Check() && p->Check(); });
}

}  // namespace

int RunLidarOdometryCommand(int argc, char** argv) {
  std::string database_path;
  std::string output_path;
  LidarOdometryOptions odometry_options;
  LidarPriorPosesOptions prior_options;
  OptionManager options;
  options.AddRequiredOption("database_path", &database_path,
                            "COLMAP database with ext_lidar_scans (from "
                            "lidar_importer); receives the prior poses.");
  options.AddRequiredOption("output_path", &output_path,
                            "Folder for a sparse model with the odometry "
                            "poses and no points (e.g. sparse/prior); "
                            "replaced if it holds a model.");
  AddLidarOdometryOptions(&odometry_options, &prior_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (!ExistsFile(database_path)) {
    LOG(ERROR) << "--database_path " << database_path << " does not exist";
    return EXIT_FAILURE;
  }
  const LidarPriorPosesSummary summary = RunLidarOdometryPriors(
      database_path, output_path, odometry_options, prior_options);
  std::cout << "LIDAR odometry: " << summary.poses.size() << " frames, "
            << summary.trajectory_length_m << " m travelled, "
            << summary.num_priors_written << " priors written, "
            << summary.num_priors_kept << " kept, "
            << summary.num_images_without_scan << " images without scan, "
            << summary.num_failed_registrations << " failed registrations, "
            << summary.seconds << " s" << std::endl;
  return EXIT_SUCCESS;
}

}  // namespace colmap_lidar
