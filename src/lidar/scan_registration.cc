#include "src/lidar/scan_registration.h"

#include <algorithm>
#include <cmath>
#include <mutex>

#include <Eigen/Eigenvalues>
#include <glog/logging.h>
#include <pcl/common/transforms.h>
#include <pcl/registration/gicp.h>
#include <pcl/search/kdtree.h>

#include "colmap_ext/util/logging.h"
#include "src/lidar/gicp_helpers.h"

namespace colmap_lidar {
namespace {

using KdTree = pcl::search::KdTree<pcl::PointXYZ>;
using Gicp =
    pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>;

constexpr size_t kMinNumPoints = 10;
constexpr double kMinAutoVoxelM = 0.1;
constexpr double kMaxAutoVoxelM = 0.5;
constexpr double kPi = 3.14159265358979323846;

// One resolution of a prepared scan.
struct Level {
  GicpCloud::Ptr cloud;
  std::shared_ptr<GicpCovariances> covariances;
  std::vector<Eigen::Vector3d> normals;
  KdTree::Ptr tree;
  double voxel_size_m = 0.0;
};

void PrepareLevel(const LidarScan& scan, const ScanRegistrationOptions& options,
                  double voxel_size_m, Level* level) {
  level->voxel_size_m = voxel_size_m;
  level->cloud = RangeFilterAndDownsample(scan, options.min_range_m,
                                          options.max_range_m, voxel_size_m);
  THROW_CHECK(level->cloud->size() >= kMinNumPoints,
              "scan registration: only "
                  << level->cloud->size()
                  << " points left after the range filter and a voxel grid "
                     "of "
                  << voxel_size_m << " m");
  level->covariances = std::make_shared<GicpCovariances>(
      ComputeGicpCovariances(level->cloud, options.num_neighbors,
                             options.num_threads, &level->normals));
  level->tree.reset(new KdTree);
  level->tree->setInputCloud(level->cloud);
}

struct Overlap {
  double fitness = 0.0;
  double rmse_m = 0.0;
  int num_inliers = 0;
  Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
};

// Nearest target point of each source point moved by target_from_source;
// those within max_distance_m are correspondences, with the point-to-plane
// residual r = n . (T p - q) and its Jacobian w.r.t. a right perturbation
// T Exp(delta): [p x (R^T n); R^T n] (see the header).
Overlap EvaluateOverlap(const Level& source, const Level& target,
                        const Rigid3d& target_from_source,
                        double max_distance_m, int num_threads) {
  const size_t n = source.cloud->size();
  const Eigen::Matrix3d rotation =
      target_from_source.rotation.normalized().toRotationMatrix();
  std::vector<int> nearest(n, -1);
  std::vector<double> residuals(n, 0.0);
  const float max_distance2 = static_cast<float>(max_distance_m * max_distance_m);
  ParallelFor(n, num_threads, [&](size_t begin, size_t end) {
    pcl::Indices indices(1);
    std::vector<float> distances2(1);
    for (size_t i = begin; i < end; ++i) {
      const Eigen::Vector3d p =
          (*source.cloud)[i].getVector3fMap().cast<double>();
      const Eigen::Vector3d moved = target_from_source * p;
      pcl::PointXYZ query(static_cast<float>(moved.x()),
                          static_cast<float>(moved.y()),
                          static_cast<float>(moved.z()));
      if (target.tree->nearestKSearch(query, 1, indices, distances2) == 1 &&
          distances2[0] <= max_distance2) {
        nearest[i] = indices[0];
        const Eigen::Vector3d q =
            (*target.cloud)[indices[0]].getVector3fMap().cast<double>();
        residuals[i] = target.normals[indices[0]].dot(moved - q);
      }
    }
  });
  Overlap overlap;
  double sum_squares = 0.0;
  for (size_t i = 0; i < n; ++i) {
    if (nearest[i] < 0) {
      continue;
    }
    ++overlap.num_inliers;
    sum_squares += residuals[i] * residuals[i];
    const Eigen::Vector3d p = (*source.cloud)[i].getVector3fMap().cast<double>();
    const Eigen::Vector3d normal_in_source =
        rotation.transpose() * target.normals[nearest[i]];
    Eigen::Matrix<double, 6, 1> jacobian;
    jacobian << p.cross(normal_in_source), normal_in_source;
    overlap.hessian += jacobian * jacobian.transpose();
  }
  overlap.fitness = n > 0 ? static_cast<double>(overlap.num_inliers) / n : 0.0;
  overlap.rmse_m = overlap.num_inliers > 0
                       ? std::sqrt(sum_squares / overlap.num_inliers)
                       : 0.0;
  if (overlap.num_inliers > 6) {
    const double variance = sum_squares / (overlap.num_inliers - 6);
    overlap.hessian /= std::max(variance, 1e-12);
  } else {
    overlap.hessian.setZero();
  }
  return overlap;
}

// GICP of source onto target from `guess`; returns target_from_source.
Rigid3d RunGicp(const Level& source, const Level& target, const Rigid3d& guess,
                double max_correspondence_distance_m,
                const ScanRegistrationOptions& options, bool* converged) {
  Gicp gicp;
  gicp.setInputSource(source.cloud);
  gicp.setSourceCovariances(source.covariances);
  gicp.setInputTarget(target.cloud);
  gicp.setTargetCovariances(target.covariances);
  gicp.setSearchMethodTarget(target.tree, /*force_no_recompute=*/true);
  gicp.setMaxCorrespondenceDistance(max_correspondence_distance_m);
  gicp.setMaximumIterations(options.max_iterations);
  gicp.setTransformationEpsilon(options.transformation_epsilon);
  gicp.setRotationEpsilon(options.transformation_epsilon);
  GicpCloud aligned;
  gicp.align(aligned, ToMatrix4f(guess));
  const Eigen::Matrix4f result = gicp.getFinalTransformation();
  *converged = gicp.hasConverged() && result.allFinite();
  return result.allFinite() ? FromMatrix4f(result) : guess;
}

// Point-to-plane Gauss-Newton with the correspondences re-found at every
// iteration (Chen and Medioni 1992), from `guess`. Run next to GICP because
// GICP's plane-to-plane cost is nearly flat along a direction that only a few
// surfaces constrain (the axis of a corridor: window recesses and door jambs
// among long walls): measured on the synthetic corridor, PCL's GICP ends
// where it starts along the axis (0.6 m off stays 0.6 m off), while this cost
// still falls to the truth (2 cm). Stops when the update moves no point
// within 10 m by more than 1 % of a voxel, at max_iterations, or when
// fewer than 7 correspondences remain.
// *converged (optional) tells whether the update criterion was met.
Rigid3d RefinePointToPlane(const Level& source, const Level& target,
                           const Rigid3d& guess, double max_distance_m,
                           int max_iterations, int num_threads,
                           bool* converged = nullptr) {
  if (converged != nullptr) {
    *converged = false;
  }
  Rigid3d target_from_source = guess;
  const size_t n = source.cloud->size();
  const float max_distance2 =
      static_cast<float>(max_distance_m * max_distance_m);
  // A regular subsample of at most kMaxPoints source points: enough for six
  // unknowns, and it keeps the share of the rare surfaces that fix a weak
  // direction, at a fraction of the nearest-neighbour queries.
  constexpr size_t kMaxPoints = 6000;
  const size_t stride = std::max<size_t>(1, (n + kMaxPoints - 1) / kMaxPoints);
  const size_t num_samples = (n + stride - 1) / stride;
  struct NormalEquations {
    size_t begin = 0;
    Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> gradient = Eigen::Matrix<double, 6, 1>::Zero();
    int count = 0;
  };
  int iteration = 0;
  for (; iteration < max_iterations; ++iteration) {
    const Eigen::Matrix3d rotation =
        target_from_source.rotation.normalized().toRotationMatrix();
    // Per-chunk normal equations, summed in chunk order afterwards
    // (deterministic for a given thread count).
    std::vector<NormalEquations> chunks;
    std::mutex chunks_mutex;
    ParallelFor(num_samples, num_threads, [&](size_t begin, size_t end) {
      NormalEquations local;
      local.begin = begin;
      pcl::Indices indices(1);
      std::vector<float> distances2(1);
      for (size_t sample = begin; sample < end; ++sample) {
        const size_t i = sample * stride;
        const Eigen::Vector3d p =
            (*source.cloud)[i].getVector3fMap().cast<double>();
        const Eigen::Vector3d moved = target_from_source * p;
        const pcl::PointXYZ query(static_cast<float>(moved.x()),
                                  static_cast<float>(moved.y()),
                                  static_cast<float>(moved.z()));
        if (target.tree->nearestKSearch(query, 1, indices, distances2) != 1 ||
            distances2[0] > max_distance2) {
          continue;
        }
        const Eigen::Vector3d& normal = target.normals[indices[0]];
        const Eigen::Vector3d q =
            (*target.cloud)[indices[0]].getVector3fMap().cast<double>();
        const double residual = normal.dot(moved - q);
        const Eigen::Vector3d normal_in_source = rotation.transpose() * normal;
        Eigen::Matrix<double, 6, 1> jacobian;
        jacobian << p.cross(normal_in_source), normal_in_source;
        local.hessian += jacobian * jacobian.transpose();
        local.gradient += jacobian * residual;
        ++local.count;
      }
      const std::lock_guard<std::mutex> lock(chunks_mutex);
      chunks.push_back(local);
    });
    std::sort(chunks.begin(), chunks.end(),
              [](const NormalEquations& a, const NormalEquations& b) {
                return a.begin < b.begin;
              });
    Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> gradient = Eigen::Matrix<double, 6, 1>::Zero();
    int count = 0;
    for (const NormalEquations& chunk : chunks) {
      hessian += chunk.hessian;
      gradient += chunk.gradient;
      count += chunk.count;
    }
    if (count < 7) {
      break;
    }
    // A little Levenberg damping keeps a direction with no information
    // (a featureless corridor) where it is instead of sending it away.
    hessian.diagonal() += 1e-6 * hessian.diagonal().cwiseMax(1e-9);
    const Eigen::Matrix<double, 6, 1> delta = -hessian.ldlt().solve(gradient);
    if (!delta.allFinite()) {
      break;
    }
    const Eigen::Vector3d omega = delta.head<3>();
    const double angle = omega.norm();
    const Eigen::Quaterniond step_rotation =
        angle > 0.0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, omega / angle))
                    : Eigen::Quaterniond::Identity();
    // Right perturbation T * Exp(delta), to first order in the translation.
    target_from_source.translation += rotation * delta.tail<3>();
    target_from_source.rotation =
        (target_from_source.rotation * step_rotation).normalized();
    // Converged: the step moves no point at 10 m by 1 % of a voxel.
    if (delta.tail<3>().norm() + 10.0 * angle < 1e-2 * source.voxel_size_m) {
      ++iteration;
      if (converged != nullptr) {
        *converged = true;
      }
      break;
    }
  }
  VLOG(2) << "point-to-plane: " << iteration << " iterations, moved "
          << (target_from_source.translation - guess.translation).norm()
          << " m";
  return target_from_source;
}

}  // namespace

