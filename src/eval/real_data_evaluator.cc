// The parts of real_data_evaluator.h: crispness in real_data_crispness.cc,
// the trajectory against LIDAR odometry in real_data_trajectory.cc, the mesh
// against the LIDAR points in real_data_mesh_vs_lidar.cc; here the options,
// the evaluation of a workspace and its JSON and text reports.
#include "src/eval/real_data_evaluator.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iomanip>
#include <memory>
#include <sstream>

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "src/eval/eval_stats.h"
#include "src/eval/mesh_sampling.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {

// "lidar_within_0.1m": the shortest text that reads back to the threshold.
std::string ThresholdKey(const std::string& prefix, double threshold_m) {
  char buffer[64];
  const std::to_chars_result result =
      std::to_chars(buffer, buffer + sizeof(buffer), threshold_m);
  return prefix + std::string(buffer, result.ptr) + "m";
}

void AddCrispness(const std::string& prefix, const CrispnessStats& stats,
                  Json* json) {
  (*json)[prefix + "_median_m"] = stats.median_m;
  (*json)[prefix + "_p90_m"] = stats.p90_m;
  (*json)[prefix + "_coverage"] = stats.coverage;
  (*json)[prefix + "_num_planes"] = stats.num_planes;
  (*json)[prefix + "_frame_median_m"] = stats.frame_median_m;
}

}  // namespace

bool RealDataEvaluationOptions::Check() const {
#define REAL_DATA_CHECK(condition, field)                                 \
  if (!(condition)) {                                                     \
    LOG(ERROR) << "RealDataEvaluation." #field " = " << (field)           \
               << " is out of range (" #condition ")";                    \
    return false;                                                         \
  }
  REAL_DATA_CHECK(crispness_voxel_size_m >= 0.0, crispness_voxel_size_m);
  REAL_DATA_CHECK(crispness_voxel_angle_deg > 0.0, crispness_voxel_angle_deg);
  REAL_DATA_CHECK(crispness_radius_voxels > 1.0, crispness_radius_voxels);
  REAL_DATA_CHECK(crispness_min_neighbors >= 3, crispness_min_neighbors);
  REAL_DATA_CHECK(
      crispness_min_planarity >= 0.0 && crispness_min_planarity <= 1.0,
      crispness_min_planarity);
  REAL_DATA_CHECK(crispness_max_queries_per_scan >= 1,
                  crispness_max_queries_per_scan);
  REAL_DATA_CHECK(min_fitness >= 0.0 && min_fitness <= 1.0, min_fitness);
  REAL_DATA_CHECK(mesh_sample_density_per_m2 > 0.0,
                  mesh_sample_density_per_m2);
  REAL_DATA_CHECK(max_mesh_samples >= 1000, max_mesh_samples);
  REAL_DATA_CHECK(mesh_view_max_depth_m > 0.0 &&
                      std::isfinite(mesh_view_max_depth_m),
                  mesh_view_max_depth_m);
#undef REAL_DATA_CHECK
  if (!registration.Check()) {
    return false;
  }
  return CheckThresholds(mesh_thresholds_m,
                         "RealDataEvaluation.mesh_thresholds_m");
}

RealDataEvaluation EvaluateRealDataFrames(
    const std::vector<RealDataFrame>& frames,
    const RealDataEvaluationOptions& options) {
  THROW_CHECK(options.Check(), "invalid RealDataEvaluation options");
  THROW_CHECK(frames.size() >= 2,
              "Real-data evaluation needs >= 2 frames with a scan, got "
                  << frames.size());
  RealDataEvaluation evaluation;
  evaluation.num_frames = frames.size();
  evaluation.crispness_voxel_size_m = CrispnessVoxelSize(*frames[0].scan,
                                                         options);
  evaluation.crispness_radius_m =
      options.crispness_radius_voxels * evaluation.crispness_voxel_size_m;
  std::vector<std::vector<Eigen::Vector3d>> thinned;
  std::vector<Rigid3d> refined;
  std::vector<Rigid3d> prior;
  evaluation.has_prior = true;
  for (const RealDataFrame& frame : frames) {
    thinned.push_back(
        ThinScan(*frame.scan, evaluation.crispness_voxel_size_m, options));
    refined.push_back(frame.refined_world_from_lidar);
    prior.push_back(frame.prior_world_from_lidar);
    evaluation.has_prior = evaluation.has_prior && frame.has_prior;
  }
  evaluation.refined_crispness = EvaluateCrispness(
      thinned, refined, evaluation.crispness_radius_m, options);
  if (evaluation.has_prior) {
    evaluation.prior_crispness = EvaluateCrispness(
        thinned, prior, evaluation.crispness_radius_m, options);
  }
  evaluation.trajectory = CompareTrajectoryWithOdometry(frames, options);
  evaluation.has_trajectory = true;
  evaluation.odometry_crispness =
      EvaluateCrispness(thinned, evaluation.trajectory.odometry_world_from_lidar,
                        evaluation.crispness_radius_m, options);
  return evaluation;
}

