// Pairwise registration of two LIDAR scans (PCL Generalized-ICP, Segal et
// al. 2009) from an initial guess, with the overlap, the residual and an
// information matrix of the result, for the edges of a pose graph
// (src/sfm/lidar_pose_graph.h).
//
// Two stages: a coarse GICP on scans downsampled coarse_voxel_factor times
// coarser, with a wide correspondence distance, then point-to-plane ICP,
// from each initial guess given (among those with nearly the largest coarse
// overlap, the smallest rmse wins), then a fine point-to-plane ICP and GICP
// with a correspondence distance of a few voxels. Point-to-plane steps are
// there because GICP does not slide along weakly constrained directions. The initial guesses of a
// pose graph come from noisy priors (relative errors up to about 1 m and
// 10 deg between two frames with 0.5 m / 5 deg priors), which the fine stage
// alone does not pull in.
//
// Information matrix: the Gauss-Newton Hessian J^T J / sigma^2 of the
// point-to-plane residuals r_k = n_k . (T p_k - q_k) at the final
// correspondences (p_k a source point, q_k its nearest target point, n_k the
// target's local normal), with sigma^2 = sum r_k^2 / (N - 6) the residual
// variance. It refers to a right perturbation of the result:
// target_from_source * Exp(delta), delta = [rotation (rad, 3); translation
// (m, 3)] in the source frame. Thousands of correspondences make the
// Hessian claim sub-millimetre precision that correlated errors (ring
// pattern, voxel centroids, de-skew) do not support, so its eigenvalues are
// capped at the floor sigmas min_rotation_sigma_deg / min_translation_sigma_m
// (in the units-scaled space), while directions the scene does not
// constrain (a corridor along its axis) keep their small information.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {

struct ScanRegistrationOptions {
  // Points nearer to / farther from the sensor are dropped, metres,
  // 0 <= min < max. The near limit removes the ego vehicle (KITTI's roof
  // lies within 3 m; the synthetic rigs have none, their scenes are
  // 20-80 m across).
  double min_range_m = 2.0;
  double max_range_m = 80.0;
  // Fine voxel edge, metres, >= 0. 0: from the data, the median range of
  // the target scan times voxel_angle_deg, clamped to [0.1, 0.5] m (about
  // two ring spacings of a 64-ring 33 deg sensor at the median range, one of
  // a 32-ring 41 deg sensor; 0.5 m is lidar_odometry's KITTI voxel).
  double voxel_size_m = 0.0;
  double voxel_angle_deg = 1.5;
  // Coarse stage: voxel edge = coarse_voxel_factor * fine voxel, >= 1;
  // correspondence distance, metres, > 0, about the largest relative
  // error of the initial guess at the scene's typical range (1 m + 10 deg
  // at 6 m).
  double coarse_voxel_factor = 3.0;
  double coarse_max_correspondence_distance_m = 2.0;
  // Fine stage: correspondence distance = this times the fine voxel, > 0.
  // The overlap (fitness) counts source points with a target point this
  // near after the fine stage.
  double fine_correspondence_voxels = 3.0;
  // GICP iterations per stage at most, >= 1.
  int max_iterations = 50;
  // Convergence: pose update between two iterations below this
  // (translation m, rotation rad), > 0.
  double transformation_epsilon = 1e-5;
  // Point-to-plane iterations after each GICP stage's start (see
  // RefinePointToPlane in the .cc: GICP alone does not slide along a
  // corridor's axis), >= 0; 0 turns the step off.
  int point_to_plane_iterations = 30;
  // Neighbours per point for the GICP covariances and normals, >= 3.
  int num_neighbors = 20;
  // Floor of the standard deviations the information matrix may claim
  // (see the file comment), > 0.
  double min_translation_sigma_m = 0.005;
  double min_rotation_sigma_deg = 0.02;
  // Threads for covariances and correspondences; <= 0: all cores.
  int num_threads = -1;

  bool Check() const;
};

struct ScanRegistrationResult {
  // p_target = target_from_source * p_source.
  Rigid3d target_from_source;
  // Fraction of the (fine, downsampled) source points with a target point
  // within the fine correspondence distance, [0, 1].
  double fitness = 0.0;
  // Root mean square point-to-plane residual of those points, metres.
  double rmse_m = 0.0;
  // Both GICP stages converged (before max_iterations).
  bool converged = false;
  // See the file comment: order [rotation (rad); translation (m)], a right
  // perturbation in the source frame. Zero when there are fewer than 7
  // correspondences.
  Eigen::Matrix<double, 6, 6> information =
      Eigen::Matrix<double, 6, 6>::Zero();
  // The same before the cap: J^T J / sigma^2 (for a cap measured from the
  // data, src/sfm/lidar_edge_noise.h).
  Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
  // Index of the initial guess the coarse stage kept.
  int guess_index = 0;
  int num_correspondences = 0;
  double voxel_size_m = 0.0;
};

// The floor sigmas of the options, [rotation (rad, 3); translation (m, 3)].
Eigen::Matrix<double, 6, 1> FloorSigma(const ScanRegistrationOptions& options);

// The information `hessian` capped at `floor_sigma` (> 0): in the space
// scaled by them no eigenvalue exceeds 1, so no direction claims less than
// its floor sigma while weakly constrained directions keep their small
// information.
Eigen::Matrix<double, 6, 6> CapInformation(
    const Eigen::Matrix<double, 6, 6>& hessian,
    const Eigen::Matrix<double, 6, 1>& floor_sigma);

// A scan filtered, downsampled at two voxel sizes, with GICP covariances,
// normals and search trees: prepared once, registered against many.
class PreparedScan {
 public:
  // Throws colmap_lidar::Error when fewer than 10 points remain after the
  // range filter and the voxel grid, or the options fail Check().
  // voxel_size_m > 0 overrides the options' voxel (to register scans of one
  // graph at one voxel size); see VoxelSizeForScan().
  PreparedScan(const LidarScan& scan, const ScanRegistrationOptions& options,
               double voxel_size_m = 0.0);
  ~PreparedScan();
  PreparedScan(const PreparedScan&) = delete;
  PreparedScan& operator=(const PreparedScan&) = delete;

  size_t NumPoints() const;
  double VoxelSize() const;

  struct Data;
  const Data& data() const { return *data_; }

 private:
  std::unique_ptr<Data> data_;
};

// options.voxel_size_m when > 0, else the data-derived voxel of the file
// comment (median range * voxel_angle_deg, clamped to [0.1, 0.5] m).
double VoxelSizeForScan(const LidarScan& scan,
                        const ScanRegistrationOptions& options);

// Registers `source` onto `target` starting from each of
// `target_from_source_guesses` (at least one). Never throws on a failed
// registration: judge it by fitness / converged.
ScanRegistrationResult RegisterScans(
    const PreparedScan& source, const PreparedScan& target,
    const std::vector<Rigid3d>& target_from_source_guesses,
    const ScanRegistrationOptions& options);

// Convenience: prepares both scans (target's voxel) and registers them.
ScanRegistrationResult RegisterScans(const LidarScan& source,
                                     const LidarScan& target,
                                     const Rigid3d& target_from_source_guess,
                                     const ScanRegistrationOptions& options);

}  // namespace colmap_lidar
