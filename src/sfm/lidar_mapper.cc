#include "src/sfm/lidar_mapper.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <utility>
#include <vector>

#include <sys/resource.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/runner/colmap_runner.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/eval/segment_io.h"
#include "src/lines/workspace_line_extractor.h"
#include "src/sfm/association_step.h"
#include "src/sfm/ba_input.h"
#include "src/sfm/model_alignment.h"

namespace colmap_lidar {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                       start)
      .count();
}

// User + system time of this process and of its finished children (the
// colmap runs), seconds.
double CpuSeconds() {
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * t.tv_usec;
  };
  rusage self{};
  rusage children{};
  getrusage(RUSAGE_SELF, &self);
  getrusage(RUSAGE_CHILDREN, &children);
  return seconds(self.ru_utime) + seconds(self.ru_stime) +
         seconds(children.ru_utime) + seconds(children.ru_stime);
}

// How far a pose lies from its prior: 0 inside the 99.9 % region of the
// prior noise, 1 outside it, 2 outside the 1 - 1e-6 region. Centre: chi-square
// with 3 degrees of freedom (16.27, 30.66); rotation: the angle in RMS angles
// as a Gaussian (3.29, 4.89), a test that also holds (more loosely) for a
// Gaussian rotation vector.
int PriorOutlierLevel(const Rigid3d& cam_from_world, const Rigid3d& prior,
                      double position_sigma_m, double rotation_rms_deg) {
  const double centre_error = (cam_from_world.Inverse().translation -
                               prior.Inverse().translation)
                                  .norm() /
                              position_sigma_m;
  const double angle = cam_from_world.rotation.normalized().angularDistance(
                           prior.rotation.normalized()) *
                       180.0 / M_PI / rotation_rms_deg;
  const double chi_square = centre_error * centre_error;
  if (chi_square > 30.66 || angle > 4.89) {
    return 2;
  }
  return chi_square > 16.27 || angle > 3.29 ? 1 : 0;
}

// Per-axis rotation-vector sigma of priors whose RMS angle is
// rms_angle_deg (isotropic error: the squared angle splits over 3 axes).
double PerAxisRotationSigmaDeg(double rms_angle_deg) {
  return rms_angle_deg / std::sqrt(3.0);
}

std::string ThreadsArg(int num_threads) {
  return std::to_string(num_threads <= 0 ? -1 : num_threads);
}

// The Mapper.* options of stock `mapper` and `image_registrator`: the
// calibrated intrinsics stay fixed, lidar_mapper's PnP thresholds.
void AppendStockMapperArgs(
    const LidarMapperOptions& options,
    std::vector<std::pair<std::string, std::string>>* args) {
  args->insert(
      args->end(),
      {{"Mapper.ba_refine_focal_length", "0"},
       {"Mapper.ba_refine_principal_point", "0"},
       {"Mapper.ba_refine_extra_params", "0"},
       {"Mapper.abs_pose_min_num_inliers",
        std::to_string(options.mapper_abs_pose_min_num_inliers)},
       {"Mapper.abs_pose_min_inlier_ratio",
        std::to_string(options.mapper_abs_pose_min_inlier_ratio)},
       {"Mapper.num_threads", ThreadsArg(options.num_threads)}});
}

// Registers the images of `pending` (absent from the model at
// `model_path`) with stock image_registrator and takes each registered pose
// that lies inside the 99.9 % region of its prior; those images leave
// `pending`. Returns their count. A failed registrator run is a warning:
// the images keep waiting at their prior pose.
int RegisterPendingImages(const ColmapRunner& colmap,
                          const LidarMapperPaths& paths,
                          const LidarMapperOptions& options,
                          const std::string& model_path,
                          const std::string& output_path,
                          const std::unordered_map<image_t, Rigid3d>& priors,
                          std::unordered_map<image_t, bool>* pending,
                          Reconstruction* model) {
  std::filesystem::remove_all(output_path);
  CreateDirIfNotExists(output_path);
  Reconstruction registered;
  try {
    std::vector<std::pair<std::string, std::string>> args = {
        {"database_path", paths.database_path},
        {"input_path", model_path},
        {"output_path", output_path}};
    AppendStockMapperArgs(options, &args);
    colmap.Run("image_registrator", args);
    registered = ReadReconstruction(output_path);
  } catch (const Error& error) {
    LOG(WARNING) << "lidar_mapper: image_registrator failed (" << error.what()
                 << "); " << pending->size()
                 << " images keep their prior pose";
    return 0;
  }
  int num_taken = 0;
  int num_far = 0;
  for (auto it = pending->begin(); it != pending->end();) {
    const Image* image = registered.FindImage(it->first);
    Image* target = model->FindImage(it->first);
    if (image == nullptr || target == nullptr) {
      ++it;
      continue;
    }
    if (PriorOutlierLevel(image->cam_from_world, priors.at(it->first),
                          options.prior_position_sigma_m,
                          options.prior_rotation_sigma_deg) > 0) {
      ++num_far;
      ++it;
      continue;
    }
    target->cam_from_world = image->cam_from_world;
    ++num_taken;
    it = pending->erase(it);
  }
  LOG(INFO) << "lidar_mapper: image_registrator placed " << num_taken
            << " pending images (" << num_far
            << " registered outside their prior's region, not taken); "
            << pending->size() << " still pending";
  return num_taken;
}

