// ICP refinement of a mesh's alignment to the reference cloud, as Tanks and
// Temples does after the trajectory fit (Knapitsch et al. 2017, Sec. 4): the
// trajectory fit carries the reconstruction into the ground-truth frame up
// to the accuracy of the camera poses; ICP then removes the remaining rigid
// offset of the surface itself, so that the figures after it measure the
// shape, those before it the shape and its placement (report both).
//
// Source: uniform samples of the mesh (or the points of a cloud estimate),
// at most max_num_samples, cropped to the reference's bounding box enlarged
// by the crop margin. Target: the reference points near the source's box,
// on a voxel grid of edge d / 6, with normals from a plane fit of their
// normal_num_neighbors nearest neighbours (point_to_plane). The largest
// correspondence distance d = max_distance_factor * the evaluation
// threshold, preceded by num_stages - 1 coarser stages of 2x, 4x, ... that
// distance (coarse to fine, each from the previous result). The result is
// rigid (PCL's ICP; point_to_plane by linear least squares, Low 2004).
// Coordinates are centred on the source's centroid before PCL's single
// precision.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace colmap_lidar {

struct MeshIcpOptions {
  // point_to_plane (reference normals from local plane fits) |
  // point_to_point.
  std::string method = "point_to_plane";
  // Final largest correspondence distance, as a multiple of the evaluation
  // threshold it serves (> 0).
  double max_distance_factor = 3.0;
  // Coarse-to-fine stages, each halving the distance down to the final one
  // (>= 1).
  int num_stages = 3;
  // ICP iterations per stage at most (>= 1).
  int max_num_iterations = 30;
  // Mesh samples used at most (>= 100).
  int max_num_samples = 100000;
  // Neighbours of a reference point's plane fit (>= 3).
  int normal_num_neighbors = 12;
  // Seed of the mesh sampling.
  int seed = 0;

  bool Check() const;
};

struct MeshIcpResult {
  // The rigid correction in the reference frame: the refined alignment is
  // refined_from_aligned * (the trajectory fit).
  Eigen::Affine3d refined_from_aligned = Eigen::Affine3d::Identity();
  // Its size.
  double rotation_deg = 0.0;
  double translation_m = 0.0;
  std::vector<double> stage_distances_m;
  size_t num_source_points = 0;
  size_t num_target_points = 0;
  // After the last stage: share of the source points with a target point
  // within the final distance, and the RMS of those distances (metres),
  // before and after the refinement.
  double inlier_ratio_before = 0.0;
  double inlier_ratio = 0.0;
  double inlier_rmse_before_m = 0.0;
  double inlier_rmse_m = 0.0;
  // PCL's convergence flag of the last stage.
  bool converged = false;
};

// `vertices` are already in the reference's frame (after the trajectory
// fit); `triangles` empty means a point-cloud estimate. `evaluation_
// threshold_m` > 0 sets the distances; crop_margin_m < 0 disables the crop.
// Throws colmap_lidar::Error on invalid options, empty inputs, or when no
// source point lies in the reference's box or near the reference.
MeshIcpResult RefineMeshAlignmentIcp(
    const std::vector<Eigen::Vector3d>& vertices,
    const std::vector<Eigen::Vector3i>& triangles,
    const std::vector<Eigen::Vector3d>& reference,
    double evaluation_threshold_m, double crop_margin_m,
    const MeshIcpOptions& options);

// Reads the estimate (mesh or cloud PLY) and the reference PLY, carries the
// estimate by `reference_from_estimate` and refines; errors name the file.
MeshIcpResult RefineMeshAlignmentIcpFiles(
    const std::string& estimate_path, const std::string& reference_path,
    const Eigen::Affine3d& reference_from_estimate,
    double evaluation_threshold_m, double crop_margin_m,
    const MeshIcpOptions& options);

// One-line summary for logs and tables.
std::string FormatMeshIcpResult(const MeshIcpResult& result);

}  // namespace colmap_lidar
