// The relative pose of two views from their 3D line segments, for the line
// association under uncertain prior poses (paper section III-C with the
// paper's 0.5 m / 5 deg priors).
//
// Each view's segments are metric in its own camera frame (lifted by the
// LIDAR), so two views that see the same edges can be registered on the
// segments alone: the prior relative pose only has to be good enough to
// gate candidate correspondences. Steps, for views 1 and 2:
//   1. Candidates: every segment a of view 1 (those visible in view 2 under
//      the prior) against every segment b of view 2: the 3D directions
//      within the rotation gate and a's midpoint within the distance gate
//      of b's line after the prior relative pose (gates from the pose
//      uncertainty, EffectiveThresholds), LBD distance below t_LBD.
//   2. Rotation: every candidate of the right direction family agrees on
//      it, true match or not, so that sampling pairs of non-parallel
//      candidates (100 samples, inliers within the inlier angle) and a
//      least-squares fit over the inliers find it; one family only (all
//      lines parallel) does not register.
//   3. Translation: under that rotation, a candidate allows the
//      translations of a line (a's midpoint onto b's line); these vote in a
//      15 cm grid around the prior, and the strongest separate local maxima
//      are the hypotheses. Periodic facades give several (a shift by a
//      window's width): all are screened by a short refinement.
//   4. Each of the best hypotheses is refined by Gauss-Newton alternating
//      with the inlier selection, on the 3D endpoint-to-line distances and
//      on the angles of the endpoints to the other view's interpretation
//      planes (blind to the depth noise along the rays); the one with the
//      lowest MSAC cost (over the segments of view 1: the best candidate's
//      squared normalised angle and distance, truncated at 1) wins.
// The pose is accepted with at least min_inliers inlier segments whose
// directions pin the translation in all three axes. A periodic facade can
// still make a wrong shift win; pose_graph.h sorts those out.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <vector>

#include "colmap_ext/scene/rigid3.h"
#include "src/matching/line_matching_options.h"
#include "src/matching/matching_view.h"

namespace colmap_lidar {

struct RelativeLinePose {
  bool valid = false;
  // x_cam2 = cam2_from_cam1 * x_cam1.
  Rigid3d cam2_from_cam1;
  // Segments of view 1 with an inlier correspondence, and their number of
  // distinct directions' weakest translation axis (smallest eigenvalue of
  // the sum of the projectors orthogonal to the inlier lines).
  int num_inliers = 0;
  double translation_conditioning = 0.0;
  // Candidate correspondences and RANSAC hypotheses scored.
  int num_candidates = 0;
  int num_hypotheses = 0;
  // MSAC cost of the result (segments of view 1 count 1 as outliers, less
  // as inliers), and of the best hypothesis that converged more than 0.3 m
  // or 1 deg away (+infinity without one): close costs mean an ambiguous
  // registration (a periodic facade).
  double cost = 0.0;
  double runner_up_cost = std::numeric_limits<double>::infinity();
  int runner_up_inliers = 0;
  // Information matrix of the pose, for the increments (theta, t) with
  // rotation <- Exp(theta) rotation, translation <- translation + t (view 2
  // frame).
  Eigen::Matrix<double, 6, 6> information =
      Eigen::Matrix<double, 6, 6>::Identity();
};

// `segments1`: the segments of view1 to register (indices), e.g. those the
// prior places in view2's field of view. Deterministic for a given seed.
RelativeLinePose EstimateRelativeLinePose(const MatchingView& view1,
                                          const std::vector<int>& segments1,
                                          const MatchingView& view2,
                                          const LineMatchingOptions& options,
                                          uint32_t seed);

// Steps 1 and 3 only, from `cam2_from_cam1` instead of RANSAC's best.
RelativeLinePose RefineRelativeLinePose(const MatchingView& view1,
                                        const std::vector<int>& segments1,
                                        const MatchingView& view2,
                                        const LineMatchingOptions& options,
                                        const Rigid3d& cam2_from_cam1);

}  // namespace colmap_lidar
