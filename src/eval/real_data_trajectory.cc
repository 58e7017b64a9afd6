// The refined trajectory against LIDAR odometry (see real_data_evaluator.h).
#include "src/eval/real_data_evaluator.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

double TrajectoryLength(const std::vector<Eigen::Vector3d>& centres) {
  double length = 0.0;
  for (size_t i = 1; i < centres.size(); ++i) {
    length += (centres[i] - centres[i - 1]).norm();
  }
  return length;
}

}  // namespace

TrajectoryComparison CompareTrajectoryWithOdometry(
    const std::vector<RealDataFrame>& frames,
    const RealDataEvaluationOptions& options) {
  THROW_CHECK(options.Check(), "invalid RealDataEvaluation options");
  THROW_CHECK(frames.size() >= 2,
              "Trajectory comparison needs >= 2 frames, got " << frames.size());
  ScanRegistrationOptions registration = options.registration;
  registration.num_threads = options.num_threads;
  THROW_CHECK(frames[0].scan != nullptr, "frame " << frames[0].name
                                                  << " has no scan");
  const double voxel_m = VoxelSizeForScan(*frames[0].scan, registration);
  std::vector<std::unique_ptr<PreparedScan>> scans;
  for (const RealDataFrame& frame : frames) {
    THROW_CHECK(frame.scan != nullptr, "frame " << frame.name
                                                << " has no scan");
    try {
      scans.push_back(
          std::make_unique<PreparedScan>(*frame.scan, registration, voxel_m));
    } catch (const Error& error) {
      THROW_ERROR("Odometry of frame " << frame.name << ": " << error.what());
    }
  }

  TrajectoryComparison result;
  std::vector<Eigen::Vector3d> refined_centres;
  std::vector<Eigen::Vector3d> prior_centres;
  for (const RealDataFrame& frame : frames) {
    refined_centres.push_back(frame.refined_world_from_lidar.translation);
    if (frame.has_prior) {
      prior_centres.push_back(frame.prior_world_from_lidar.translation);
    }
  }
  Rigid3d previous_step;
  result.odometry_world_from_lidar.push_back(
      frames[0].refined_world_from_lidar);
  for (size_t i = 0; i + 1 < frames.size(); ++i) {
    // lidar_i_from_lidar_{i+1} guesses: the priors' (independent of the
    // refined poses), constant velocity; standing still only without
    // priors (see the file comment).
    std::vector<Rigid3d> guesses;
    if (frames[i].has_prior && frames[i + 1].has_prior) {
      guesses.push_back(frames[i].prior_world_from_lidar.Inverse() *
                        frames[i + 1].prior_world_from_lidar);
    }
    if (i > 0) {
      guesses.push_back(previous_step);
    }
    if (guesses.empty()) {
      guesses.push_back(Rigid3d());
    }
    const ScanRegistrationResult registered =
        RegisterScans(*scans[i + 1], *scans[i], guesses, registration);
    previous_step = registered.target_from_source;
    result.odometry_world_from_lidar.push_back(
        result.odometry_world_from_lidar.back() * previous_step);
    const double odometry_step = registered.target_from_source.translation.norm();
    const double refined_step =
        (refined_centres[i + 1] - refined_centres[i]).norm();
    result.step_frames.push_back(frames[i].name);
    result.odometry_steps_m.push_back(odometry_step);
    result.refined_steps_m.push_back(refined_step);
    result.fitness.push_back(registered.fitness);
    result.odometry_length_m += odometry_step;
    result.refined_length_m += refined_step;
    result.min_fitness = std::min(result.min_fitness, registered.fitness);
    if (registered.fitness < options.min_fitness) {
      ++result.num_failed_registrations;
      LOG(WARNING) << "real data evaluation: odometry " << frames[i].name
                   << " -> " << frames[i + 1].name << " has fitness "
                   << registered.fitness << " < " << options.min_fitness;
    }
    const double difference = std::abs(refined_step - odometry_step);
    if (difference > result.max_step_difference_m ||
        result.max_step_difference_frame.empty()) {
      result.max_step_difference_m = difference;
      result.max_step_difference_frame = frames[i].name;
    }
  }
  result.num_steps = frames.size() - 1;
  result.prior_length_m = TrajectoryLength(prior_centres);
  result.length_ratio = result.odometry_length_m > 0.0
                            ? result.refined_length_m / result.odometry_length_m
                            : 0.0;
  return result;
}

}  // namespace colmap_lidar