struct PreparedScan::Data {
  Level fine;
  Level coarse;
};

bool ScanRegistrationOptions::Check() const {
#define SCAN_REGISTRATION_CHECK(condition, field)                       \
  if (!(condition)) {                                                   \
    LOG(ERROR) << "ScanRegistration." #field " = " << (field)           \
               << " is out of range (" #condition ")";                  \
    return false;                                                       \
  }
  SCAN_REGISTRATION_CHECK(min_range_m >= 0.0, min_range_m);
  SCAN_REGISTRATION_CHECK(max_range_m > min_range_m, max_range_m);
  SCAN_REGISTRATION_CHECK(voxel_size_m >= 0.0, voxel_size_m);
  SCAN_REGISTRATION_CHECK(voxel_angle_deg > 0.0, voxel_angle_deg);
  SCAN_REGISTRATION_CHECK(coarse_voxel_factor >= 1.0, coarse_voxel_factor);
  SCAN_REGISTRATION_CHECK(coarse_max_correspondence_distance_m > 0.0,
                          coarse_max_correspondence_distance_m);
  SCAN_REGISTRATION_CHECK(fine_correspondence_voxels > 0.0,
                          fine_correspondence_voxels);
  SCAN_REGISTRATION_CHECK(max_iterations >= 1, max_iterations);
  SCAN_REGISTRATION_CHECK(transformation_epsilon > 0.0,
                          transformation_epsilon);
  SCAN_REGISTRATION_CHECK(num_neighbors >= 3, num_neighbors);
  SCAN_REGISTRATION_CHECK(point_to_plane_iterations >= 0,
                          point_to_plane_iterations);
  SCAN_REGISTRATION_CHECK(min_translation_sigma_m > 0.0,
                          min_translation_sigma_m);
  SCAN_REGISTRATION_CHECK(min_rotation_sigma_deg > 0.0, min_rotation_sigma_deg);
#undef SCAN_REGISTRATION_CHECK
  return true;
}