// Cameras of the database plus one image per database image with a prior
// pose, at that pose, without points: the starting model of the "priors"
// initialisation and the fallback pose of images the mapper missed.
Reconstruction PriorModel(const Database& database) {
  Reconstruction model;
  for (const Camera& camera : database.ReadAllCameras()) {
    model.cameras[camera.camera_id] = camera;
  }
  for (const DatabaseImage& db_image : database.ReadAllImages()) {
    if (!db_image.prior_q || !db_image.prior_t) {
      continue;
    }
    Image image;
    image.image_id = db_image.image_id;
    image.name = db_image.name;
    image.camera_id = db_image.camera_id;
    const Eigen::Quaterniond rotation = db_image.prior_q->normalized();
    image.cam_from_world = Rigid3d(rotation, -(rotation * *db_image.prior_t));
    model.images.push_back(std::move(image));
  }
  return model;
}

// The model with poses only (no points, no observations): what stock
// point_triangulator gets, so that it fills points2D from the database.
Reconstruction PosesOnly(const Reconstruction& model) {
  Reconstruction poses;
  poses.cameras = model.cameras;
  for (const Image& image : model.images) {
    Image copy;
    copy.image_id = image.image_id;
    copy.name = image.name;
    copy.camera_id = image.camera_id;
    copy.cam_from_world = image.cam_from_world;
    poses.images.push_back(std::move(copy));
  }
  return poses;
}

// The models colmap mapper writes (numbered sub-folders).
std::vector<Reconstruction> ReadMapperModels(const std::string& mapper_path) {
  std::vector<Reconstruction> models;
  for (const auto& entry : std::filesystem::directory_iterator(mapper_path)) {
    if (entry.is_directory() && ExistsModel(entry.path().string())) {
      models.push_back(ReadReconstruction(entry.path().string()));
    }
  }
  return models;
}

double RotationAngleDeg(const Eigen::Quaterniond& a,
                        const Eigen::Quaterniond& b) {
  return a.normalized().angularDistance(b.normalized()) * 180.0 / M_PI;
}

