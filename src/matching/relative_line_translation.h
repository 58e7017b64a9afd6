// Step 3 of the relative line pose (relative_line_pose.h): translation
// hypotheses under a known rotation. A candidate correspondence (a, b)
// allows the translations of a line (a's midpoint onto b's line); these vote
// in a grid of kTranslationVoteCellM cells around the prior translation, and
// the strongest separate local maxima are the hypotheses. Periodic facades
// give several (a shift by a window's width), so more than one is returned.
// Internal to src/matching.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "src/matching/line_matching_options.h"
#include "src/matching/relative_line_pose_problem.h"

namespace colmap_lidar {
namespace relative_pose_internal {

// Edge of a vote cell; also the distance scale of the first inlier
// selection from a cell's centre.
constexpr double kTranslationVoteCellM = 0.15;

// The centres of the best local maxima of the votes under `rotation`,
// strongest first (at most 12, more than 2 cells apart). The grid spans the
// distance gate (EffectiveThresholds at the segments' mean depth) around the
// prior translation, moved so that the segments' centroid stays put.
std::vector<Eigen::Vector3d> VoteLineTranslations(
    const LinePoseProblem& problem, const LineMatchingOptions& options,
    const Eigen::Matrix3d& rotation);

}  // namespace relative_pose_internal
}  // namespace colmap_lidar