double VoxelSizeForScan(const LidarScan& scan,
                        const ScanRegistrationOptions& options) {
  if (options.voxel_size_m > 0.0) {
    return options.voxel_size_m;
  }
  std::vector<float> ranges;
  ranges.reserve(scan.size());
  for (const Eigen::Vector3f& point : scan.points) {
    const float range = point.norm();
    if (range >= options.min_range_m && range <= options.max_range_m) {
      ranges.push_back(range);
    }
  }
  if (ranges.empty()) {
    return kMaxAutoVoxelM;
  }
  std::nth_element(ranges.begin(), ranges.begin() + ranges.size() / 2,
                   ranges.end());
  const double median_range = ranges[ranges.size() / 2];
  return std::clamp(median_range * options.voxel_angle_deg * kPi / 180.0,
                    kMinAutoVoxelM, kMaxAutoVoxelM);
}

PreparedScan::PreparedScan(const LidarScan& scan,
                           const ScanRegistrationOptions& options,
                           double voxel_size_m)
    : data_(std::make_unique<Data>()) {
  THROW_CHECK(options.Check(), "invalid ScanRegistration options");
  const double voxel =
      voxel_size_m > 0.0 ? voxel_size_m : VoxelSizeForScan(scan, options);
  PrepareLevel(scan, options, voxel, &data_->fine);
  PrepareLevel(scan, options, voxel * options.coarse_voxel_factor,
               &data_->coarse);
}

