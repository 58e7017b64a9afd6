#include "src/sfm/lidar_pose_graph.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <glog/logging.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/parallel.h"
#include "colmap_ext/util/resource_usage.h"
#include "src/lidar/gicp_helpers.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Chi-square(6) 99.9 % quantile: a used edge whose whitened squared
// residual exceeds it after the solve is reported as downweighted.
constexpr double kChi2Dof6Quantile999 = 22.458;


double AngleDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.normalized().angularDistance(b.normalized()) * 180.0 / kPi;
}

}  // namespace

bool LidarPoseGraphOptions::Check() const {
#define LIDAR_POSE_GRAPH_CHECK(condition, field)                      \
  if (!(condition)) {                                                 \
    LOG(ERROR) << "LidarPoseGraph." #field " = " << (field)           \
               << " is out of range (" #condition ")";                \
    return false;                                                     \
  }
  LIDAR_POSE_GRAPH_CHECK(loop_radius_m >= 0.0, loop_radius_m);
  LIDAR_POSE_GRAPH_CHECK(max_loop_candidates_per_frame >= 0,
                         max_loop_candidates_per_frame);
  LIDAR_POSE_GRAPH_CHECK(min_fitness >= 0.0 && min_fitness <= 1.0,
                         min_fitness);
  LIDAR_POSE_GRAPH_CHECK(min_loop_fitness >= 0.0 && min_loop_fitness <= 1.0,
                         min_loop_fitness);
  LIDAR_POSE_GRAPH_CHECK(max_rmse_voxels > 0.0, max_rmse_voxels);
  LIDAR_POSE_GRAPH_CHECK(consecutive_rmse_over_median >= 1.0,
                         consecutive_rmse_over_median);
  LIDAR_POSE_GRAPH_CHECK(max_prior_deviation_sigmas > 0.0,
                         max_prior_deviation_sigmas);
  LIDAR_POSE_GRAPH_CHECK(prior_position_sigma_m > 0.0, prior_position_sigma_m);
  LIDAR_POSE_GRAPH_CHECK(prior_rotation_sigma_deg > 0.0,
                         prior_rotation_sigma_deg);
  LIDAR_POSE_GRAPH_CHECK(robust_loss_scale > 0.0, robust_loss_scale);
  LIDAR_POSE_GRAPH_CHECK(max_num_iterations >= 1, max_num_iterations);
#undef LIDAR_POSE_GRAPH_CHECK
  return edge_noise.Check() && registration.Check();
}

Eigen::Matrix<double, 6, 6> SqrtInformation(
    const Eigen::Matrix<double, 6, 6>& information) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> solver(
      0.5 * (information + information.transpose()));
  const Eigen::Matrix<double, 6, 1> roots =
      solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return roots.asDiagonal() * solver.eigenvectors().transpose();
}

std::string LidarPoseGraphResult::Format() const {
  std::ostringstream out;
  int num_consecutive = 0;
  int num_loops = 0;
  for (const LidarPoseGraphEdge& edge : edges) {
    (edge.loop ? num_loops : num_consecutive) += 1;
  }
  out << "LIDAR pose graph: " << num_frames << " frames, voxel "
      << voxel_size_m << " m; " << num_used_edges - num_used_loops << " of "
      << num_consecutive << " consecutive edges and " << num_used_loops
      << " of " << num_loops << " loop candidates used, " << num_downweighted
      << " downweighted after the solve, " << num_isolated_frames
      << " frames without an edge (at their prior); registration "
      << registration_seconds << " s, solve " << solve_seconds << " s ("
      << solver_report << "); " << edge_noise.Format();
  if (num_dropped_relaxed_loops > 0) {
    out << "; " << num_dropped_relaxed_loops
        << " skip-one loops dropped (closures biased with them)";
  }
  return out.str();
}

