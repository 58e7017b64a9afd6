#include "src/eval/real_data_evaluator.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <functional>
#include <iomanip>
#include <memory>
#include <sstream>
#include <thread>
#include <unordered_map>

#include <Eigen/Eigenvalues>

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "src/eval/eval_stats.h"
#include "src/eval/mesh_sampling.h"
#include "src/eval/nearest_neighbor.h"
#include "src/lidar/gicp_helpers.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {

// Value at quantile q of `values` (nearest rank); 0 when empty.
double Quantile(std::vector<double> values, double q) {
  if (values.empty()) {
    return 0.0;
  }
  const size_t k = std::min(
      values.size() - 1,
      static_cast<size_t>(std::floor(q * static_cast<double>(values.size()))));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

struct CellKeyHash {
  size_t operator()(const Eigen::Vector3i& key) const {
    return static_cast<size_t>(key.x()) * 73856093u ^
           static_cast<size_t>(key.y()) * 19349663u ^
           static_cast<size_t>(key.z()) * 83492791u;
  }
};

Eigen::Vector3i CellOf(const Eigen::Vector3d& point, double cell_m) {
  return Eigen::Vector3i(static_cast<int>(std::floor(point.x() / cell_m)),
                         static_cast<int>(std::floor(point.y() / cell_m)),
                         static_cast<int>(std::floor(point.z() / cell_m)));
}

double TrajectoryLength(const std::vector<Eigen::Vector3d>& centres) {
  double length = 0.0;
  for (size_t i = 1; i < centres.size(); ++i) {
    length += (centres[i] - centres[i - 1]).norm();
  }
  return length;
}

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

double CrispnessVoxelSize(const LidarScan& first_scan,
                          const RealDataEvaluationOptions& options) {
  if (options.crispness_voxel_size_m > 0.0) {
    return options.crispness_voxel_size_m;
  }
  std::vector<double> ranges;
  ranges.reserve(first_scan.size());
  for (const Eigen::Vector3f& point : first_scan.points) {
    const double range = point.cast<double>().norm();
    if (range >= options.registration.min_range_m &&
        range <= options.registration.max_range_m) {
      ranges.push_back(range);
    }
  }
  const double median_range = Quantile(std::move(ranges), 0.5);
  return std::clamp(median_range * options.crispness_voxel_angle_deg * M_PI /
                        180.0,
                    0.05, 0.3);
}

std::vector<Eigen::Vector3d> ThinScan(const LidarScan& scan, double voxel_m,
                                      const RealDataEvaluationOptions& options) {
  THROW_CHECK(voxel_m > 0.0, "ThinScan: voxel " << voxel_m << " m");
  struct Cell {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int count = 0;
    size_t order = 0;
  };
  std::unordered_map<Eigen::Vector3i, Cell, CellKeyHash> cells;
  for (const Eigen::Vector3f& point_f : scan.points) {
    const Eigen::Vector3d point = point_f.cast<double>();
    const double range = point.norm();
    if (!point.allFinite() || range < options.registration.min_range_m ||
        range > options.registration.max_range_m) {
      continue;
    }
    Cell& cell = cells[CellOf(point, voxel_m)];
    if (cell.count == 0) {
      cell.order = cells.size();
    }
    cell.sum += point;
    ++cell.count;
  }
  // In first-seen order, so that strided queries sample the whole scan
  // deterministically.
  std::vector<std::pair<size_t, Eigen::Vector3d>> ordered;
  ordered.reserve(cells.size());
  for (const auto& [key, cell] : cells) {
    ordered.emplace_back(cell.order, cell.sum / cell.count);
  }
  std::sort(ordered.begin(), ordered.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::Vector3d> thinned;
  thinned.reserve(ordered.size());
  for (const auto& entry : ordered) {
    thinned.push_back(entry.second);
  }
  return thinned;
}

CrispnessStats EvaluateCrispness(
    const std::vector<std::vector<Eigen::Vector3d>>& thinned_scans,
    const std::vector<Rigid3d>& world_from_lidar, double radius_m,
    const RealDataEvaluationOptions& options) {
  THROW_CHECK(options.Check(), "invalid RealDataEvaluation options");
  THROW_CHECK(thinned_scans.size() == world_from_lidar.size() &&
                  thinned_scans.size() >= 2,
              "Crispness needs >= 2 scans with one pose each, got "
                  << thinned_scans.size() << " scans and "
                  << world_from_lidar.size() << " poses");
  THROW_CHECK(radius_m > 0.0, "Crispness radius " << radius_m << " m");
  const size_t num_scans = thinned_scans.size();

  // All points in the world, and a hash grid of radius-sized cells.
  std::vector<Eigen::Vector3d> points;
  std::vector<uint32_t> scan_of_point;
  std::vector<size_t> scan_begin(num_scans + 1, 0);
  for (size_t s = 0; s < num_scans; ++s) {
    scan_begin[s] = points.size();
    for (const Eigen::Vector3d& point : thinned_scans[s]) {
      points.push_back(world_from_lidar[s] * point);
      scan_of_point.push_back(static_cast<uint32_t>(s));
    }
  }
  scan_begin[num_scans] = points.size();
  std::unordered_map<Eigen::Vector3i, std::vector<uint32_t>, CellKeyHash> grid;
  for (size_t i = 0; i < points.size(); ++i) {
    grid[CellOf(points[i], radius_m)].push_back(static_cast<uint32_t>(i));
  }

  // Queries: evenly strided points of every scan.
  std::vector<uint32_t> queries;
  for (size_t s = 0; s < num_scans; ++s) {
    const size_t count = scan_begin[s + 1] - scan_begin[s];
    const size_t stride = std::max<size_t>(
        1, (count + options.crispness_max_queries_per_scan - 1) /
               options.crispness_max_queries_per_scan);
    for (size_t k = 0; k < count; k += stride) {
      queries.push_back(static_cast<uint32_t>(scan_begin[s] + k));
    }
  }
  // Distance per query; negative: no plane.
  std::vector<double> distances(queries.size(), -1.0);
  const double radius_squared = radius_m * radius_m;
  ParallelFor(queries.size(), options.num_threads, [&](size_t begin,
                                                          size_t end) {
    std::vector<Eigen::Vector3d> neighbors;
    for (size_t q = begin; q < end; ++q) {
      const Eigen::Vector3d& query = points[queries[q]];
      const uint32_t own_scan = scan_of_point[queries[q]];
      const Eigen::Vector3i cell = CellOf(query, radius_m);
      neighbors.clear();
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = grid.find(cell + Eigen::Vector3i(dx, dy, dz));
            if (it == grid.end()) {
              continue;
            }
            for (const uint32_t index : it->second) {
              if (scan_of_point[index] != own_scan &&
                  (points[index] - query).squaredNorm() <= radius_squared) {
                neighbors.push_back(points[index]);
              }
            }
          }
        }
      }
      if (static_cast<int>(neighbors.size()) <
          options.crispness_min_neighbors) {
        continue;
      }
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (const Eigen::Vector3d& neighbor : neighbors) {
        centroid += neighbor;
      }
      centroid /= static_cast<double>(neighbors.size());
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (const Eigen::Vector3d& neighbor : neighbors) {
        const Eigen::Vector3d d = neighbor - centroid;
        covariance += d * d.transpose();
      }
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
      const Eigen::Vector3d eigenvalues = solver.eigenvalues();  // Ascending.
      if (!(eigenvalues(1) >=
                options.crispness_min_planarity * eigenvalues(2) &&
            eigenvalues(2) > 0.0)) {
        continue;
      }
      const Eigen::Vector3d normal = solver.eigenvectors().col(0);
      distances[q] = std::abs(normal.dot(query - centroid));
    }
  });

  CrispnessStats stats;
  stats.num_queries = queries.size();
  std::vector<double> valid;
  std::vector<std::vector<double>> per_frame(num_scans);
  for (size_t q = 0; q < queries.size(); ++q) {
    if (distances[q] >= 0.0) {
      valid.push_back(distances[q]);
      per_frame[scan_of_point[queries[q]]].push_back(distances[q]);
    }
  }
  stats.num_planes = valid.size();
  stats.coverage = queries.empty() ? 0.0
                                   : static_cast<double>(valid.size()) /
                                         static_cast<double>(queries.size());
  stats.median_m = Quantile(valid, 0.5);
  stats.p90_m = Quantile(std::move(valid), 0.9);
  for (std::vector<double>& frame : per_frame) {
    stats.frame_median_m.push_back(Quantile(std::move(frame), 0.5));
  }
  return stats;
}

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