RealDataEvaluation EvaluateRealData(const RealDataEvaluationInput& input,
                                    const RealDataEvaluationOptions& options) {
  THROW_CHECK(options.Check(), "invalid RealDataEvaluation options");
  CheckFileExists(input.database_path, "Database");
  THROW_CHECK(ExistsModel(input.refined_model_path),
              "No refined model in " << input.refined_model_path);
  const Reconstruction refined = ReadReconstruction(input.refined_model_path);
  std::unique_ptr<Reconstruction> prior;
  if (!input.prior_model_path.empty() && ExistsModel(input.prior_model_path)) {
    prior = std::make_unique<Reconstruction>(
        ReadReconstruction(input.prior_model_path));
  }
  const Database database(input.database_path);

  std::vector<const Image*> images;
  for (const Image& image : refined.images) {
    images.push_back(&image);
  }
  std::sort(images.begin(), images.end(),
            [](const Image* a, const Image* b) { return a->name < b->name; });
  std::vector<LidarScan> scans;
  std::vector<RealDataFrame> frames;
  scans.reserve(images.size());
  for (const Image* image : images) {
    const std::optional<DatabaseImage> db_image =
        database.ReadImageWithName(image->name);
    if (!db_image) {
      continue;
    }
    const std::optional<LidarScanRecord> record =
        database.ReadLidarScan(db_image->image_id);
    if (!record) {
      continue;
    }
    scans.push_back(ReadLidarScan(
        LidarScanFilePath(input.database_path, record->path)));
    RealDataFrame frame;
    frame.name = image->name;
    frame.refined_world_from_lidar =
        image->cam_from_world.Inverse() * record->cam_from_lidar;
    const Image* prior_image =
        prior != nullptr ? prior->FindImageByName(image->name) : nullptr;
    if (prior_image != nullptr) {
      frame.has_prior = true;
      frame.prior_world_from_lidar =
          prior_image->cam_from_world.Inverse() * record->cam_from_lidar;
    }
    frames.push_back(frame);
  }
  THROW_CHECK(frames.size() >= 2,
              "Real-data evaluation: " << frames.size()
                                       << " images of the refined model "
                                       << input.refined_model_path
                                       << " have a LIDAR scan in "
                                       << input.database_path << ", need 2");
  for (size_t i = 0; i < frames.size(); ++i) {
    frames[i].scan = &scans[i];
  }
  RealDataEvaluation evaluation = EvaluateRealDataFrames(frames, options);

  if (!input.mesh_path.empty() && ExistsFile(input.mesh_path) &&
      !input.lidar_cloud_path.empty() && ExistsFile(input.lidar_cloud_path)) {
    const PlyData mesh = ReadPly(input.mesh_path);
    const std::vector<Eigen::Vector3d> vertices =
        mesh.Positions(input.mesh_path);
    const std::vector<Eigen::Vector3i> triangles =
        TriangulatePolygons(mesh.faces, vertices.size(), input.mesh_path);
    const std::vector<Eigen::Vector3d> lidar_points =
        ReadPly(input.lidar_cloud_path).Positions(input.lidar_cloud_path);
    if (triangles.empty() || lidar_points.empty()) {
      LOG(WARNING) << "real data evaluation: " << input.mesh_path << " ("
                   << triangles.size() << " triangles) or "
                   << input.lidar_cloud_path << " (" << lidar_points.size()
                   << " points) is empty; no mesh figures";
    } else {
      evaluation.mesh_vs_lidar = EvaluateMeshVsLidar(
          vertices, triangles, lidar_points, options,
          InCameraView(refined, lidar_points,
                       options.mesh_view_max_depth_m));
      evaluation.has_mesh = true;
    }
  }
  LOG(INFO) << "real data evaluation: " << FormatRealDataEvaluation(evaluation);
  return evaluation;
}

