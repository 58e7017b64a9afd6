// Figures for a recording without ground truth (the KITTI raw sample), from
// what the sensors themselves say about the reconstruction:
//
//  - crispness of the LIDAR map: every scan is thinned by a voxel grid and
//    carried into the world by a set of poses (refined, then prior); for
//    points of each scan, the distance to the plane fitted to the points of
//    the OTHER scans within a radius of a few voxels. Consistent poses stack
//    the scans of one wall onto one plane (distance ~ range noise); a
//    mis-posed scan stands off it. Neighbourhoods with too few points or
//    without a plane (a pole, a single ring: second eigenvalue below
//    crispness_min_planarity times the largest) give no distance; their
//    share is 1 - coverage. Distances saturate near the radius: poses off
//    by more than that lose coverage instead.
//  - the refined trajectory against LIDAR odometry: consecutive scans
//    registered pairwise (src/lidar/scan_registration.h, two-stage GICP,
//    initial guesses from the prior poses and the previous step, the
//    identity only without priors: a scan's sensor-fixed pattern (ground
//    rings) draws a slowly moving pair towards it; never from the refined
//    poses, which are what is judged). Steps are distances between
//    consecutive LIDAR centres. The crispness of the map posed by the
//    chained odometry is reported too: it tells which of two lengths the
//    scans support.
//  - the mesh against the LIDAR points: share of the fused LIDAR points
//    (lidar_fused.ply) within t of the mesh surface (exact
//    point-to-triangle), all of them and those in the cameras' view (in a
//    refined image, at most mesh_view_max_depth_m deep), and share of
//    uniform area samples of the mesh within t of a LIDAR point.
//
// Frames: the refined model's images with a scan in the database's
// ext_lidar_scans (a relative scan path is relative to the database's
// folder), in name order (the recording order of the importer's frame
// names). World frame and metres throughout.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/reconstruction.h"
#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"
#include "src/lidar/scan_registration.h"

namespace colmap_lidar {

struct RealDataEvaluationOptions {
  // Crispness: voxel edge thinning each scan (centroid per voxel, LIDAR
  // frame), metres, >= 0. 0: from the data, the median range of the first
  // scan times crispness_voxel_angle_deg, clamped to [0.05, 0.3] m (about the
  // ring spacing of a 64-ring sensor at that range).
  double crispness_voxel_size_m = 0.0;
  double crispness_voxel_angle_deg = 0.5;
  // Plane neighbourhood radius = this times the voxel, > 1.
  double crispness_radius_voxels = 3.0;
  // Points of other scans needed for a plane, >= 3.
  int crispness_min_neighbors = 6;
  // A neighbourhood is a plane when its middle covariance eigenvalue is at
  // least this times the largest (rejects lines: one ring, a pole), [0, 1].
  double crispness_min_planarity = 0.05;
  // Query points per scan at most (evenly strided over the thinned scan),
  // >= 1.
  int crispness_max_queries_per_scan = 5000;
  // Odometry: pairwise registration of consecutive scans. Its range limits
  // (min_range_m: the ego vehicle) also filter the crispness points.
  ScanRegistrationOptions registration;
  // A consecutive registration below this fitness counts as failed (its
  // step is still used; the count is reported), [0, 1].
  double min_fitness = 0.3;
  // Mesh vs LIDAR: distance thresholds, metres, positive and increasing.
  std::vector<double> mesh_thresholds_m = {0.1, 0.5};
  // Mesh samples per square metre, > 0, lowered so that at most
  // max_mesh_samples are drawn (>= 1000).
  double mesh_sample_density_per_m2 = 100.0;
  int max_mesh_samples = 2000000;
  // The LIDAR points "in view" (issue 17's figure): in the image of at least
  // one refined camera and at most this depth in front of it, metres, > 0.
  // A spinning LIDAR sees all around and 80 m deep, the cameras a forward
  // cone: the mesh can only be asked to explain what the cameras saw.
  double mesh_view_max_depth_m = 40.0;
  int seed = 0;
  // <= 0: all cores.
  int num_threads = -1;