MeshVsLidar EvaluateMeshVsLidar(const std::vector<Eigen::Vector3d>& vertices,
                                const std::vector<Eigen::Vector3i>& triangles,
                                const std::vector<Eigen::Vector3d>& lidar_points,
                                const RealDataEvaluationOptions& options,
                                const std::vector<bool>& in_view) {
  THROW_CHECK(options.Check(), "invalid RealDataEvaluation options");
  THROW_CHECK(in_view.empty() || in_view.size() == lidar_points.size(),
              "Mesh vs LIDAR: " << in_view.size() << " view flags for "
                                << lidar_points.size() << " points");
  THROW_CHECK(!triangles.empty(), "Mesh vs LIDAR: the mesh has no triangles");
  THROW_CHECK(!lidar_points.empty(), "Mesh vs LIDAR: no LIDAR points");
  MeshVsLidar result;
  result.thresholds_m = options.mesh_thresholds_m;
  result.num_lidar_points = lidar_points.size();
  result.mesh_area_m2 = TriangleMeshArea(vertices, triangles);
  const double density =
      std::min(options.mesh_sample_density_per_m2,
               result.mesh_area_m2 > 0.0
                   ? options.max_mesh_samples / result.mesh_area_m2
                   : options.mesh_sample_density_per_m2);
  const std::vector<Eigen::Vector3d> samples =
      SampleTriangleMesh(vertices, triangles, density,
                         static_cast<uint64_t>(options.seed));
  result.num_mesh_samples = samples.size();
  const std::vector<double> lidar_to_mesh =
      TriangleMeshIndex(vertices, triangles).NearestDistances(lidar_points);
  std::vector<double> mesh_to_lidar;
  if (!samples.empty()) {
    mesh_to_lidar = PointCloudIndex(lidar_points).NearestDistances(samples);
  }
  std::vector<double> in_view_to_mesh;
  for (size_t i = 0; i < in_view.size(); ++i) {
    if (in_view[i]) in_view_to_mesh.push_back(lidar_to_mesh[i]);
  }
  result.num_lidar_points_in_view = in_view_to_mesh.size();
  for (const double threshold : result.thresholds_m) {
    result.lidar_within.push_back(ShareBelow(lidar_to_mesh, threshold));
    result.mesh_within.push_back(ShareBelow(mesh_to_lidar, threshold));
    if (!in_view.empty()) {
      result.lidar_in_view_within.push_back(
          ShareBelow(in_view_to_mesh, threshold));
    }
  }
  return result;
}

