// Step 2 of the relative line pose (relative_line_pose.h): the rotation
// alone, from the directions of the candidate correspondences. Every
// candidate of the right direction family agrees on it, true match or not,
// so RANSAC on pairs of non-parallel candidates converges in a few samples;
// a least-squares fit (Kabsch on directions) over the inliers follows.
// Internal to src/matching.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "src/matching/line_matching_options.h"
#include "src/matching/relative_line_pose_problem.h"

namespace colmap_lidar {
namespace relative_pose_internal {

// The rotation of cam2_from_cam1 from problem.candidates, at most
// `max_rotation_change_deg` from the prior rotation. False when the
// directions cannot fix it (one family: all lines parallel). Deterministic
// for a given seed.
bool EstimateLineRotation(const LinePoseProblem& problem,
                          const LineMatchingOptions& options,
                          double max_rotation_change_deg, uint32_t seed,
                          Eigen::Matrix3d* rotation);

}  // namespace relative_pose_internal
}  // namespace colmap_lidar
