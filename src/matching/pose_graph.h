// A robust pose graph over the views of the line association: the prior
// poses as absolute terms, the pairwise registrations on line segments
// (relative_line_pose.h) as relative terms. Periodic facades make some
// registrations snap to the wrong window (shifts of a window's width):
// those are locally as good as the right one, but disagree with the chains
// of other registrations, so that the robust optimisation (graduated
// non-convexity on a Geman-McClure kernel, from nearly least squares to a
// narrow kernel) leaves them out.
//
// The robust phase weighs all edges alike (edge_sigma_*), so that a few
// confident but wrong registrations cannot outvote the chains of right
// ones; the final least squares over the inliers uses each edge's own
// information matrix.
//
// Unknowns per view: its rotation (left increment, camera frame) and its
// centre in the world. Residuals:
//   prior     Log(R_i R_prior_i^T) / sigma_prior_r, (c_i - c_prior_i) /
//   sigma_prior_t; relative  L^T [Log(R_j R_i^T R_ji^T); R_j (c_i - c_j) -
//   t_ji], with
//             (R_ji, t_ji) = cam_j_from_cam_i measured and L L^T its
//             information matrix (RelativeLinePose::information).
// Solved by Gauss-Newton on sparse normal equations.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "colmap_ext/scene/rigid3.h"

namespace colmap_lidar {

struct PoseGraphEdge {
  int view1 = -1;
  int view2 = -1;
  Rigid3d cam2_from_cam1;
  // Of the increments (theta, t) of cam2_from_cam1 (rotation <- Exp(theta)
  // rotation, translation <- translation + t), symmetric positive definite.
  Eigen::Matrix<double, 6, 6> information =
      Eigen::Matrix<double, 6, 6>::Identity();
};

struct PoseGraphOptions {
  // Standard deviations of the prior poses (per axis / rotation angle),
  // > 0.
  double prior_sigma_t_m = 0.5;
  double prior_sigma_r_deg = 5.0;
  // Standard deviations of a registration in the robust phase, > 0.
  double edge_sigma_t_m = 0.05;
  double edge_sigma_r_deg = 0.5;
  // An edge is an inlier when its residual norm (6 components, whitened by
  // edge_sigma_*) ends below this, > 0.
  double max_edge_residual = 4.0;

  bool Check() const;
};

struct PoseGraphResult {
  // Per view: the optimised pose, and the connected component of the
  // inlier edges it belongs to (views without inlier edges are components
  // of their own).
  std::vector<Rigid3d> cam_from_world;
  std::vector<int> component;
  // Per edge.
  std::vector<bool> inlier;
  std::vector<double> residual;
  int num_inlier_edges = 0;
};

PoseGraphResult OptimizePoseGraph(
    const std::vector<Rigid3d>& prior_cam_from_world,
    const std::vector<PoseGraphEdge>& edges, const PoseGraphOptions& options);

}  // namespace colmap_lidar