std::vector<bool> InCameraView(const Reconstruction& model,
                               const std::vector<Eigen::Vector3d>& points,
                               double max_depth_m) {
  std::vector<bool> in_view(points.size(), false);
  for (const Image& image : model.images) {
    const auto camera = model.cameras.find(image.camera_id);
    if (camera == model.cameras.end()) continue;
    const double width = static_cast<double>(camera->second.width);
    const double height = static_cast<double>(camera->second.height);
    for (size_t i = 0; i < points.size(); ++i) {
      if (in_view[i]) continue;
      const Eigen::Vector3d point_in_cam = image.cam_from_world * points[i];
      if (!(point_in_cam.z() > 0.0 && point_in_cam.z() <= max_depth_m)) {
        continue;
      }
      const Eigen::Vector2d pixel = camera->second.ImgFromCam(point_in_cam);
      in_view[i] = pixel.x() >= 0.0 && pixel.x() < width && pixel.y() >= 0.0 &&
                   pixel.y() < height;
    }
  }
  return in_view;
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
  std::string database_dir = ".";
  const size_t slash = input.database_path.find_last_of('/');
  if (slash != std::string::npos) {
    database_dir = input.database_path.substr(0, slash);
  }

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
    const std::string scan_path =
        (!record->path.empty() && record->path[0] == '/')
            ? record->path
            : JoinPaths(database_dir, record->path);
    scans.push_back(ReadLidarScan(scan_path));
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
