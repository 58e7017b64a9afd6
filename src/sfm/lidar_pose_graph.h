// Initial poses from a LIDAR pose graph (issue 16, first part): the prior
// poses carry 0.5 m / 5 deg of noise and cannot tell a good stock mapper
// model from a broken one, while overlapping LIDAR scans register to
// centimetres in the structured scenes we target.
//
// Frames: prior world_from_cam, cam_from_lidar, a scan. Edges (target i,
// source j, measuring lidar_i_from_lidar_j by src/lidar/scan_registration):
// - consecutive frames j = i + 1, registered from two initial guesses, the
//   priors' relative pose and the previous consecutive edge's result
//   (constant velocity), since relative prior errors reach ~1 m / 10 deg;
// - loop candidates: j >= i + 2 with prior centres within loop_radius_m
//   (the max_loop_candidates_per_frame nearest per frame), and j = i + 2
//   whatever the distance when skip_one_candidates is set (its overlap
//   decides; these short loops are what measures the edges' noise, see
//   src/sfm/lidar_edge_noise.h), from the priors' relative pose and, when
//   the consecutive edges between them all registered, from their
//   composition.
// An edge is used when its overlap reaches min_fitness (min_loop_fitness for
// loops), its rmse stays below max_rmse_voxels, and it lies within max_prior_deviation_sigmas of the priors'
// relative pose (a GICP that slid into a repeated structure lies farther);
// a skip-one loop (j = i + 2) passes the rmse gate as consecutive edges do,
// unless the loop closures then disagree systematically with the chains
// (moving traffic on KITTI drags two-step registrations): such loops are
// dropped again.
//
// Edge noise: the used loops whose consecutive chain is complete measure
// the edges' actual noise per sensor axis (src/sfm/lidar_edge_noise.h);
// each edge's information is its registration Hessian capped at the
// measured sigma (where it is cleaner than the registration's floor) with
// the measured excess variance added (where it is noisier: a corridor's
// axis). A bias common to every edge (a scale error per metre) cancels in
// the closures and is not seen.
//
// Solve (Ceres, Levenberg-Marquardt): variables world_from_cam per frame
// (quaternion manifold + translation); a unary prior factor per frame (as
// lidar_mapper's prior terms: position sigma per axis, rotation RMS angle
// sigma / sqrt(3) per axis); a relative-pose factor per used edge, weighted
// by the square root of that information, under a Cauchy loss of
// scale robust_loss_scale (whitened units). After the solve an edge whose
// whitened residual exceeds the chi-square(6) 99.9 % quantile is reported
// as downweighted.
#pragma once

#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "colmap_ext/scene/reconstruction.h"
#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"
#include "src/lidar/scan_registration.h"
#include "src/optim/cost_functions.h"
#include "src/sfm/lidar_edge_noise.h"