  bool Check() const;
};

struct CrispnessStats {
  // Point-to-plane distances of the query points with a plane, metres.
  size_t num_queries = 0;
  size_t num_planes = 0;
  double median_m = 0.0;
  double p90_m = 0.0;
  // num_planes / num_queries.
  double coverage = 0.0;
  // Median per frame (0 when the frame had no plane).
  std::vector<double> frame_median_m;
};

struct TrajectoryComparison {
  size_t num_steps = 0;
  double odometry_length_m = 0.0;
  double refined_length_m = 0.0;
  // 0 when no frame has a prior.
  double prior_length_m = 0.0;
  // refined / odometry; 0 when the odometry did not move.
  double length_ratio = 0.0;
  // max over steps of |refined step - odometry step|, and its first frame.
  double max_step_difference_m = 0.0;
  std::string max_step_difference_frame;
  size_t num_failed_registrations = 0;
  double min_fitness = 1.0;
  // Per step k (frames k -> k + 1).
  std::vector<std::string> step_frames;
  std::vector<double> odometry_steps_m;
  std::vector<double> refined_steps_m;
  std::vector<double> fitness;
  // The odometry chain, anchored at the first frame's refined pose.
  std::vector<Rigid3d> odometry_world_from_lidar;
};

struct MeshVsLidar {
  size_t num_lidar_points = 0;
  size_t num_mesh_samples = 0;
  double mesh_area_m2 = 0.0;
  std::vector<double> thresholds_m;
  // Per threshold.
  std::vector<double> lidar_within;
  std::vector<double> mesh_within;
  // The same share for the LIDAR points in view (empty without flags).
  size_t num_lidar_points_in_view = 0;
  std::vector<double> lidar_in_view_within;
};

struct RealDataEvaluation {
  size_t num_frames = 0;
  double crispness_voxel_size_m = 0.0;
  double crispness_radius_m = 0.0;
  CrispnessStats refined_crispness;
  bool has_prior = false;
  CrispnessStats prior_crispness;
  // The map posed by the odometry chain (with has_trajectory).
  CrispnessStats odometry_crispness;
  bool has_trajectory = false;
  TrajectoryComparison trajectory;
  bool has_mesh = false;
  MeshVsLidar mesh_vs_lidar;
};

// One frame: its scan (LIDAR frame) and poses.
struct RealDataFrame {
  std::string name;
  const LidarScan* scan = nullptr;
  Rigid3d refined_world_from_lidar;
  bool has_prior = false;
  Rigid3d prior_world_from_lidar;
};

// Voxel of the crispness (see the options) for these frames.
double CrispnessVoxelSize(const LidarScan& first_scan,
                          const RealDataEvaluationOptions& options);

// Centroid per voxel of the points within the registration's range limits,
// LIDAR frame.
std::vector<Eigen::Vector3d> ThinScan(const LidarScan& scan, double voxel_m,
                                      const RealDataEvaluationOptions& options);

// Crispness of `thinned_scans` (LIDAR frame) posed by `world_from_lidar`
// (same size, >= 2). Throws on invalid options or sizes.
CrispnessStats EvaluateCrispness(
    const std::vector<std::vector<Eigen::Vector3d>>& thinned_scans,
    const std::vector<Rigid3d>& world_from_lidar, double radius_m,
    const RealDataEvaluationOptions& options);

// Odometry of consecutive frames against the refined poses (>= 2 frames).
// Throws naming the frame when a scan cannot be prepared (too few points).
TrajectoryComparison CompareTrajectoryWithOdometry(
    const std::vector<RealDataFrame>& frames,
    const RealDataEvaluationOptions& options);

// `triangles` non-empty, `lidar_points` non-empty. `in_view` (empty: no
// in-view figures) flags the LIDAR points in view, one per point.
MeshVsLidar EvaluateMeshVsLidar(const std::vector<Eigen::Vector3d>& vertices,
                                const std::vector<Eigen::Vector3i>& triangles,
                                const std::vector<Eigen::Vector3d>& lidar_points,
                                const RealDataEvaluationOptions& options,
                                const std::vector<bool>& in_view = {});

// Flags the points that project into the image of at least one image of
// `model` with a depth in (0, max_depth_m] (world frame of the model).
std::vector<bool> InCameraView(const Reconstruction& model,
                               const std::vector<Eigen::Vector3d>& points,
                               double max_depth_m);

// In-memory evaluation of crispness (refined, prior when every frame has
// one, odometry chain) and trajectory; the mesh part stays empty.
RealDataEvaluation EvaluateRealDataFrames(
    const std::vector<RealDataFrame>& frames,
    const RealDataEvaluationOptions& options);

struct RealDataEvaluationInput {
  // Scans and cam_from_lidar (ext_lidar_scans).
  std::string database_path;
  // Optional (skipped when it does not exist).
  std::string prior_model_path;
  std::string refined_model_path;
  // Optional: the mesh part needs both.
  std::string mesh_path;
  std::string lidar_cloud_path;
};

// Reads the files and evaluates. Throws naming the file on a missing
// database or refined model, fewer than 2 refined frames with a scan, or an
// unreadable scan, mesh or cloud.
RealDataEvaluation EvaluateRealData(const RealDataEvaluationInput& input,
                                    const RealDataEvaluationOptions& options);

// {"num_frames", "crispness": {...refined_median_m, prior_median_m...},
//  "trajectory": {...}, "mesh_vs_lidar": {"lidar_within_0.1m", ...}};
// sections without data are left out. Atomic.
void WriteRealDataJson(const std::string& path,
                       const RealDataEvaluation& evaluation);

// One line with the headline figures (for the log and the stage note).
std::string FormatRealDataEvaluation(const RealDataEvaluation& evaluation);

}  // namespace colmap_lidar