namespace {

std::string FormatVector(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(4);
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

// The largest standard deviation of the translation that the information
// claims (the pseudo-inverse's translation block), metres: a corridor's axis
// shows here. Infinity when a direction has no information at all.
double WeakestTranslationSigma(const Eigen::Matrix<double, 6, 6>& information) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> solver(
      0.5 * (information + information.transpose()));
  const Eigen::Matrix<double, 6, 1>& values = solver.eigenvalues();
  if (!(values.maxCoeff() > 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  Eigen::Matrix<double, 6, 1> inverse = Eigen::Matrix<double, 6, 1>::Zero();
  for (int k = 0; k < 6; ++k) {
    if (values[k] <= 1e-12 * values.maxCoeff()) {
      return std::numeric_limits<double>::infinity();
    }
    inverse[k] = 1.0 / values[k];
  }
  const Eigen::Matrix<double, 6, 6> covariance = solver.eigenvectors() *
                                                 inverse.asDiagonal() *
                                                 solver.eigenvectors().transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> translation(
      covariance.bottomRightCorner<3, 3>());
  return std::sqrt(translation.eigenvalues().maxCoeff());
}

}  // namespace

std::string LidarPoseGraphResult::FormatEdges() const {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  for (const LidarPoseGraphEdge& edge : edges) {
    out << (edge.loop ? "loop " : "next ") << edge.i << " -> " << edge.j
        << ": fitness " << edge.registration.fitness << ", rmse "
        << edge.registration.rmse_m << " m, converged "
        << edge.registration.converged << ", guess "
        << edge.registration.guess_index << ", off priors "
        << edge.prior_deviation_m << " m / " << edge.prior_deviation_deg
        << " deg, "
        << (edge.used ? (edge.downweighted ? "downweighted" : "kept")
                      : "not used")
        << ", t " << FormatVector(edge.registration.target_from_source.translation)
        << " m, weakest translation sigma "
        << WeakestTranslationSigma(edge.used ? edge.information
                                             : edge.registration.information)
        << " m"
        << (edge.used ? ", residual " + std::to_string(edge.residual_m) +
                            " m / " + std::to_string(edge.residual_deg) +
                            " deg, whitened " +
                            std::to_string(edge.whitened_residual)
                      : std::string())
        << "\n";
  }
  return out.str();
}

LidarPoseGraphResult SolveLidarPoseGraph(
    const std::vector<LidarPoseGraphFrame>& frames,
    const LidarPoseGraphOptions& options) {
  THROW_CHECK(options.Check(), "invalid LidarPoseGraph options (see the log)");
  THROW_CHECK(frames.size() >= 2, "LIDAR pose graph: " << frames.size()
                                                       << " frames, need 2");
  const int n = static_cast<int>(frames.size());
  for (const LidarPoseGraphFrame& frame : frames) {
    THROW_CHECK(frame.scan != nullptr,
                "LIDAR pose graph: frame " << frame.name << " has no scan");
  }
  LidarPoseGraphResult result;
  result.num_frames = n;
  for (const LidarPoseGraphFrame& frame : frames) {
    result.cam_from_lidar.push_back(frame.cam_from_lidar);
  }
  const auto registration_start = std::chrono::steady_clock::now();

  // Every scan at the first scan's voxel (one resolution per graph).
  ScanRegistrationOptions registration = options.registration;
  registration.num_threads = options.num_threads;
  result.voxel_size_m = VoxelSizeForScan(*frames[0].scan, registration);
  std::vector<std::unique_ptr<PreparedScan>> scans;
  scans.reserve(n);
  for (const LidarPoseGraphFrame& frame : frames) {
    try {
      scans.push_back(std::make_unique<PreparedScan>(
          *frame.scan, registration, result.voxel_size_m));
    } catch (const Error& error) {
      THROW_CHECK(false, "LIDAR pose graph, frame " << frame.name << ": "
                                                    << error.what());
    }
  }

  std::vector<Rigid3d> prior_world_from_lidar(n);
  for (int k = 0; k < n; ++k) {
    prior_world_from_lidar[k] =
        frames[k].prior_world_from_cam * frames[k].cam_from_lidar;
  }
  const auto prior_relative = [&](int i, int j) {
    return prior_world_from_lidar[i].Inverse() * prior_world_from_lidar[j];
  };
  // Gate on the deviation from the priors' relative pose (relative sigma =
  // sqrt(2) x per-frame sigma; 3D norm against sqrt(3) per-axis sigmas).
  const double max_deviation_m = options.max_prior_deviation_sigmas *
                                 std::sqrt(2.0) * std::sqrt(3.0) *
                                 options.prior_position_sigma_m;
  const double max_deviation_deg = options.max_prior_deviation_sigmas *
                                   std::sqrt(2.0) *
                                   options.prior_rotation_sigma_deg;
  const auto passes_gates_but_rmse = [&](const LidarPoseGraphEdge& edge,
                                         bool loop) {
    return edge.registration.fitness >=
               (loop ? options.min_loop_fitness : options.min_fitness) &&
           edge.prior_deviation_m <= max_deviation_m &&
           edge.prior_deviation_deg <= max_deviation_deg &&
           edge.registration.num_correspondences > 6;
  };
  // Progress at most every 20 s (a registration takes about a second;
  // a 600-frame graph registers for minutes).
  int num_registrations = 0;
  auto last_progress = std::chrono::steady_clock::now();
  std::mutex progress_mutex;  // loop edges register in parallel
  const auto log_progress = [&](int frame, bool loops) {
    const std::lock_guard<std::mutex> lock(progress_mutex);
    ++num_registrations;
    if (SecondsSince(last_progress) >= 20.0) {
      last_progress = std::chrono::steady_clock::now();
      LOG(INFO) << "LIDAR pose graph: " << num_registrations
                << " registrations, " << (loops ? "loops" : "consecutive edges")
                << " at frame " << frame + 1 << " of " << n << ", "
                << SecondsSince(registration_start) << " s";
    }
  };
  const auto register_edge = [&](int i, int j, bool loop,
                                 const std::vector<Rigid3d>& guesses) {
    log_progress(i, loop);
    LidarPoseGraphEdge edge;
    edge.i = i;
    edge.j = j;
    edge.loop = loop;
    edge.registration =
        RegisterScans(*scans[j], *scans[i], guesses, registration);
    const Rigid3d prior = prior_relative(i, j);
    edge.prior_deviation_m = (edge.registration.target_from_source.translation -
                              prior.translation)
                                 .norm();
    edge.prior_deviation_deg =
        AngleDeg(edge.registration.target_from_source.rotation, prior.rotation);
    edge.used = passes_gates_but_rmse(edge, loop) &&
                edge.registration.rmse_m <=
                    options.max_rmse_voxels * edge.registration.voxel_size_m;
    return edge;
  };

  // Consecutive edges; consecutive_index[i] = edge i -> i + 1.
  std::vector<int> consecutive_index(n, -1);
  for (int i = 0; i + 1 < n; ++i) {
    std::vector<Rigid3d> guesses = {prior_relative(i, i + 1)};
    if (i > 0 && result.edges[consecutive_index[i - 1]].used) {
      // Constant velocity: the previous step once more.
      guesses.push_back(
          result.edges[consecutive_index[i - 1]].registration.target_from_source);
    }
    consecutive_index[i] = static_cast<int>(result.edges.size());
    result.edges.push_back(register_edge(i, i + 1, /*loop=*/false, guesses));
  }
  // The rmse gate in voxels fits clean synthetic scans; a real scanner's
  // residuals after a correct registration are set by its own range noise,
  // laser offsets and motion (KITTI's HDL-64E: 0.06 m at a 0.13 m voxel on
  // every consecutive pair, measured). So a consecutive edge may also pass
  // when its rmse is within consecutive_rmse_over_median of the median rmse
  // of all consecutive edges that pass the other gates: the scanner's noise
  // floor, estimated from the recording itself. Loop edges keep the strict
  // gate (a loop that slid along a straight street has an rmse close to the
  // floor).
  double consecutive_noise_floor_m = 0.0;
  {
    std::vector<double> rmses;
    for (int i = 0; i + 1 < n; ++i) {
      const LidarPoseGraphEdge& edge = result.edges[consecutive_index[i]];
      if (passes_gates_but_rmse(edge, /*loop=*/false)) {
        rmses.push_back(edge.registration.rmse_m);
      }
    }
    if (!rmses.empty()) {
      std::nth_element(rmses.begin(), rmses.begin() + rmses.size() / 2,
                       rmses.end());
      consecutive_noise_floor_m = rmses[rmses.size() / 2];
      for (int i = 0; i + 1 < n; ++i) {
        LidarPoseGraphEdge& edge = result.edges[consecutive_index[i]];
        if (!edge.used && passes_gates_but_rmse(edge, /*loop=*/false) &&
            edge.registration.rmse_m <=
                options.consecutive_rmse_over_median *
                    consecutive_noise_floor_m) {
          edge.used = true;
        }
      }
    }
  }
  // lidar_i_from_lidar_j composed of the consecutive edges i -> ... -> j;
  // false when one of them is not used.
  const auto chain_of_consecutive = [&](int i, int j, Rigid3d* chained) {
    *chained = Rigid3d();
    for (int k = i; k < j; ++k) {
      const LidarPoseGraphEdge& step = result.edges[consecutive_index[k]];
      if (!step.used) {
        return false;
      }
      *chained = *chained * step.registration.target_from_source;
    }
    return true;
  };
  // Loop candidates.
  if ((options.loop_radius_m > 0.0 && options.max_loop_candidates_per_frame > 0) ||
      options.skip_one_candidates) {
    struct LoopTask {
      int i = 0;
      int j = 0;
      std::vector<Rigid3d> guesses;
    };
    std::vector<LoopTask> loop_tasks;
    for (int i = 0; i < n; ++i) {
      std::vector<std::pair<double, int>> candidates;
      for (int j = i + 2; j < n; ++j) {
        const double distance = (frames[i].prior_world_from_cam.translation -
                                 frames[j].prior_world_from_cam.translation)
                                    .norm();
        if (distance <= options.loop_radius_m) {
          candidates.emplace_back(distance, j);
        }
      }
      std::sort(candidates.begin(), candidates.end());
      if (static_cast<int>(candidates.size()) >
          options.max_loop_candidates_per_frame) {
        candidates.resize(options.max_loop_candidates_per_frame);
      }
      if (options.skip_one_candidates && i + 2 < n &&
          std::none_of(candidates.begin(), candidates.end(),
                       [i](const std::pair<double, int>& candidate) {
                         return candidate.second == i + 2;
                       })) {
        candidates.emplace_back(0.0, i + 2);
      }
      for (const auto& [distance, j] : candidates) {
        LoopTask task;
        task.i = i;
        task.j = j;
        task.guesses = {prior_relative(i, j)};
        Rigid3d chained;
        if (chain_of_consecutive(i, j, &chained)) {
          task.guesses.push_back(chained);
        }
        loop_tasks.push_back(std::move(task));
      }
    }
    // The loop registrations depend on the consecutive edges only: they run
    // in parallel (each with the same registration options, so the same
    // edges as one after the other) and join the graph in candidate order.
    std::vector<LidarPoseGraphEdge> loop_edges(loop_tasks.size());
    ParallelFor(0, static_cast<int>(loop_tasks.size()), options.num_threads,
                [&](int t) {
                  const LoopTask& task = loop_tasks[t];
                  loop_edges[t] = register_edge(task.i, task.j,
                                                /*loop=*/true, task.guesses);
                });
    for (LidarPoseGraphEdge& edge : loop_edges) {
      // A skip-one loop spans two steps of the same walk: the consecutive
      // edges' noise-floor gate applies to it as to them.
      if (!edge.used && edge.j == edge.i + 2 &&
          passes_gates_but_rmse(edge, true) &&
          edge.registration.rmse_m <= options.consecutive_rmse_over_median *
                                          consecutive_noise_floor_m) {
        edge.used = true;
        edge.relaxed_loop = true;
      }
      result.edges.push_back(std::move(edge));
    }
  }
  result.registration_seconds = SecondsSince(registration_start);

  // ---- The edges' noise from the loop closures.
  {
    const auto closures_of_used_loops = [&]() {
      std::vector<LidarLoopClosure> closures;
      for (const LidarPoseGraphEdge& edge : result.edges) {
        if (!edge.loop || !edge.used) {
          continue;
        }
        Rigid3d chained;
        if (chain_of_consecutive(edge.i, edge.j, &chained)) {
          LidarLoopClosure closure;
          closure.i = edge.i;
          closure.j = edge.j;
          closure.delta =
              ClosureDelta(chained, edge.registration.target_from_source);
          closures.push_back(closure);
        }
      }
      return closures;
    };
    result.edge_noise = EstimateLidarEdgeNoise(
        closures_of_used_loops(), FloorSigma(registration), options.edge_noise);
    result.edge_noise_before_drop = result.edge_noise;
    if (result.edge_noise.biased.any()) {
      int num_dropped = 0;
      for (LidarPoseGraphEdge& edge : result.edges) {
        if (edge.relaxed_loop && edge.used) {
          edge.used = false;
          ++num_dropped;
        }
      }
      if (num_dropped > 0) {
        LOG(WARNING) << "LIDAR pose graph: " << result.edge_noise.Format()
                     << "; the " << num_dropped
                     << " skip-one loops admitted by the consecutive edges' "
                        "noise floor are dropped";
        result.num_dropped_relaxed_loops = num_dropped;
        result.edge_noise = EstimateLidarEdgeNoise(closures_of_used_loops(),
                                                   FloorSigma(registration),
                                                   options.edge_noise);
      }
    }
    for (LidarPoseGraphEdge& edge : result.edges) {
      edge.information =
          result.edge_noise.estimated
              ? InflateInformation(
                    CapInformation(edge.registration.hessian,
                                   result.edge_noise.cap_sigma),
                    result.edge_noise.added_variance)
              : edge.registration.information;
    }
  }

  // ---- Solve.
  const auto solve_start = std::chrono::steady_clock::now();
  std::vector<Rigid3d> poses(n);
  for (int k = 0; k < n; ++k) {
    poses[k] = frames[k].prior_world_from_cam;
    poses[k].rotation.normalize();
  }
  // Start from the chain of consecutive edges where it is unbroken (the
  // priors alone are far from the LIDAR's relative poses; LM from them
  // needs more iterations and risks local minima), re-anchored to the
  // prior at each break.
  for (int i = 0; i + 1 < n; ++i) {
    const LidarPoseGraphEdge& edge = result.edges[consecutive_index[i]];
    if (edge.used) {
      poses[i + 1] = poses[i] * frames[i].cam_from_lidar *
                     edge.registration.target_from_source *
                     frames[i + 1].cam_from_lidar.Inverse();
    }
  }
  // The chain hangs from frame 0's prior: move it as a whole onto the priors
  // (mean of the centre offsets) so the priors start balanced.
  {
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    for (int k = 0; k < n; ++k) {
      offset += frames[k].prior_world_from_cam.translation - poses[k].translation;
    }
    offset /= n;
    for (Rigid3d& pose : poses) {
      pose.translation += offset;
    }
  }

  ceres::Problem problem;
  ceres::EigenQuaternionManifold* quaternion_manifold =
      new ceres::EigenQuaternionManifold;
  const double rotation_sigma_rad =
      options.prior_rotation_sigma_deg / std::sqrt(3.0) * kPi / 180.0;
  for (int k = 0; k < n; ++k) {
    problem.AddResidualBlock(
        WorldPosePriorCostFunctor::Create(frames[k].prior_world_from_cam,
                                          options.prior_position_sigma_m,
                                          rotation_sigma_rad),
        nullptr, poses[k].rotation.coeffs().data(),
        poses[k].translation.data());
    problem.SetManifold(poses[k].rotation.coeffs().data(),
                        quaternion_manifold);
  }
  std::vector<int> num_edges_of_frame(n, 0);
  for (LidarPoseGraphEdge& edge : result.edges) {
    if (!edge.used) {
      continue;
    }
    ++result.num_used_edges;
    result.num_used_loops += edge.loop ? 1 : 0;
    ++num_edges_of_frame[edge.i];
    ++num_edges_of_frame[edge.j];
    problem.AddResidualBlock(
        RelativePoseCostFunctor::Create(
            edge.registration.target_from_source, frames[edge.i].cam_from_lidar,
            frames[edge.j].cam_from_lidar, SqrtInformation(edge.information)),
        new ceres::CauchyLoss(options.robust_loss_scale),
        poses[edge.i].rotation.coeffs().data(),
        poses[edge.i].translation.data(),
        poses[edge.j].rotation.coeffs().data(),
        poses[edge.j].translation.data());
  }
  for (int k = 0; k < n; ++k) {
    result.num_isolated_frames += num_edges_of_frame[k] == 0 ? 1 : 0;
  }
  ceres::Solver::Options solver_options;
  solver_options.minimizer_type = ceres::TRUST_REGION;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.max_num_iterations;
  solver_options.function_tolerance = 1e-10;
  solver_options.parameter_tolerance = 1e-10;
  solver_options.num_threads = NumThreadsOrAll(options.num_threads);
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  {
    std::ostringstream report;
    report << summary.iterations.size() << " LM iterations, cost "
           << summary.initial_cost << " -> " << summary.final_cost << ", "
           << (summary.IsSolutionUsable() ? "usable" : "NOT usable");
    result.solver_report = report.str();
  }
  THROW_CHECK(summary.IsSolutionUsable(),
              "LIDAR pose graph: Ceres failed: " << summary.message);

  // Per-edge report.
  for (LidarPoseGraphEdge& edge : result.edges) {
    const Rigid3d solved =
        (poses[edge.i] * frames[edge.i].cam_from_lidar).Inverse() *
        (poses[edge.j] * frames[edge.j].cam_from_lidar);
    edge.residual_m =
        (solved.translation - edge.registration.target_from_source.translation)
            .norm();
    edge.residual_deg =
        AngleDeg(solved.rotation, edge.registration.target_from_source.rotation);
    if (!edge.used) {
      continue;
    }
    const RelativePoseCostFunctor functor(
        edge.registration.target_from_source, frames[edge.i].cam_from_lidar,
        frames[edge.j].cam_from_lidar, SqrtInformation(edge.information));
    double residuals[6];
    functor(poses[edge.i].rotation.coeffs().data(),
            poses[edge.i].translation.data(),
            poses[edge.j].rotation.coeffs().data(),
            poses[edge.j].translation.data(), residuals);
    const double squared =
        Eigen::Map<const Eigen::Matrix<double, 6, 1>>(residuals).squaredNorm();
    edge.whitened_residual = std::sqrt(squared);
    edge.downweighted = squared > kChi2Dof6Quantile999;
    result.num_downweighted += edge.downweighted ? 1 : 0;
  }
  result.world_from_cam = poses;
  result.solve_seconds = SecondsSince(solve_start);
  return result;
}

LidarPoseGraphResult LidarGraphPoses(const Database& database,
                                     const LidarPoseGraphOptions& options,
                                     Reconstruction* model) {
  THROW_CHECK(model != nullptr, "LidarGraphPoses: no model");
  std::vector<Image*> images;
  for (Image& image : model->images) {
    images.push_back(&image);
  }
  std::sort(images.begin(), images.end(),
            [](const Image* a, const Image* b) { return a->name < b->name; });
  std::vector<LidarScan> scans;
  scans.reserve(images.size());
  std::vector<LidarPoseGraphFrame> frames;
  std::vector<Image*> frame_images;
  for (Image* image : images) {
    const std::optional<LidarScanRecord> record =
        database.ReadLidarScan(image->image_id);
    if (!record) {
      LOG(WARNING) << "LIDAR pose graph: image " << image->name
                   << " has no LIDAR scan; it keeps its pose";
      continue;
    }
    scans.push_back(
        ReadLidarScan(LidarScanFilePath(database.path(), record->path)));
    LidarPoseGraphFrame frame;
    frame.name = image->name;
    frame.prior_world_from_cam = image->cam_from_world.Inverse();
    frame.cam_from_lidar = record->cam_from_lidar;
    frames.push_back(frame);
    frame_images.push_back(image);
  }
  for (size_t k = 0; k < frames.size(); ++k) {
    frames[k].scan = &scans[k];
  }
  LidarPoseGraphResult result = SolveLidarPoseGraph(frames, options);
  for (size_t k = 0; k < frames.size(); ++k) {
    frame_images[k]->cam_from_world = result.world_from_cam[k].Inverse();
    result.image_ids.push_back(frame_images[k]->image_id);
  }
  return result;
}

}  // namespace colmap_lidar