namespace colmap_lidar {

class Database;

struct LidarPoseGraphOptions {
  ScanRegistrationOptions registration;
  // Loop candidates: frames at least 2 apart in the sequence whose prior
  // camera centres lie within this distance, metres, >= 0 (0: none). With
  // 0.5 m prior noise the true distance is known to about 1 m; scans of
  // 20-80 m scenes taken 8 m apart still overlap by most of their points.
  double loop_radius_m = 8.0;
  // At most this many loop candidates per frame (the nearest), >= 0.
  int max_loop_candidates_per_frame = 3;
  // Frame i + 2 is a loop candidate of frame i also beyond loop_radius_m
  // (on a street walked in 4-5 m steps no other frame is within 8 m), 0/1.
  bool skip_one_candidates = true;
  // Overlap (ScanRegistrationResult::fitness) an edge needs to be used,
  // [0, 1]: consecutive edges, and loop candidates (stricter: a wrong loop
  // hurts more than a missing one).
  double min_fitness = 0.3;
  double min_loop_fitness = 0.5;
  // Largest point-to-plane rmse of a used edge, in fine voxels, > 0.
  // Aligned surfaces leave residuals of the range noise and the voxel
  // centroids' scatter (measured: 0.024 m at a 0.45 m voxel with 1.5 cm
  // noise in the tests, 0.05 voxels); a registration onto a similar but
  // wrong structure leaves residuals up to the correspondence distance
  // (0.38 m at 0.45 m, 0.84 voxels, in the test). On the synthetic street
  // (32 rings, 2 cm noise, 0.145 m voxel) correct-looking edges reach 0.5
  // voxels, but 0.6 let in loop edges that slid 1-3 m along the street
  // and broke the graph; 0.25 dropped them (measured, see the report).
  double max_rmse_voxels = 0.25;
  // A consecutive edge also passes when its rmse is at most this times the
  // median rmse of the consecutive edges (the scanner's noise floor, see
  // lidar_pose_graph.cc), >= 1; loop edges do not.
  double consecutive_rmse_over_median = 1.5;
  // An edge farther from the priors' relative pose than this many sigmas
  // of a relative prior (sqrt(2) times the per-frame sigmas below; the
  // translation against its 3D norm) is not used, > 0.
  double max_prior_deviation_sigmas = 4.0;
  // Pose priors, as LidarMapperOptions: position sigma per axis (m),
  // rotation RMS angle (deg), > 0.
  double prior_position_sigma_m = 0.5;
  double prior_rotation_sigma_deg = 5.0;
  // Cauchy loss scale of the relative factors, in whitened units, > 0:
  // whitened squared norms are chi-square(6) for correct edges, whose
  // 99 % quantile is 4.1^2.
  double robust_loss_scale = 4.0;
  // The edges' noise measured by the loop closures (src/sfm/lidar_edge_noise.h):
  // axes where it exceeds the registrations' floor get its variance added,
  // axes where it is cleaner get the floor lowered to it.
  LidarEdgeNoiseOptions edge_noise;
  // Levenberg-Marquardt iterations at most, >= 1.
  int max_num_iterations = 100;
  // Threads for the registrations' covariances / correspondences, for the
  // loop registrations side by side (the same edges whatever the order) and
  // Ceres; <= 0: all cores.
  int num_threads = -1;

  bool Check() const;
};

struct LidarPoseGraphFrame {
  std::string name;
  // p_world = world_from_cam * p_cam.
  Rigid3d prior_world_from_cam;
  // p_cam = cam_from_lidar * p_lidar.
  Rigid3d cam_from_lidar;
  // Not owned; must outlive the call.
  const LidarScan* scan = nullptr;
};

struct LidarPoseGraphEdge {
  // Frame indices: target i (earlier), source j.
  int i = 0;
  int j = 0;
  bool loop = false;
  // registration.target_from_source = lidar_i_from_lidar_j.
  ScanRegistrationResult registration;
  // Deviation of the registration from the priors' relative pose.
  double prior_deviation_m = 0.0;
  double prior_deviation_deg = 0.0;
  // In the graph (fitness and prior deviation passed).
  bool used = false;
  // A skip-one loop that passed by the consecutive edges' noise-floor gate
  // only (not max_rmse_voxels): dropped again when the loop closures show a
  // systematic disagreement (LidarEdgeNoiseEstimate::biased).
  bool relaxed_loop = false;
  // The information the graph and the adjustment use: the registration's,
  // inflated by the loop closures' measured noise (LidarEdgeNoiseEstimate),
  // same order and frame.
  Eigen::Matrix<double, 6, 6> information =
      Eigen::Matrix<double, 6, 6>::Zero();
  // After the solve: the solved relative pose against the registration
  // (metres, degrees) and the whitened residual norm; used edges beyond
  // the chi-square(6) 99.9 % quantile are downweighted by the loss.
  double residual_m = 0.0;
  double residual_deg = 0.0;
  double whitened_residual = 0.0;
  bool downweighted = false;
};

struct LidarPoseGraphResult {
  std::vector<Rigid3d> world_from_cam;
  std::vector<LidarPoseGraphEdge> edges;
  // Per frame (the index of edges' i, j): its cam_from_lidar, and its image
  // id (LidarGraphPoses only; empty from SolveLidarPoseGraph).
  std::vector<Rigid3d> cam_from_lidar;
  std::vector<image_t> image_ids;
  int num_frames = 0;
  int num_used_edges = 0;
  int num_used_loops = 0;
  int num_downweighted = 0;
  // Frames with no used edge: they stay at their prior.
  int num_isolated_frames = 0;
  double voxel_size_m = 0.0;
  LidarEdgeNoiseEstimate edge_noise;
  // Skip-one loops taken out again because the closures were biased with
  // them (LidarPoseGraphEdge::relaxed_loop), and the estimate that showed
  // it (edge_noise is then re-estimated without them).
  int num_dropped_relaxed_loops = 0;
  LidarEdgeNoiseEstimate edge_noise_before_drop;
  double registration_seconds = 0.0;
  double solve_seconds = 0.0;
  std::string solver_report;