// The check of the final poses against the LIDAR edges (see
// LidarMapperSummary): a correct edge's squared whitened error is below the
// chi-square(6) 99.9 % quantile; frames with an edge beyond it are logged.
// When the final poses violate the edges much more than the input poses
// (the graph's) did, the input poses are restored; the points and lines
// stay those of the final iteration.
void CheckLidarEdges(const std::vector<RelativePoseEdge>& edges,
                     const std::unordered_map<image_t, Rigid3d>& input_poses,
                     Reconstruction* model, LidarMapperSummary* summary) {
  constexpr double kChi2Dof6Quantile999 = 22.458;
  Reconstruction input = *model;
  for (Image& image : input.images) {
    const auto it = input_poses.find(image.image_id);
    if (it != input_poses.end()) {
      image.cam_from_world = it->second;
    }
  }
  double sum_input = 0.0;
  double sum_final = 0.0;
  int count = 0;
  std::unordered_map<image_t, double> worst_of_frame;
  for (const RelativePoseEdge& edge : edges) {
    const double error_input = ComputeRelativePoseEdgeError(input, edge);
    const double error_final = ComputeRelativePoseEdgeError(*model, edge);
    if (error_input < 0.0 || error_final < 0.0) {
      continue;
    }
    sum_input += error_input;
    sum_final += error_final;
    ++count;
    for (const image_t image_id : {edge.image_id1, edge.image_id2}) {
      double& worst = worst_of_frame[image_id];
      worst = std::max(worst, error_final);
    }
  }
  if (count == 0) {
    return;
  }
  summary->lidar_edge_error_input = sum_input / count;
  summary->lidar_edge_error_final = sum_final / count;
  std::vector<std::pair<double, image_t>> violated;
  for (const auto& [image_id, worst] : worst_of_frame) {
    if (worst * worst > kChi2Dof6Quantile999) {
      violated.emplace_back(worst, image_id);
    }
  }
  std::sort(violated.rbegin(), violated.rend());
  summary->num_lidar_edge_violated_frames = static_cast<int>(violated.size());
  if (!violated.empty()) {
    std::ostringstream worst;
    for (size_t k = 0; k < std::min<size_t>(5, violated.size()); ++k) {
      worst << " " << model->FindImage(violated[k].second)->name << " ("
            << violated[k].first << ")";
    }
    LOG(WARNING) << "lidar_mapper: " << violated.size()
                 << " frames violate a LIDAR edge beyond the chi-square(6) "
                    "99.9 % quantile after the iterations; worst (whitened "
                    "error):"
                 << worst.str();
  }
  // Expected whitened norm of a correct edge: sqrt(6).
  if (summary->lidar_edge_error_final > 2.0 * summary->lidar_edge_error_input &&
      summary->lidar_edge_error_final - summary->lidar_edge_error_input >
          std::sqrt(6.0)) {
    for (Image& image : model->images) {
      const auto it = input_poses.find(image.image_id);
      if (it != input_poses.end()) {
        image.cam_from_world = it->second;
      }
    }
    summary->kept_lidar_graph_poses = true;
    LOG(WARNING) << "lidar_mapper: the iterations raised the mean whitened "
                    "LIDAR edge error from "
                 << summary->lidar_edge_error_input << " to "
                 << summary->lidar_edge_error_final
                 << ": the LIDAR graph poses are kept (points and lines are "
                    "those of the last iteration)";
  } else {
    LOG(INFO) << "lidar_mapper: mean whitened LIDAR edge error "
              << summary->lidar_edge_error_input << " (graph) -> "
              << summary->lidar_edge_error_final << " (final) over " << count
              << " edges";
  }
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
         (init_method != "lidar_graph" || lidar_graph.Check());
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
  const double start_cpu = CpuSeconds();
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
  const std::string threads = ThreadsArg(options.num_threads);

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
  double stage_cpu = CpuSeconds();
  if (need_features) {
    LOG(INFO) << "lidar_mapper: feature_extractor (CPU SIFT) on " << num_images
              << " images";
    colmap.Run("feature_extractor",
               {{"database_path", paths.database_path},
                {"image_path", paths.image_path},
                {"SiftExtraction.use_gpu", "0"},
                {"SiftExtraction.num_threads", threads},
                {"SiftExtraction.max_image_size",
                 std::to_string(options.sift_max_image_size)},
                {"SiftExtraction.max_num_features",
                 std::to_string(options.sift_max_num_features)}});
  } else {
    LOG(INFO) << "lidar_mapper: every image has keypoints, feature "
                 "extraction skipped";
  }
  if (num_images <= options.exhaustive_max_num_images) {
    LOG(INFO) << "lidar_mapper: exhaustive_matcher";
    colmap.Run("exhaustive_matcher", {{"database_path", paths.database_path},
                                      {"SiftMatching.use_gpu", "0"},
                                      {"SiftMatching.num_threads", threads}});
  } else {
    LOG(INFO) << "lidar_mapper: sequential_matcher, overlap "
              << options.sequential_overlap;
    colmap.Run("sequential_matcher",
               {{"database_path", paths.database_path},
                {"SiftMatching.use_gpu", "0"},
                {"SiftMatching.num_threads", threads},
                {"SequentialMatching.overlap",
                 std::to_string(options.sequential_overlap)},
                {"SequentialMatching.quadratic_overlap",
                 options.sequential_quadratic_overlap ? "1" : "0"}});
  }
  summary.features_seconds = SecondsSince(stage_start);
  summary.features_cpu_seconds = CpuSeconds() - stage_cpu;

  // ---- 3. Lines.
  stage_start = std::chrono::steady_clock::now();
  stage_cpu = CpuSeconds();
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
  summary.lines_cpu_seconds = CpuSeconds() - stage_cpu;

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
  stage_cpu = CpuSeconds();
  const double rotation_sigma_deg =
      PerAxisRotationSigmaDeg(options.prior_rotation_sigma_deg);
  Reconstruction model = prior_model;
  bool points_only_first = options.init_method == "priors";
  // Images registered by an accepted initial model outside its consensus:
  // their poses are wrong (or their part of the model is) and their prior
  // poses are too coarse to triangulate or associate with, so they stay at
  // their prior pose, out of triangulation and association, and only their
  // prior residual enters the adjustment (measured: keeping them in drags
  // the consensus images back to prior-level errors).
  std::unordered_map<image_t, bool> held_out;
  // init_method lidar_graph: its accepted edges, terms of every adjustment.
  std::vector<RelativePoseEdge> lidar_edges;
  summary.init_used = options.init_method;
  summary.num_initial_images = static_cast<int>(model.images.size());
  if (options.init_method == "lidar_graph") {
    LidarPoseGraphOptions graph_options = options.lidar_graph;
    graph_options.prior_position_sigma_m = options.prior_position_sigma_m;
    graph_options.prior_rotation_sigma_deg = options.prior_rotation_sigma_deg;
    graph_options.num_threads = options.num_threads;
    const std::string database_dir =
        std::filesystem::path(paths.database_path).parent_path().string();
    const LidarPoseGraphResult graph = LidarGraphPoses(
        database, database_dir.empty() ? "." : database_dir, graph_options,
        &model);
    LOG(INFO) << "lidar_mapper: " << graph.Format() << "\n"
              << graph.FormatEdges();
    WriteReconstruction(JoinPaths(work_path, "lidar_graph"), PosesOnly(model),
                        ModelFormat::kBinary);
    for (const LidarPoseGraphEdge& graph_edge : graph.edges) {
      if (!graph_edge.used) {
        continue;
      }
      RelativePoseEdge edge;
      edge.image_id1 = graph.image_ids.at(graph_edge.i);
      edge.image_id2 = graph.image_ids.at(graph_edge.j);
      edge.lidar1_from_lidar2 = graph_edge.registration.target_from_source;
      edge.cam1_from_lidar = graph.cam_from_lidar.at(graph_edge.i);
      edge.cam2_from_lidar = graph.cam_from_lidar.at(graph_edge.j);
      edge.sqrt_information =
          SqrtInformation(graph_edge.registration.information);
      lidar_edges.push_back(edge);
    }
    summary.num_lidar_edges = static_cast<int>(lidar_edges.size());
    summary.init_alignment = graph.Format();
  } else if (options.init_method != "priors") {
    // Each model (stock mapper may write several, e.g. split where the walk
    // turns on the spot) is aligned robustly on its own. Accepted models
    // give their consensus images, the largest consensus first (an image
    // is taken once).
    RobustPriorAlignmentOptions alignment_options;
    alignment_options.position_sigma_m = options.prior_position_sigma_m;
    alignment_options.rotation_sigma_deg = options.prior_rotation_sigma_deg;
    alignment_options.min_num_inliers = options.init_min_num_inliers;
    alignment_options.min_inlier_ratio = options.init_min_inlier_ratio;
    std::vector<Reconstruction> candidates;
    std::vector<RobustPriorAlignmentSummary> alignments;
    int num_registered = 0;
    // Stock mapper is randomised: a run that gives no acceptable model (on
    // small scenes one in a few builds a broken one, cameras turned by
    // 100 degrees) is repeated with another random seed.
    const int num_attempts =
        options.init_method == "model" ? 1 : options.mapper_num_attempts;
    for (int attempt = 0; attempt < num_attempts; ++attempt) {
      candidates.clear();
      alignments.clear();
      num_registered = 0;
      if (options.init_method == "model") {
        THROW_CHECK(ExistsModel(options.init_model_path),
                    "lidar_mapper: init_model_path "
                        << options.init_model_path
                        << " holds no sparse model");
        candidates.push_back(ReadReconstruction(options.init_model_path));
      } else {
        const std::string mapper_path = JoinPaths(work_path, "mapper");
        std::filesystem::remove_all(mapper_path);
        CreateDirIfNotExists(mapper_path);
        LOG(INFO) << "lidar_mapper: stock mapper for the initial poses"
                  << " (random seed " << attempt << ")";
        try {
          std::vector<std::pair<std::string, std::string>> args = {
              {"database_path", paths.database_path},
              {"image_path", paths.image_path},
              {"output_path", mapper_path},
              {"random_seed", std::to_string(attempt)}};
          AppendStockMapperArgs(options, &args);
          colmap.Run("mapper", args);
          candidates = ReadMapperModels(mapper_path);
        } catch (const Error& error) {
          LOG(WARNING) << "lidar_mapper: stock mapper failed (" << error.what()
                       << ")";
        }
      }
      bool any_accepted = false;
      for (Reconstruction& candidate : candidates) {
        num_registered += static_cast<int>(candidate.images.size());
        alignments.push_back(RobustAlignReconstructionToPriors(
            priors, alignment_options, &candidate));
        any_accepted = any_accepted || alignments.back().accepted;
        LOG(INFO) << "lidar_mapper: initial model of "
                  << candidate.images.size()
                  << " images: " << alignments.back().Format();
      }
      if (any_accepted) {
        break;
      }
      if (attempt + 1 < num_attempts) {
        LOG(WARNING) << "lidar_mapper: no stock mapper model agrees with the "
                        "priors; running stock mapper again";
      }
    }
    std::vector<size_t> order(candidates.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return alignments[a].inlier_image_ids.size() >
             alignments[b].inlier_image_ids.size();
    });
    std::unordered_map<image_t, bool> initialised;
    std::ostringstream alignment_text;
    double sum_squared_rms = 0.0;
    int num_accepted = 0;
    for (const size_t index : order) {
      const RobustPriorAlignmentSummary& alignment = alignments[index];
      alignment_text << (alignment_text.tellp() > 0 ? "; " : "")
                     << candidates[index].images.size()
                     << " images: " << alignment.Format();
      if (!alignment.accepted) {
        continue;
      }
      ++num_accepted;
      for (const image_t image_id : alignment.inlier_image_ids) {
        const Image* mapped_image = candidates[index].FindImage(image_id);
        Image* image = model.FindImage(image_id);
        if (mapped_image != nullptr && image != nullptr &&
            !initialised[image_id]) {
          image->cam_from_world = mapped_image->cam_from_world;
          initialised[image_id] = true;
          sum_squared_rms +=
              alignment.rms_residual_m * alignment.rms_residual_m;
        }
      }
    }
    summary.init_alignment = alignment_text.str();
    int num_initialised = 0;
    for (const auto& [image_id, done] : initialised) {
      num_initialised += done ? 1 : 0;
    }
    if (num_accepted == 0) {
      // No trustworthy relative poses: continue as init_method "priors".
      LOG(WARNING) << "lidar_mapper: initial model rejected ("
                   << (candidates.empty() ? std::string("no model")
                                          : summary.init_alignment)
                   << "); starting from the prior poses instead";
      points_only_first = true;
      summary.init_used = "priors (fallback)";
    } else {
      summary.num_initial_images = num_initialised;
      summary.prior_alignment_rms_m =
          std::sqrt(sum_squared_rms / num_initialised);
      summary.num_init_outliers = num_registered - num_initialised;
      for (const Reconstruction& candidate : candidates) {
        for (const Image& image : candidate.images) {
          if (!initialised[image.image_id] &&
              model.FindImage(image.image_id) != nullptr) {
            held_out[image.image_id] = true;
          }
        }
      }
      // Images the mapper did not register at all join at their prior
      // pose: their observations triangulate with their neighbours' and the
      // adjustment moves them (on the default scene frames 12-18, 0.5-1.2 m
      // off, end within 2 cm after sim3); image_registrator could not place
      // them, as they see few points triangulated without them.
      summary.num_pending_images = static_cast<int>(held_out.size());
      LOG(INFO) << "lidar_mapper: " << num_initialised << " of "
                << model.images.size() << " images start at the pose of "
                << num_accepted << " accepted initial model(s), the others ("
                << summary.num_init_outliers
                << " registered outside a consensus) at their prior pose"
                << (options.register_pending_images && !held_out.empty()
                        ? "; those wait for image_registrator"
                        : std::string());
    }
  }
  summary.init_seconds = SecondsSince(stage_start);
  summary.init_cpu_seconds = CpuSeconds() - stage_cpu;

  // ---- 5. Iterations.
  stage_start = std::chrono::steady_clock::now();
  stage_cpu = CpuSeconds();
  std::vector<LineTrack> tracks;
  std::unordered_map<image_t, Rigid3d> input_poses;
  for (const Image& image : model.images) {
    input_poses[image.image_id] = image.cam_from_world;
  }
  for (int iteration = 0; iteration < options.max_num_iterations;
       ++iteration) {
    const auto iteration_start = std::chrono::steady_clock::now();
    LidarMapperIteration record;
    // What the guard restores when it undoes this iteration.
    const Reconstruction model_before = model;

    // Points: stock point_triangulator, poses and intrinsics fixed.
    const std::string poses_path = JoinPaths(work_path, "poses");
    const std::string triangulated_path = JoinPaths(work_path, "triangulated");
    Reconstruction active = PosesOnly(model);
    if (!held_out.empty()) {
      active.images.erase(
          std::remove_if(active.images.begin(), active.images.end(),
                         [&](const Image& image) {
                           return held_out.count(image.image_id) > 0;
                         }),
          active.images.end());
    }
    WriteReconstruction(poses_path, active, ModelFormat::kBinary);
    CreateDirIfNotExists(triangulated_path);
    colmap.Run("point_triangulator",
               {{"database_path", paths.database_path},
                {"image_path", paths.image_path},
                {"input_path", poses_path},
                {"output_path", triangulated_path},
                {"clear_points", "1"},
                {"Mapper.ba_refine_focal_length", "0"},
                {"Mapper.ba_refine_principal_point", "0"},
                {"Mapper.ba_refine_extra_params", "0"},
                {"Mapper.filter_max_reproj_error",
                 std::to_string(options.triangulation_max_error_px)},
                {"Mapper.num_threads", threads}});
    Reconstruction triangulated = ReadReconstruction(triangulated_path);
    // Keep our image order and poses; take cameras (unchanged) and the
    // observations from the triangulator.
    model.points3D = std::move(triangulated.points3D);
    model.point3D_file_order.clear();
    for (Image& image : model.images) {
      const Image* observed = triangulated.FindImage(image.image_id);
      image.points2D =
          observed != nullptr ? observed->points2D : std::vector<Point2D>();
    }
    model.lines3D.clear();
    // Observations of points the triangulator dropped for an image we lack
    // cannot occur: every image of ours was in its input.
    record.num_points = static_cast<int>(model.points3D.size());

    // Pending images: registered against this iteration's points; they join
    // the triangulation from the next iteration on.
    if (options.register_pending_images && !held_out.empty()) {
      record.num_registered_images = RegisterPendingImages(
          colmap, paths, options, triangulated_path,
          JoinPaths(work_path, "registered"), priors, &held_out, &model);
      summary.num_registered_pending += record.num_registered_images;
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
          AssociateWorkspaceLines(&database, held_out.empty() ? model : active,
                                  matching);
      LOG(INFO) << "lidar_mapper: association with pose sigma "
                << matching.pose_sigma_t_m << " m / "
                << matching.pose_sigma_r_deg << " deg: "
                << association.num_tracks << " tracks, mean length "
                << association.mean_track_length;
      tracks = LoadLineTracks(database, model);
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
    record.adjustment = adjuster.Solve(&model, &tracks);
    summary.adjustment_seconds += record.adjustment.solve_time_s;

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
      ++summary.num_rejected_iterations;
      summary.iterations.push_back(record);
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
      summary.num_reset_images += static_cast<int>(far_images.size());
    }
    LOG(INFO) << "lidar_mapper: iteration " << iteration + 1 << ": "
              << record.num_points << " points, " << record.num_line_tracks
              << " line tracks" << (use_lines ? "" : " (points only)")
              << "; pose change max " << record.max_position_change_m
              << " m / " << record.max_rotation_change_deg << " deg, mean "
              << record.mean_position_change_m << " m; "
              << record.adjustment.ToString();
    summary.iterations.push_back(record);
    if (use_lines && iteration > 0 && far_images.empty() &&
        record.num_registered_images == 0 &&
        record.max_position_change_m < options.max_position_change_m &&
        record.max_rotation_change_deg < options.max_rotation_change_deg) {
      summary.converged = true;
      break;
    }
  }
  if (!lidar_edges.empty()) {
    CheckLidarEdges(lidar_edges, input_poses, &model, &summary);
  }
  summary.iterations_seconds = SecondsSince(stage_start);
  summary.iterations_cpu_seconds = CpuSeconds() - stage_cpu;

  // ---- 6. Output.
  WriteReconstruction(paths.output_path, model, ModelFormat::kBinary);
  WriteLines3DPly(paths.lines_ply_path, model);
  summary.num_points = static_cast<int>(model.points3D.size());
  summary.num_lines = static_cast<int>(model.lines3D.size());
  summary.total_seconds = SecondsSince(start_time);
  summary.total_cpu_seconds = CpuSeconds() - start_cpu;
  return summary;
}

}  // namespace colmap_lidar