PreparedScan::~PreparedScan() = default;

size_t PreparedScan::NumPoints() const { return data_->fine.cloud->size(); }

double PreparedScan::VoxelSize() const { return data_->fine.voxel_size_m; }

ScanRegistrationResult RegisterScans(
    const PreparedScan& source, const PreparedScan& target,
    const std::vector<Rigid3d>& target_from_source_guesses,
    const ScanRegistrationOptions& options) {
  THROW_CHECK(!target_from_source_guesses.empty(),
              "RegisterScans: no initial guess");
  THROW_CHECK(options.Check(), "invalid ScanRegistration options");
  const Level& coarse_source = source.data().coarse;
  const Level& coarse_target = target.data().coarse;
  ScanRegistrationResult result;
  // Coarse stage from every guess: GICP, and point-to-plane after it (see
  // RefinePointToPlane), each a candidate. The candidates are judged at the
  // fine level: among those whose overlap is within kNearBestFitness of the
  // largest, the smallest point-to-plane rmse wins. The overlap alone
  // prefers a scan slid backwards along a corridor (more of the
  // sensor-fixed ring pattern lines up); the rmse does not. Point-to-plane
  // on the coarse level alone can also slide the wrong way (smeared
  // normals), hence both candidates.
  constexpr double kNearBestFitness = 0.9;
  const Level& fine_source = source.data().fine;
  const Level& fine_target = target.data().fine;
  const double coarse_distance =
      options.fine_correspondence_voxels * coarse_target.voxel_size_m;
  const double fine_distance =
      options.fine_correspondence_voxels * fine_target.voxel_size_m;
  struct Candidate {
    Rigid3d target_from_source;
    Overlap overlap;  // At the fine level.
    bool converged = false;
    int guess_index = 0;
  };
  std::vector<Candidate> candidates;
  const auto add_candidate = [&](const Rigid3d& target_from_source,
                                 bool converged, int guess_index) {
    Candidate candidate;
    candidate.target_from_source = target_from_source;
    candidate.converged = converged;
    candidate.guess_index = guess_index;
    candidate.overlap =
        EvaluateOverlap(fine_source, fine_target, target_from_source,
                        fine_distance, options.num_threads);
    candidates.push_back(candidate);
  };
  // Index of the winner among candidates[first..].
  const auto select = [&](size_t first) {
    double max_fitness = 0.0;
    for (size_t c = first; c < candidates.size(); ++c) {
      max_fitness = std::max(max_fitness, candidates[c].overlap.fitness);
    }
    size_t best = candidates.size();
    for (size_t c = first; c < candidates.size(); ++c) {
      if (candidates[c].overlap.fitness >= kNearBestFitness * max_fitness &&
          (best == candidates.size() ||
           candidates[c].overlap.rmse_m < candidates[best].overlap.rmse_m)) {
        best = c;
      }
    }
    return best;
  };
  for (size_t g = 0; g < target_from_source_guesses.size(); ++g) {
    bool converged = false;
    const Rigid3d coarse =
        RunGicp(coarse_source, coarse_target, target_from_source_guesses[g],
                options.coarse_max_correspondence_distance_m, options,
                &converged);
    add_candidate(coarse, converged, static_cast<int>(g));
    if (options.point_to_plane_iterations > 0) {
      add_candidate(RefinePointToPlane(coarse_source, coarse_target, coarse,
                                       coarse_distance,
                                       options.point_to_plane_iterations,
                                       options.num_threads),
                    converged, static_cast<int>(g));
    }
  }
  const Candidate start = candidates[select(0)];
  result.guess_index = start.guess_index;
  const bool coarse_converged = start.converged;
  // Fine stage: point-to-plane from the winner (to reach the basin along
  // weakly constrained directions), then GICP (its precision in the
  // others). When point-to-plane moved the winner by more than a voxel, GICP
  // from the winner itself competes by the same rule, so that a slide of
  // the point-to-plane step the scans do not support is not taken.
  // PCL's GICP reports no convergence when its first step already makes no
  // progress (it then keeps its start): after a converged point-to-plane
  // refinement that is convergence too.
  const size_t first_fine = candidates.size();
  Rigid3d fine_start = start.target_from_source;
  bool point_to_plane_converged = false;
  if (options.point_to_plane_iterations > 0) {
    fine_start = RefinePointToPlane(
        fine_source, fine_target, fine_start, fine_distance,
        options.point_to_plane_iterations, options.num_threads,
        &point_to_plane_converged);
  }
  bool converged = false;
  const Rigid3d fine = RunGicp(fine_source, fine_target, fine_start,
                               fine_distance, options, &converged);
  add_candidate(fine, converged || point_to_plane_converged,
                start.guess_index);
  if ((fine_start.translation - start.target_from_source.translation).norm() >
      fine_target.voxel_size_m) {
    add_candidate(RunGicp(fine_source, fine_target, start.target_from_source,
                          fine_distance, options, &converged),
                  converged, start.guess_index);
  }
  const Candidate& chosen = candidates[select(first_fine)];
  const bool fine_converged = chosen.converged;
  for (size_t c = 0; c < candidates.size(); ++c) {
    VLOG(2) << "registration candidate " << c << (c < first_fine ? " (coarse" : " (fine")
            << ", guess " << candidates[c].guess_index << "): fitness "
            << candidates[c].overlap.fitness << ", rmse "
            << candidates[c].overlap.rmse_m << " m, converged "
            << candidates[c].converged;
  }
  result.target_from_source = chosen.target_from_source;
  result.converged = coarse_converged && fine_converged;
  result.voxel_size_m = fine_target.voxel_size_m;
  const Overlap& overlap = chosen.overlap;
  result.fitness = overlap.fitness;
  result.rmse_m = overlap.rmse_m;
  result.num_correspondences = overlap.num_inliers;
  result.hessian = overlap.hessian;
  result.information = CapInformation(overlap.hessian, FloorSigma(options));
  return result;
}

