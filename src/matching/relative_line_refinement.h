// Step 4 of the relative line pose (relative_line_pose.h): Gauss-Newton on
// the inlier correspondences, with two kinds of residuals: the 3D distance
// of a's endpoints to b's line (metric, but dominated by the LIDAR depth
// noise along the rays), and, both ways, the angle between an endpoint and
// the other view's interpretation plane of its segment (the plane through
// the camera centre and the 2D segment: blind to depth noise along the
// rays, as precise as the 2D detection). Internal to src/matching.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "src/matching/relative_line_pose_problem.h"

namespace colmap_lidar {
namespace relative_pose_internal {

// The normal equations in (theta, t), for rotation <- Exp(theta) rotation,
// translation <- translation + t, with the residuals weighted by their
// nominal noise (5 cm in 3D, 1 px on the interpretation planes).
struct LinePoseLinearization {
  Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> gradient = Eigen::Matrix<double, 6, 1>::Zero();
  double squared_error = 0.0;
  int num_residuals = 0;
};

// `inliers`: indices into problem.candidates.
LinePoseLinearization LinearizeLinePose(const LinePoseProblem& problem,
                                        const std::vector<int>& inliers,
                                        const Eigen::Matrix3d& rotation,
                                        const Eigen::Vector3d& translation);

constexpr int kLinePoseGaussNewtonIterations = 5;

// Gauss-Newton steps from (rotation, translation) in place, until the step
// is below 1e-9 or not finite.
void RefineLinePose(const LinePoseProblem& problem,
                    const std::vector<int>& inliers, Eigen::Matrix3d* rotation,
                    Eigen::Vector3d* translation,
                    int num_iterations = kLinePoseGaussNewtonIterations);

}  // namespace relative_pose_internal
}  // namespace colmap_lidar