  // One summary line.
  std::string Format() const;
  // One line per edge.
  std::string FormatEdges() const;
};

// Builds, registers and solves the graph of the file comment over `frames`
// in sequence order. Throws colmap_lidar::Error on invalid options, fewer
// than 2 frames, a frame without a scan, or a scan with too few points
// (naming the frame).
LidarPoseGraphResult SolveLidarPoseGraph(
    const std::vector<LidarPoseGraphFrame>& frames,
    const LidarPoseGraphOptions& options);

// The graph over the images of `model` that have a LIDAR scan in
// `database` (ext_lidar_scans; LidarScanFilePath), in the
// order of their names, with the images' current poses as priors; writes
// the solved poses into `model`. Images without a scan keep their pose.
LidarPoseGraphResult LidarGraphPoses(const Database& database,
                                     const LidarPoseGraphOptions& options,
                                     Reconstruction* model);

// ---- Cost functors (exposed for the tests).

// Unary prior on world_from_cam = (R, t):
//   r = [ (t - t_prior) / sigma_position ;
//         AngleAxis(R * R_prior^T) / sigma_rotation ]   (6)
// sigma_rotation per axis, radians.
class WorldPosePriorCostFunctor {
 public:
  WorldPosePriorCostFunctor(const Rigid3d& prior_world_from_cam,
                            double position_sigma_m, double rotation_sigma_rad)
      : prior_rotation_inverse_(
            prior_world_from_cam.rotation.normalized().conjugate()),
        prior_translation_(prior_world_from_cam.translation),
        inv_position_sigma_(1.0 / position_sigma_m),
        inv_rotation_sigma_(1.0 / rotation_sigma_rad) {}

  static ceres::CostFunction* Create(const Rigid3d& prior_world_from_cam,
                                     double position_sigma_m,
                                     double rotation_sigma_rad) {
    return new ceres::AutoDiffCostFunction<WorldPosePriorCostFunctor, 6, 4, 3>(
        new WorldPosePriorCostFunctor(prior_world_from_cam, position_sigma_m,
                                      rotation_sigma_rad));
  }

  template <typename T>
  bool operator()(const T* world_from_cam_rotation,
                  const T* world_from_cam_translation, T* residuals) const {
    const Eigen::Map<const Eigen::Quaternion<T>> rotation(
        world_from_cam_rotation);
    for (int k = 0; k < 3; ++k) {
      residuals[k] = (world_from_cam_translation[k] -
                      T(prior_translation_[k])) *
                     T(inv_position_sigma_);
    }
    const Eigen::Quaternion<T> delta =
        rotation * prior_rotation_inverse_.cast<T>();
    const T delta_wxyz[4] = {delta.w(), delta.x(), delta.y(), delta.z()};
    T angle_axis[3];
    ceres::QuaternionToAngleAxis(delta_wxyz, angle_axis);
    for (int k = 0; k < 3; ++k) {
      residuals[3 + k] = angle_axis[k] * T(inv_rotation_sigma_);
    }
    return true;
  }

