#include "src/sfm/mapper_iterations.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>
#include <unordered_set>
#include <utility>
#include <vector>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/resource_usage.h"
#include "src/optim/line_bundle_adjustment.h"
#include "src/optim/line_track.h"
#include "src/sfm/association_step.h"
#include "src/sfm/ba_input.h"
#include "src/sfm/pose_guided_matching.h"
#include "src/sfm/pose_prior_checks.h"
#include "src/sfm/stock_colmap_steps.h"

namespace colmap_lidar {

Reconstruction TriangulateAtPoses(
    const ColmapRunner& colmap, const LidarMapperPaths& paths,
    const LidarMapperOptions& options, const std::string& work_path,
    const std::unordered_map<image_t, bool>& held_out, Reconstruction* model) {
  Reconstruction active = PosesOnly(*model);
  active.images.erase(std::remove_if(active.images.begin(), active.images.end(),
                                     [&](const Image& image) {
                                       return held_out.count(image.image_id) >
                                              0;
                                     }),
                      active.images.end());
  Reconstruction triangulated = TriangulatePoints(
      colmap, paths, options, active, JoinPaths(work_path, "poses"),
      JoinPaths(work_path, "triangulated"));
  // Keep our image order and poses; take cameras (unchanged) and the
  // observations from the triangulator. Observations of points the
  // triangulator dropped for an image we lack cannot occur: every image of
  // ours was in its input.
  model->points3D = std::move(triangulated.points3D);
  model->point3D_file_order.clear();
  for (Image& image : model->images) {
    const Image* observed = triangulated.FindImage(image.image_id);
    image.points2D =
        observed != nullptr ? observed->points2D : std::vector<Point2D>();
  }
  return active;
}

void RebuildStructureAtPoses(const ColmapRunner& colmap,
                             const LidarMapperPaths& paths,
                             const LidarMapperOptions& options,
                             const std::string& work_path,
                             const std::unordered_map<image_t, bool>& held_out,
                             const Database& database, Reconstruction* model) {
  TriangulateAtPoses(colmap, paths, options, work_path, held_out, model);
  // The last association's tracks, each line placed anew from its LIDAR
  // endpoints (else its views) at these poses, without adjustment.
  std::vector<LineTrack> kept;
  for (LineTrack& track : LoadLineTracks(database, *model)) {
    track.plucker_in_world.setZero();
    if ((InitializeLineFromLidar(*model, &track) ||
         InitializeLineFromViews(*model, &track)) &&
        ComputeLineSegment(*model, &track)) {
      track.error = ComputeLineReprojectionError(*model, track);
      if (track.error >= 0.0 && track.error <= options.max_line_error_px) {
        kept.push_back(std::move(track));
      }
    }
  }
  SetReconstructionLines(kept, model);  // Replaces the lines.
  LOG(INFO) << "lidar_mapper: structure rebuilt at the kept poses: "
            << model->points3D.size() << " points, " << kept.size()
            << " line tracks";
}

namespace {

// Pose-guided matching at the model's poses; true when it added matches
// (summary->guided_database_path then names the triangulation database).
bool GuidedMatchingAtPoses(const LidarMapperPaths& paths,
                           const LidarMapperOptions& options,
                           const std::string& work_path,
                           const std::vector<RelativePoseEdge>& lidar_edges,
                           const std::unordered_map<image_t, bool>& held_out,
                           const Reconstruction& model,
                           LidarMapperSummary* summary) {
  // Trusted: images a LIDAR edge holds (an image without one sits at its
  // prior) and that take part in the triangulation.
  std::unordered_set<image_t> trusted;
  for (const RelativePoseEdge& edge : lidar_edges) {
    for (const image_t id : {edge.image_id1, edge.image_id2}) {
      if (held_out.count(id) == 0) trusted.insert(id);
    }
  }
  const std::vector<std::pair<image_t, image_t>> pairs =
      LidarMapperMatchingPairs(paths.database_path, options);
  PoseGuidedMatchingOptions guided = options.guided_matching;
  guided.pose_sigma_m = options.refined_pose_sigma_t_m;
  guided.pose_sigma_deg = options.refined_pose_sigma_r_deg;
  guided.num_threads = options.num_threads;
  const std::string output = JoinPaths(work_path, "guided_matches.db");
  const PoseGuidedMatchingSummary result = RunPoseGuidedMatching(
      paths.database_path, model, trusted, pairs, guided, output);
  LOG(INFO) << "lidar_mapper: pose-guided matching: " << result.ToString();
  summary->guided_matching = result.ToString();
  if (result.num_added == 0) return false;
  summary->guided_database_path = output;
  return true;
}

}  // namespace

void RunMapperIterations(const ColmapRunner& colmap,
                         const LidarMapperPaths& paths,
                         const LidarMapperOptions& options,
                         const std::string& work_path,
                         const std::unordered_map<image_t, Rigid3d>& priors,
                         Database* database, InitialPoses* init,
                         LidarMapperSummary* summary) {
  Reconstruction& model = init->model;
  std::unordered_map<image_t, bool>& held_out = init->held_out;
  const std::vector<RelativePoseEdge>& lidar_edges = init->lidar_edges;
  const bool points_only_first = init->points_only_first;
  const double rotation_sigma_deg =
      PerAxisRotationSigmaDeg(options.prior_rotation_sigma_deg);
  std::vector<LineTrack> tracks;
  // The scans for the LIDAR planes of the points, loaded once.
  std::unique_ptr<LidarPlaneScans> plane_scans;
  if (options.adjustment.lidar_point_weight > 0.0 &&
      options.adjustment.lambda_R > 0.0) {
    plane_scans = std::make_unique<LidarPlaneScans>(*database, model);
    LOG(INFO) << "lidar_mapper: " << plane_scans->NumScans()
              << " scans for the LIDAR planes of the points, range noise "
              << plane_scans->RangeSigma() << " m";
  }
  // An initialisation by the priors adjusts points only first: the rounds
  // with lines come after it.
  int num_iterations = options.max_num_iterations + (points_only_first ? 1 : 0);
  // The triangulation reads the workspace's matches until pose-guided
  // matching has written its own database (src/sfm/pose_guided_matching.h).
  LidarMapperPaths triangulation_paths = paths;
  bool guided_matching_done = false;
  for (int iteration = 0; iteration < num_iterations; ++iteration) {
    const auto iteration_start = std::chrono::steady_clock::now();
    LidarMapperIteration record;
    // What the guard restores when it undoes this iteration.
    const Reconstruction model_before = model;

    // Points: stock point_triangulator, poses and intrinsics fixed.
    const Reconstruction active = TriangulateAtPoses(
        colmap, triangulation_paths, options, work_path, held_out, &model);
    const std::string triangulated_path = JoinPaths(work_path, "triangulated");
    model.lines3D.clear();
    record.num_points = static_cast<int>(model.points3D.size());

    // Pending images: registered against this iteration's points; they join
    // the triangulation from the next iteration on.
    if (options.register_pending_images && !held_out.empty()) {
      record.num_registered_images = RegisterPendingImages(
          colmap, paths, options, triangulated_path,
          JoinPaths(work_path, "registered"), priors, &held_out, &model);
      summary->num_registered_pending += record.num_registered_images;
    }

    // Lines: association with the current poses.
    const bool use_lines = !(points_only_first && iteration == 0);
    tracks.clear();
    if (use_lines) {
      LineMatchingOptions matching = options.matching;
      const bool first_line_iteration =
          iteration == (points_only_first ? 1 : 0);
      matching.pose_sigma_t_m = first_line_iteration
                                    ? options.initial_pose_sigma_t_m
                                    : options.refined_pose_sigma_t_m;
      matching.pose_sigma_r_deg = first_line_iteration
                                      ? options.initial_pose_sigma_r_deg
                                      : options.refined_pose_sigma_r_deg;
      matching.num_threads = options.num_threads;
      const AssociationStepSummary association =
          AssociateWorkspaceLines(database, held_out.empty() ? model : active,
                                  matching);
      LOG(INFO) << "lidar_mapper: association with pose sigma "
                << matching.pose_sigma_t_m << " m / "
                << matching.pose_sigma_r_deg << " deg: "
                << association.num_tracks << " tracks, mean length "
                << association.mean_track_length;
      tracks = LoadLineTracks(*database, model);
    }
    record.num_line_tracks = static_cast<int>(tracks.size());

    // Adjustment.
    LineBundleAdjustmentOptions adjustment = options.adjustment;
    adjustment.gauge = LineBAGauge::kPosePriors;
    adjustment.prior_position_sigma_m = options.prior_position_sigma_m;
    adjustment.prior_rotation_sigma_deg = rotation_sigma_deg;
    adjustment.num_threads = options.num_threads;
    if (!use_lines) {
      adjustment.lambda_L = 0.0;
      adjustment.lambda_lidar = 0.0;
    }
    std::unordered_map<image_t, Rigid3d> poses_before;
    for (const Image& image : model.images) {
      poses_before[image.image_id] = image.cam_from_world;
    }
    LineBundleAdjuster adjuster(adjustment);
    adjuster.SetPosePriors(priors);
    adjuster.SetRelativePoseEdges(lidar_edges);
    if (plane_scans != nullptr) {
      LidarPointPlaneOptions plane_options = options.point_planes;
      plane_options.num_threads =
          options.num_threads > 0 ? options.num_threads : -1;
      adjuster.SetPointPlanes(
          plane_scans->Associate(model, adjustment.min_point_track_length,
                                 plane_options, &record.point_planes));
      LOG(INFO) << "lidar_mapper: iteration " << iteration + 1 << ": "
                << record.point_planes.ToString();
    }
    record.adjustment = adjuster.Solve(&model, &tracks);
    summary->adjustment_seconds += record.adjustment.solve_time_s;

    // Outliers.
    record.num_filtered_points = FilterPoints(options.max_point_error_px, &model);
    std::vector<LineTrack> kept;
    for (LineTrack& track : tracks) {
      if (IsLineInitialized(track) && track.error >= 0.0 &&
          track.error <= options.max_line_error_px) {
        kept.push_back(std::move(track));
      }
    }
    record.num_filtered_lines = static_cast<int>(tracks.size() - kept.size());
    tracks = std::move(kept);
    SetReconstructionLines(tracks, &model);

    // Convergence.
    double sum_change = 0.0;
    for (const Image& image : model.images) {
      const Rigid3d& before = poses_before.at(image.image_id);
      const double change = (image.ProjectionCenter() -
                             before.Inverse().translation)
                                .norm();
      record.max_position_change_m =
          std::max(record.max_position_change_m, change);
      sum_change += change;
      record.max_rotation_change_deg =
          std::max(record.max_rotation_change_deg,
                   RotationAngleDeg(image.cam_from_world.rotation,
                                    before.rotation));
    }
    record.mean_position_change_m = sum_change / model.images.size();

    // Guard: poses against their priors, before and after.
    int num_outliers_before = 0;
    std::vector<Image*> far_images;
    for (Image& image : model.images) {
      const Rigid3d& prior = priors.at(image.image_id);
      if (PriorOutlierLevel(poses_before.at(image.image_id), prior,
                            options.prior_position_sigma_m,
                            options.prior_rotation_sigma_deg) > 0) {
        ++num_outliers_before;
      }
      const int level = PriorOutlierLevel(image.cam_from_world, prior,
                                          options.prior_position_sigma_m,
                                          options.prior_rotation_sigma_deg);
      if (level > 0) {
        ++record.num_prior_outliers;
      }
      if (level > 1) {
        far_images.push_back(&image);
      }
    }
    const int max_outliers = static_cast<int>(
        std::floor(options.max_prior_outlier_ratio * model.images.size()));
    record.rejected = record.num_prior_outliers > max_outliers &&
                      record.num_prior_outliers > num_outliers_before;
    record.seconds = SecondsSince(iteration_start);
    if (record.rejected) {
      LOG(WARNING) << "lidar_mapper: iteration " << iteration + 1 << " put "
                   << record.num_prior_outliers << " of "
                   << model.images.size()
                   << " poses outside the 99.9 % region of their priors ("
                   << num_outliers_before << " before; largest move "
                   << record.max_position_change_m << " m / "
                   << record.max_rotation_change_deg
                   << " deg): undone, iterations stopped";
      model = model_before;
      ++summary->num_rejected_iterations;
      summary->iterations.push_back(record);
      break;
    }
    if (!far_images.empty()) {
      std::ostringstream names;
      for (Image* image : far_images) {
        names << " " << image->name;
        image->cam_from_world = priors.at(image->image_id);
      }
      LOG(WARNING) << "lidar_mapper: iteration " << iteration + 1 << ": "
                   << far_images.size()
                   << " images outside the 1 - 1e-6 region of their prior "
                      "reset to it:"
                   << names.str();
      summary->num_reset_images += static_cast<int>(far_images.size());
    }
    LOG(INFO) << "lidar_mapper: iteration " << iteration + 1 << ": "
              << record.num_points << " points, " << record.num_line_tracks
              << " line tracks" << (use_lines ? "" : " (points only)")
              << "; pose change max " << record.max_position_change_m
              << " m / " << record.max_rotation_change_deg << " deg, mean "
              << record.mean_position_change_m << " m; "
              << record.adjustment.ToString();
    summary->iterations.push_back(record);
    // Pose-guided matching once the poses were adjusted with the LIDAR
    // edges; the next iteration triangulates with its matches.
    if (options.guided_matching.enabled && !guided_matching_done &&
        !lidar_edges.empty() && use_lines) {
      guided_matching_done = true;
      if (GuidedMatchingAtPoses(paths, options, work_path, lidar_edges,
                                held_out, model, summary)) {
        triangulation_paths.database_path = summary->guided_database_path;
        num_iterations = std::max(num_iterations, iteration + 2);
        continue;
      }
    }
    if (use_lines && iteration > 0 && far_images.empty() &&
        record.num_registered_images == 0 &&
        record.max_position_change_m < options.max_position_change_m &&
        record.max_rotation_change_deg < options.max_rotation_change_deg) {
      summary->converged = true;
      break;
    }
  }
}

}  // namespace colmap_lidar
