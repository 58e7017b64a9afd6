#include "src/sfm/lidar_mapper.h"

#include <algorithm>
#include <chrono>
#include <sstream>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/runner/colmap_runner.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/resource_usage.h"
#include "src/eval/segment_io.h"
#include "src/lines/workspace_line_extractor.h"
#include "src/sfm/exact_feature_matcher.h"
#include "src/sfm/initial_poses.h"
#include "src/sfm/lidar_edge_check.h"
#include "src/sfm/mapper_iterations.h"
#include "src/sfm/pose_prior_checks.h"
#include "src/sfm/stock_colmap_steps.h"

namespace colmap_lidar {
namespace {

// Names of the images that no 3D point's track observes, in image order.
std::vector<std::string> ImagesWithoutPoints(const Reconstruction& model) {
  std::unordered_set<image_t> observing;
  for (const auto& [point3D_id, point3D] : model.points3D) {
    for (const TrackElement& element : point3D.track) {
      observing.insert(element.image_id);
    }
  }
  std::vector<std::string> names;
  for (const Image& image : model.images) {
    if (observing.count(image.image_id) == 0) {
      names.push_back(image.name);
    }
  }
  return names;
}

}  // namespace

bool LidarMapperOptions::Check() const {
#define LIDAR_MAPPER_CHECK(cond, name)                              \
  if (!(cond)) {                                                    \
    LOG(ERROR) << "LidarMapper." #name " is invalid: " #cond;       \
    return false;                                                   \
  }
  LIDAR_MAPPER_CHECK(sift_max_image_size > 0, sift_max_image_size);
  LIDAR_MAPPER_CHECK(sift_max_num_features > 0, sift_max_num_features);
  LIDAR_MAPPER_CHECK(exhaustive_max_num_images >= 0,
                     exhaustive_max_num_images);
  LIDAR_MAPPER_CHECK(sequential_overlap > 0, sequential_overlap);
  LIDAR_MAPPER_CHECK(matcher == "stock" || matcher == "exact", matcher);
  LIDAR_MAPPER_CHECK(init_method == "mapper" || init_method == "priors" ||
                         init_method == "model" ||
                         init_method == "lidar_graph",
                     init_method);
  LIDAR_MAPPER_CHECK(init_method != "model" || !init_model_path.empty(),
                     init_model_path);
  LIDAR_MAPPER_CHECK(init_min_num_inliers >= 3, init_min_num_inliers);
  LIDAR_MAPPER_CHECK(init_min_inlier_ratio >= 0.0 &&
                         init_min_inlier_ratio <= 1.0,
                     init_min_inlier_ratio);
  LIDAR_MAPPER_CHECK(max_prior_outlier_ratio >= 0.0 &&
                         max_prior_outlier_ratio <= 1.0,
                     max_prior_outlier_ratio);
  LIDAR_MAPPER_CHECK(mapper_num_attempts >= 1, mapper_num_attempts);
  LIDAR_MAPPER_CHECK(mapper_abs_pose_min_num_inliers > 0,
                     mapper_abs_pose_min_num_inliers);
  LIDAR_MAPPER_CHECK(mapper_abs_pose_min_inlier_ratio >= 0.0 &&
                         mapper_abs_pose_min_inlier_ratio <= 1.0,
                     mapper_abs_pose_min_inlier_ratio);
  LIDAR_MAPPER_CHECK(max_num_iterations >= 1, max_num_iterations);
  LIDAR_MAPPER_CHECK(max_position_change_m >= 0.0, max_position_change_m);
  LIDAR_MAPPER_CHECK(max_rotation_change_deg >= 0.0, max_rotation_change_deg);
  LIDAR_MAPPER_CHECK(initial_pose_sigma_t_m >= 0.0, initial_pose_sigma_t_m);
  LIDAR_MAPPER_CHECK(initial_pose_sigma_r_deg >= 0.0,
                     initial_pose_sigma_r_deg);
  LIDAR_MAPPER_CHECK(refined_pose_sigma_t_m >= 0.0, refined_pose_sigma_t_m);
  LIDAR_MAPPER_CHECK(refined_pose_sigma_r_deg >= 0.0,
                     refined_pose_sigma_r_deg);
  LIDAR_MAPPER_CHECK(max_point_error_px > 0.0, max_point_error_px);
  LIDAR_MAPPER_CHECK(max_line_error_px > 0.0, max_line_error_px);
  LIDAR_MAPPER_CHECK(triangulation_max_error_px > 0.0,
                     triangulation_max_error_px);
  LIDAR_MAPPER_CHECK(prior_position_sigma_m > 0.0, prior_position_sigma_m);
  LIDAR_MAPPER_CHECK(prior_rotation_sigma_deg > 0.0, prior_rotation_sigma_deg);
#undef LIDAR_MAPPER_CHECK
  return extraction.Check() && matching.Check() && adjustment.Check() &&
         (init_method != "lidar_graph" || lidar_graph.Check()) &&
         point_planes.Check() && guided_matching.Check();
}

std::vector<std::pair<image_t, image_t>> LidarMapperMatchingPairs(
    const std::string& database_path, const LidarMapperOptions& options) {
  const Database database(database_path);
  return MatchingPairs(database.ReadAllImages(),
                       options.exhaustive_max_num_images,
                       options.sequential_overlap,
                       options.sequential_quadratic_overlap);
}

std::string LidarMapperSummary::Outcome() const {
  std::ostringstream out;
  out << num_images << " images, " << num_points << " points, " << num_lines
      << " line tracks, " << iterations.size() << " iterations"
      << (converged ? " (converged)" : " (not converged)");
  if (num_lidar_edges > 0) {
    out << "; " << num_lidar_edges << " LIDAR edges, "
        << num_lidar_edge_violated_frames << " frames violate one"
        << (kept_lidar_graph_poses ? ", graph poses kept" : "");
  }
  if (!images_without_points.empty()) {
    // A handful of names says which; a night drive would list them all.
    constexpr size_t kMaxNames = 5;
    out << "; " << images_without_points.size()
        << " images observe no 3D point, posed by "
        << (num_lidar_edges > 0 ? "the LIDAR graph and their priors"
                                : "their priors")
        << " alone:";
    for (size_t i = 0; i < std::min(kMaxNames, images_without_points.size());
         ++i) {
      out << " " << images_without_points[i];
    }
    if (images_without_points.size() > kMaxNames) out << " ...";
  }
  return out.str();
}

std::string LidarMapperSummary::Format() const {
  std::ostringstream out;
  out << "lidar_mapper: " << num_images << " images (init " << init_used
      << ", " << num_initial_images << " initialised";
  if (prior_alignment_rms_m >= 0.0) {
    out << ", sim3 to priors rms " << prior_alignment_rms_m << " m";
  }
  if (num_pending_images > 0) {
    out << ", " << num_registered_pending << " of " << num_pending_images
        << " pending images registered";
  }
  out << "), " << iterations.size() << " iterations ("
      << num_rejected_iterations << " undone, " << num_reset_images
      << " images reset to their prior), "
      << (converged ? "converged" : "not converged") << "\n";
  if (!init_alignment.empty()) {
    out << "  initial model: " << init_alignment << "\n";
  }
  if (!guided_matching.empty()) {
    out << "  pose-guided matching: " << guided_matching << "\n";
  }
  for (size_t i = 0; i < iterations.size(); ++i) {
    const LidarMapperIteration& it = iterations[i];
    out << "  iteration " << i + 1 << (it.rejected ? " (undone)" : "")
        << ": " << it.num_points << " points, "
        << it.num_line_tracks << " line tracks, pose change max "
        << it.max_position_change_m << " m / " << it.max_rotation_change_deg
        << " deg, mean " << it.mean_position_change_m << " m; errors point "
        << it.adjustment.mean_point_error_px << " px, line "
        << it.adjustment.mean_line_error_px << " px, lidar rms "
        << it.adjustment.rms_lidar_distance_m << " m; filtered "
        << it.num_filtered_points << " points, " << it.num_filtered_lines
        << " lines; " << it.num_prior_outliers << " prior outliers; "
        << it.seconds << " s\n";
  }
  if (num_lidar_edges > 0) {
    out << "  lidar edges: " << num_lidar_edges << ", mean whitened error "
        << lidar_edge_error_input << " (graph) -> " << lidar_edge_error_final
        << " (final), " << num_lidar_edge_violated_frames
        << " frames violate an edge"
        << (kept_lidar_graph_poses ? "; graph poses kept" : "") << "\n";
  }
  if (!images_without_points.empty()) {
    out << "  images that observe no 3D point (posed by "
        << (num_lidar_edges > 0 ? "the LIDAR graph and their priors"
                                : "their priors")
        << " alone): " << images_without_points.size() << ":";
    for (const std::string& name : images_without_points) out << " " << name;
    out << "\n";
  }
  out << "  output " << output_path << ": " << num_points << " points, "
      << num_lines << " lines3D; segments " << lines_ply_path << "\n";
  out << "  time: features+matching " << features_seconds << " s, lines "
      << lines_seconds << " s, initialisation " << init_seconds
      << " s, iterations " << iterations_seconds << " s (adjustment "
      << adjustment_seconds << " s), total " << total_seconds << " s\n";
  out << "  cpu time: features+matching " << features_cpu_seconds
      << " s, lines " << lines_cpu_seconds << " s, initialisation "
      << init_cpu_seconds << " s, iterations " << iterations_cpu_seconds
      << " s, total " << total_cpu_seconds << " s";
  return out.str();
}

int FilterPoints(double max_error_px, Reconstruction* model) {
  std::unordered_map<image_t, Image*> images;
  for (Image& image : model->images) {
    images[image.image_id] = &image;
  }
  int num_removed = 0;
  for (auto it = model->points3D.begin(); it != model->points3D.end();) {
    const Point3D& point3D = it->second;
    if (point3D.track.size() >= 2 && point3D.error >= 0.0 &&
        point3D.error <= max_error_px) {
      ++it;
      continue;
    }
    for (const TrackElement& element : point3D.track) {
      const auto image = images.find(element.image_id);
      if (image != images.end() &&
          element.point2D_idx < image->second->points2D.size()) {
        image->second->points2D[element.point2D_idx].point3D_id =
            kInvalidPoint3DId;
      }
    }
    it = model->points3D.erase(it);
    ++num_removed;
  }
  return num_removed;
}

void WriteLines3DPly(const std::string& path, const Reconstruction& model) {
  std::vector<Segment3D> segments;
  segments.reserve(model.lines3D.size());
  for (const auto& [line3D_id, line3D] : model.lines3D) {
    Segment3D segment;
    segment.start = line3D.start_in_world;
    segment.end = line3D.end_in_world;
    segments.push_back(segment);
  }
  WriteSegmentsPly(path, segments);
}

LidarMapperSummary RunLidarMapper(const LidarMapperPaths& input_paths,
                                  const LidarMapperOptions& options) {
  THROW_CHECK(options.Check(), "lidar_mapper: invalid options (see the log)");
  const auto start_time = std::chrono::steady_clock::now();
  const double start_cpu = ProcessCpuSeconds();
  LidarMapperPaths paths = input_paths;
  THROW_CHECK(!paths.workspace_path.empty(),
              "lidar_mapper: the workspace path is empty");
  if (paths.database_path.empty()) {
    paths.database_path = JoinPaths(paths.workspace_path, "database.db");
  }
  if (paths.image_path.empty()) {
    paths.image_path = JoinPaths(paths.workspace_path, "images");
  }
  if (paths.output_path.empty()) {
    paths.output_path = JoinPaths(paths.workspace_path, "sparse/refined");
  }
  if (paths.lines_ply_path.empty()) {
    paths.lines_ply_path = JoinPaths(paths.output_path, "lines3D.ply");
  }
  THROW_CHECK(ExistsFile(paths.database_path),
              "lidar_mapper: no database " << paths.database_path
                                           << " (run lidar_importer first)");
  THROW_CHECK(ExistsDir(paths.image_path),
              "lidar_mapper: no image folder " << paths.image_path);
  const std::string work_path =
      JoinPaths(paths.workspace_path, "sparse/lidar_mapper");
  CreateDirIfNotExists(JoinPaths(paths.workspace_path, "sparse"));
  CreateDirIfNotExists(work_path);

  ColmapRunnerOptions runner_options;
  runner_options.colmap_binary = options.colmap_binary;
  runner_options.log_path =
      JoinPaths(paths.workspace_path, "lidar_mapper_colmap.log");
  const ColmapRunner colmap(runner_options);

  LidarMapperSummary summary;
  summary.output_path = paths.output_path;
  summary.lines_ply_path = paths.lines_ply_path;

  // ---- 1-2. Features and matches (stock colmap; our handle is closed
  // while colmap writes the database).
  int num_images = 0;
  bool need_features = false;
  {
    const Database database(paths.database_path);
    for (const DatabaseImage& image : database.ReadAllImages()) {
      ++num_images;
      need_features = need_features || !database.ExistsKeypoints(image.image_id);
    }
  }
  THROW_CHECK(num_images > 0,
              "lidar_mapper: the database " << paths.database_path
                                            << " holds no images");
  auto stage_start = std::chrono::steady_clock::now();
  double stage_cpu = ProcessCpuSeconds();
  if (need_features) {
    RunStockFeatureExtractor(colmap, paths, options, num_images);
  } else {
    LOG(INFO) << "lidar_mapper: every image has keypoints, feature "
                 "extraction skipped";
  }
  if (options.matcher == "exact") {
    const std::vector<std::pair<image_t, image_t>> pairs =
        LidarMapperMatchingPairs(paths.database_path, options);
    ExactMatchingOptions matching;
    matching.num_threads = options.num_threads;
    RunExactMatching(paths.database_path, pairs, matching);
  } else {
    RunStockMatcher(colmap, paths, options, num_images);
  }
  summary.features_seconds = SecondsSince(stage_start);
  summary.features_cpu_seconds = ProcessCpuSeconds() - stage_cpu;

  // ---- 3. Lines.
  stage_start = std::chrono::steady_clock::now();
  stage_cpu = ProcessCpuSeconds();
  {
    size_t num_segments = 0;
    {
      const Database database(paths.database_path);
      num_segments = NumLineSegments(database);
    }
    if (num_segments == 0) {
      LineExtractionOptions extraction = options.extraction;
      extraction.num_threads = options.num_threads;
      const WorkspaceLineExtractionSummary lines = ExtractWorkspaceLines(
          paths.database_path, paths.image_path, {}, extraction);
      LOG(INFO) << "lidar_mapper: line_extractor\n" << lines.Format();
    } else {
      LOG(INFO) << "lidar_mapper: " << num_segments
                << " line segments in the database, extraction skipped";
    }
  }
  summary.lines_seconds = SecondsSince(stage_start);
  summary.lines_cpu_seconds = ProcessCpuSeconds() - stage_cpu;

  Database database(paths.database_path);
  const Reconstruction prior_model = PriorModel(database);
  THROW_CHECK(prior_model.images.size() >= 3,
              "lidar_mapper: " << prior_model.images.size()
                               << " images of " << paths.database_path
                               << " have prior poses, need at least 3 (run "
                                  "lidar_importer or lidar_odometry)");
  std::unordered_map<image_t, Rigid3d> priors;
  for (const Image& image : prior_model.images) {
    priors[image.image_id] = image.cam_from_world;
  }
  summary.num_images = static_cast<int>(prior_model.images.size());

  // ---- 4. Initial poses.
  stage_start = std::chrono::steady_clock::now();
  stage_cpu = ProcessCpuSeconds();
  InitialPoses init = InitializePoses(colmap, paths, options, work_path,
                                      database, prior_model, priors, &summary);
  summary.init_seconds = SecondsSince(stage_start);
  summary.init_cpu_seconds = ProcessCpuSeconds() - stage_cpu;

  // ---- 5. Iterations.
  stage_start = std::chrono::steady_clock::now();
  stage_cpu = ProcessCpuSeconds();
  std::unordered_map<image_t, Rigid3d> input_poses;
  for (const Image& image : init.model.images) {
    input_poses[image.image_id] = image.cam_from_world;
  }
  RunMapperIterations(colmap, paths, options, work_path, priors, &database,
                      &init, &summary);
  if (!init.lidar_edges.empty()) {
    CheckLidarEdges(init.lidar_edges, input_poses, &init.model, &summary);
    if (summary.kept_lidar_graph_poses) {
      RebuildStructureAtPoses(colmap, paths, options, work_path, init.held_out,
                              database, &init.model);
    }
  }
  summary.iterations_seconds = SecondsSince(stage_start);
  summary.iterations_cpu_seconds = ProcessCpuSeconds() - stage_cpu;

  // ---- 6. Output.
  const Reconstruction& model = init.model;
  WriteReconstruction(paths.output_path, model, ModelFormat::kBinary);
  WriteLines3DPly(paths.lines_ply_path, model);
  summary.num_points = static_cast<int>(model.points3D.size());
  summary.num_lines = static_cast<int>(model.lines3D.size());
  summary.images_without_points = ImagesWithoutPoints(model);
  if (!summary.images_without_points.empty()) {
    std::string names;
    for (const std::string& name : summary.images_without_points) {
      names += " " + name;
    }
    LOG(WARNING) << "lidar_mapper: " << summary.images_without_points.size()
                 << " of " << model.images.size()
                 << " images observe no 3D point; their poses come from "
                 << (init.lidar_edges.empty()
                         ? "their priors alone"
                         : "the LIDAR graph and their priors alone")
                 << ":" << names;
  }
  summary.total_seconds = SecondsSince(start_time);
  summary.total_cpu_seconds = ProcessCpuSeconds() - start_cpu;
  return summary;
}

}  // namespace colmap_lidar