Eigen::Matrix<double, 6, 1> FloorSigma(const ScanRegistrationOptions& options) {
  const double rotation_sigma = options.min_rotation_sigma_deg * kPi / 180.0;
  Eigen::Matrix<double, 6, 1> floor_sigma;
  floor_sigma << rotation_sigma, rotation_sigma, rotation_sigma,
      options.min_translation_sigma_m, options.min_translation_sigma_m,
      options.min_translation_sigma_m;
  return floor_sigma;
}

Eigen::Matrix<double, 6, 6> CapInformation(
    const Eigen::Matrix<double, 6, 6>& hessian,
    const Eigen::Matrix<double, 6, 1>& floor_sigma) {
  // In the space scaled by the floor sigmas (unit = one floor sigma) no
  // eigenvalue may exceed 1.
  const Eigen::Matrix<double, 6, 6> scale = floor_sigma.asDiagonal();
  const Eigen::Matrix<double, 6, 6> scaled = scale * hessian * scale;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> solver(
      0.5 * (scaled + scaled.transpose()));
  const Eigen::Matrix<double, 6, 1> values =
      solver.eigenvalues().cwiseMax(0.0).cwiseMin(1.0);
  const Eigen::Matrix<double, 6, 6> capped = solver.eigenvectors() *
                                             values.asDiagonal() *
                                             solver.eigenvectors().transpose();
  const Eigen::Matrix<double, 6, 6> inverse_scale =
      floor_sigma.cwiseInverse().asDiagonal();
  return inverse_scale * capped * inverse_scale;
}

ScanRegistrationResult RegisterScans(const LidarScan& source,
                                     const LidarScan& target,
                                     const Rigid3d& target_from_source_guess,
                                     const ScanRegistrationOptions& options) {
  const double voxel = VoxelSizeForScan(target, options);
  const PreparedScan prepared_source(source, options, voxel);
  const PreparedScan prepared_target(target, options, voxel);
  return RegisterScans(prepared_source, prepared_target,
                       {target_from_source_guess}, options);
}

}  // namespace colmap_lidar