void WriteRealDataJson(const std::string& path,
                       const RealDataEvaluation& evaluation) {
  Json json;
  json["num_frames"] = evaluation.num_frames;
  Json crispness;
  crispness["voxel_size_m"] = evaluation.crispness_voxel_size_m;
  crispness["radius_m"] = evaluation.crispness_radius_m;
  crispness["num_queries"] = evaluation.refined_crispness.num_queries;
  AddCrispness("refined", evaluation.refined_crispness, &crispness);
  if (evaluation.has_prior) {
    AddCrispness("prior", evaluation.prior_crispness, &crispness);
  }
  if (evaluation.has_trajectory) {
    AddCrispness("odometry", evaluation.odometry_crispness, &crispness);
  }
  json["crispness"] = std::move(crispness);
  if (evaluation.has_trajectory) {
    const TrajectoryComparison& trajectory = evaluation.trajectory;
    Json trajectory_json;
    trajectory_json["num_steps"] = trajectory.num_steps;
    trajectory_json["odometry_length_m"] = trajectory.odometry_length_m;
    trajectory_json["refined_length_m"] = trajectory.refined_length_m;
    if (evaluation.has_prior) {
      trajectory_json["prior_length_m"] = trajectory.prior_length_m;
    }
    trajectory_json["length_ratio"] = trajectory.length_ratio;
    trajectory_json["max_step_difference_m"] =
        trajectory.max_step_difference_m;
    trajectory_json["max_step_difference_frame"] =
        trajectory.max_step_difference_frame;
    trajectory_json["num_failed_registrations"] =
        trajectory.num_failed_registrations;
    trajectory_json["min_fitness"] = trajectory.min_fitness;
    trajectory_json["odometry_steps_m"] = trajectory.odometry_steps_m;
    trajectory_json["refined_steps_m"] = trajectory.refined_steps_m;
    trajectory_json["fitness"] = trajectory.fitness;
    json["trajectory"] = std::move(trajectory_json);
  }
  if (evaluation.has_mesh) {
    const MeshVsLidar& mesh = evaluation.mesh_vs_lidar;
    Json mesh_json;
    mesh_json["num_lidar_points"] = mesh.num_lidar_points;
    mesh_json["num_mesh_samples"] = mesh.num_mesh_samples;
    mesh_json["mesh_area_m2"] = mesh.mesh_area_m2;
    for (size_t t = 0; t < mesh.thresholds_m.size(); ++t) {
      mesh_json[ThresholdKey("lidar_within_", mesh.thresholds_m[t])] =
          mesh.lidar_within[t];
      mesh_json[ThresholdKey("mesh_within_", mesh.thresholds_m[t])] =
          mesh.mesh_within[t];
      if (t < mesh.lidar_in_view_within.size()) {
        mesh_json[ThresholdKey("lidar_in_view_within_",
                               mesh.thresholds_m[t])] =
            mesh.lidar_in_view_within[t];
      }
    }
    mesh_json["num_lidar_points_in_view"] = mesh.num_lidar_points_in_view;
    json["mesh_vs_lidar"] = std::move(mesh_json);
  }
  WriteJsonFile(path, json);
}

std::string FormatRealDataEvaluation(const RealDataEvaluation& evaluation) {
  std::ostringstream text;
  text << std::setprecision(3) << evaluation.num_frames
       << " frames; crispness (median / p90, voxel "
       << evaluation.crispness_voxel_size_m << " m) refined "
       << evaluation.refined_crispness.median_m << " / "
       << evaluation.refined_crispness.p90_m << " m";
  if (evaluation.has_prior) {
    text << ", prior " << evaluation.prior_crispness.median_m << " / "
         << evaluation.prior_crispness.p90_m << " m";
  }
  if (evaluation.has_trajectory) {
    text << ", odometry " << evaluation.odometry_crispness.median_m << " / "
         << evaluation.odometry_crispness.p90_m << " m";
  }
  if (evaluation.has_trajectory) {
    text << "; trajectory refined " << evaluation.trajectory.refined_length_m
         << " m vs odometry " << evaluation.trajectory.odometry_length_m
         << " m (ratio " << evaluation.trajectory.length_ratio
         << ", max step difference "
         << evaluation.trajectory.max_step_difference_m << " m)";
  }
  if (evaluation.has_mesh) {
    const MeshVsLidar& mesh = evaluation.mesh_vs_lidar;
    text << "; mesh vs LIDAR";
    for (size_t t = 0; t < mesh.thresholds_m.size(); ++t) {
      text << " @" << mesh.thresholds_m[t] << " m: LIDAR "
           << mesh.lidar_within[t];
      if (t < mesh.lidar_in_view_within.size()) {
        text << " (in view " << mesh.lidar_in_view_within[t] << ")";
      }
      text << ", mesh " << mesh.mesh_within[t];
    }
  }
  return text.str();
}

}  // namespace colmap_lidar