 private:
  const Eigen::Quaterniond prior_rotation_inverse_;
  const Eigen::Vector3d prior_translation_;
  const double inv_position_sigma_;
  const double inv_rotation_sigma_;
};

// Relative pose between frames i and j, measured as
// M = lidar_i_from_lidar_j (a registration), with the frames' fixed
// cam_from_lidar C_i, C_j and the variables W_i, W_j = world_from_cam:
//   E = M^-1 * C_i^-1 * W_i^-1 * W_j * C_j      (identity when consistent)
//   r = S * [AngleAxis(E.R); E.t]                (6)
// S the square root of the registration's information (S^T S = Lambda),
// which refers to the same right perturbation of lidar_i_from_lidar_j.
class RelativePoseCostFunctor {
 public:
  RelativePoseCostFunctor(const Rigid3d& lidar_i_from_lidar_j,
                          const Rigid3d& cam_from_lidar_i,
                          const Rigid3d& cam_from_lidar_j,
                          const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : measured_inverse_(lidar_i_from_lidar_j.Inverse()),
        lidar_i_from_cam_i_(cam_from_lidar_i.Inverse()),
        cam_j_from_lidar_j_(cam_from_lidar_j),
        sqrt_information_(sqrt_information) {}

  static ceres::CostFunction* Create(
      const Rigid3d& lidar_i_from_lidar_j, const Rigid3d& cam_from_lidar_i,
      const Rigid3d& cam_from_lidar_j,
      const Eigen::Matrix<double, 6, 6>& sqrt_information) {
    return new ceres::AutoDiffCostFunction<RelativePoseCostFunctor, 6, 4, 3, 4,
                                           3>(
        new RelativePoseCostFunctor(lidar_i_from_lidar_j, cam_from_lidar_i,
                                    cam_from_lidar_j, sqrt_information));
  }

  template <typename T>
  bool operator()(const T* rotation_i, const T* translation_i,
                  const T* rotation_j, const T* translation_j,
                  T* residuals) const {
    using Quaternion = Eigen::Quaternion<T>;
    using Vector3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Quaternion> world_from_cam_i_q(rotation_i);
    const Eigen::Map<const Vector3> world_from_cam_i_t(translation_i);
    const Eigen::Map<const Quaternion> world_from_cam_j_q(rotation_j);
    const Eigen::Map<const Vector3> world_from_cam_j_t(translation_j);
    // cam_i_from_cam_j = W_i^-1 W_j.
    const Quaternion cam_i_from_world_q = world_from_cam_i_q.conjugate();
    const Quaternion rel_q = cam_i_from_world_q * world_from_cam_j_q;
    const Vector3 rel_t =
        cam_i_from_world_q * (world_from_cam_j_t - world_from_cam_i_t);
    WhitenedRelativeLidarPoseError(rel_q, rel_t, measured_inverse_,
                                   lidar_i_from_cam_i_, cam_j_from_lidar_j_,
                                   sqrt_information_, residuals);
    return true;
  }

 private:
  const Rigid3d measured_inverse_;
  const Rigid3d lidar_i_from_cam_i_;
  const Rigid3d cam_j_from_lidar_j_;
  const Eigen::Matrix<double, 6, 6> sqrt_information_;
};

// S with S^T S = information (symmetric positive semi-definite): the
// eigen-decomposition sqrt(D) V^T, negative eigenvalues clamped to 0.
Eigen::Matrix<double, 6, 6> SqrtInformation(
    const Eigen::Matrix<double, 6, 6>& information);

}  // namespace colmap_lidar
