// The relative line pose of two views (relative_line_pose.h): the RANSAC
// over rotation and translation hypotheses, their MSAC scoring, the
// refinement rounds alternating with the inlier selection, and the
// validation and information matrix of the result. The steps live in
// relative_line_pose_problem.h (candidates), relative_line_rotation.h,
// relative_line_translation.h and relative_line_refinement.h.
#include "src/matching/relative_line_pose.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "src/matching/relative_line_pose_problem.h"
#include "src/matching/relative_line_refinement.h"
#include "src/matching/relative_line_rotation.h"
#include "src/matching/relative_line_translation.h"

namespace colmap_lidar {
namespace {

using relative_pose_internal::EstimateLineRotation;
using relative_pose_internal::FindCandidates;
using relative_pose_internal::kTranslationVoteCellM;
using relative_pose_internal::Line;
using relative_pose_internal::LinePoseLinearization;
using relative_pose_internal::LinePoseProblem;
using relative_pose_internal::LinearizeLinePose;
using relative_pose_internal::LineDistance;
using relative_pose_internal::MakeLinePoseProblem;
using relative_pose_internal::OrthogonalProjector;
using relative_pose_internal::RefineLinePose;
using relative_pose_internal::RotationAngleDeg;
using relative_pose_internal::VoteLineTranslations;

class Registration {
 public:
  Registration(const MatchingView& view1, const std::vector<int>& segments1,
               const MatchingView& view2, const LineMatchingOptions& options)
      : options_(options),
        problem_(MakeLinePoseProblem(view1, segments1, view2)) {
    sin_inlier_angle_ =
        std::sin(options.relative_pose_inlier_angle_deg * M_PI / 180.0);
    inlier_distance_m_ = options.relative_pose_inlier_distance_m;
  }

  // Per segment of view 1: the best candidate's normalised squared error
  // under the hypothesis (and its index), truncated at 1.
  double Score(const Eigen::Matrix3d& rotation,
               const Eigen::Vector3d& translation, const double distance_scale,
               std::vector<int>* best_candidate) const {
    const std::vector<Line>& lines1 = problem_.lines1;
    double cost = 0.0;
    if (best_candidate != nullptr) {
      best_candidate->assign(lines1.size(), -1);
    }
    for (size_t a = 0; a < lines1.size(); ++a) {
      double best = 1.0;
      const Eigen::Vector3d direction = rotation * lines1[a].direction;
      for (const int c : problem_.candidates_of[a]) {
        const Line& b = problem_.lines2[problem_.candidates[c].b];
        // Small angles: the sine is the angle.
        const double angle =
            direction.cross(b.direction).norm() / sin_inlier_angle_;
        if (angle >= 1.0) continue;
        const double distance =
            LineDistance(rotation, translation, lines1[a], b) / distance_scale;
        const double error = angle * angle + distance * distance;
        if (error < best) {
          best = error;
          if (best_candidate != nullptr) (*best_candidate)[a] = c;
        }
      }
      cost += best;
    }
    return cost;
  }

  RelativeLinePose Run(const uint32_t seed) {
    RelativeLinePose result;
    max_rotation_change_deg_ =
        EffectiveThresholds(options_, 1.0, problem_.focal_length2).theta_deg;
    FindCandidates(options_, &problem_);
    result.num_candidates = static_cast<int>(problem_.candidates.size());
    if (result.num_candidates < 2) return result;
    Eigen::Matrix3d rotation;
    if (!EstimateLineRotation(problem_, options_, max_rotation_change_deg_,
                              seed, &rotation)) {
      return result;
    }
    // Screen the vote peaks with one short refinement each; refine the
    // most promising ones fully.
    std::vector<std::pair<double, Eigen::Vector3d>> screened;
    for (const Eigen::Vector3d& translation :
         VoteLineTranslations(problem_, options_, rotation)) {
      screened.emplace_back(Screen(rotation, translation), translation);
    }
    std::sort(screened.begin(), screened.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::pair<double, RelativeLinePose>> hypotheses;
    for (size_t h = 0;
         h < screened.size() && static_cast<int>(h) < kFullHypotheses; ++h) {
      if (!std::isfinite(screened[h].first)) break;
      RelativeLinePose candidate = result;
      const double cost = Finish(rotation, screened[h].second, &candidate);
      if (std::isfinite(cost)) hypotheses.emplace_back(cost, candidate);
    }
    if (hypotheses.empty()) return result;
    std::sort(hypotheses.begin(), hypotheses.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    const int num_hypotheses = static_cast<int>(hypotheses.size());
    result = hypotheses.front().second;
    result.num_hypotheses = num_hypotheses;
    result.cost = hypotheses.front().first;
    // The runner-up: the best hypothesis that converged elsewhere.
    for (size_t h = 1; h < hypotheses.size(); ++h) {
      const Rigid3d& other = hypotheses[h].second.cam2_from_cam1;
      if ((other.translation - result.cam2_from_cam1.translation).norm() >
              kDistinctTranslationM ||
          RotationAngleDeg(
              (other.rotation * result.cam2_from_cam1.rotation.inverse())
                  .toRotationMatrix()) > kDistinctRotationDeg) {
        result.runner_up_cost = hypotheses[h].first;
        result.runner_up_inliers = hypotheses[h].second.num_inliers;
        break;
      }
    }
    return result;
  }

  // Inliers <-> refinement from (rotation, translation), then validation.
  RelativeLinePose RunFrom(const Rigid3d& cam2_from_cam1) {
    RelativeLinePose result;
    max_rotation_change_deg_ =
        EffectiveThresholds(options_, 1.0, problem_.focal_length2).theta_deg;
    FindCandidates(options_, &problem_);
    result.num_candidates = static_cast<int>(problem_.candidates.size());
    Finish(cam2_from_cam1.rotation.toRotationMatrix(),
           cam2_from_cam1.translation, &result);
    return result;
  }

  // MSAC cost after a short refinement from a vote cell's centre.
  double Screen(Eigen::Matrix3d rotation, Eigen::Vector3d translation) const {
    std::vector<int> best_candidate;
    Score(rotation, translation,
          std::max(inlier_distance_m_, kTranslationVoteCellM), &best_candidate);
    std::vector<int> inliers;
    for (const int c : best_candidate) {
      if (c >= 0) inliers.push_back(c);
    }
    if (static_cast<int>(inliers.size()) < 2) {
      return std::numeric_limits<double>::infinity();
    }
    RefineLinePose(problem_, inliers, &rotation, &translation,
                   kScreeningIterations);
    return Score(rotation, translation, inlier_distance_m_, nullptr);
  }

  // Returns the final MSAC cost.
  double Finish(Eigen::Matrix3d best_rotation, Eigen::Vector3d best_translation,
                RelativeLinePose* result_ptr) const {
    RelativeLinePose& result = *result_ptr;
    std::vector<int> best_candidate;
    std::vector<int> inliers;
    for (int round = 0; round < kRefinementRounds; ++round) {
      // The first round starts from a vote cell's centre.
      Score(best_rotation, best_translation,
            round == 0 ? std::max(inlier_distance_m_, kTranslationVoteCellM)
                       : inlier_distance_m_,
            &best_candidate);
      inliers.clear();
      for (const int c : best_candidate) {
        if (c >= 0) inliers.push_back(c);
      }
      if (static_cast<int>(inliers.size()) < 2) {
        return std::numeric_limits<double>::infinity();
      }
      RefineLinePose(problem_, inliers, &best_rotation, &best_translation);
    }
    const double cost = Score(best_rotation, best_translation,
                              inlier_distance_m_, &best_candidate);
    inliers.clear();
    Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
    for (const int c : best_candidate) {
      if (c < 0) continue;
      inliers.push_back(c);
      information += OrthogonalProjector(
          problem_.lines2[problem_.candidates[c].b].direction);
    }
    result.num_inliers = static_cast<int>(inliers.size());
    result.translation_conditioning =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(information)
            .eigenvalues()(0);
    result.cam2_from_cam1 = Rigid3d(
        Eigen::Quaterniond(best_rotation).normalized(), best_translation);
    // Information of (theta, t), scaled by the a posteriori variance factor
    // (the residuals' scales are nominal), with a floor on the covariance
    // for what the residuals do not model.
    const LinePoseLinearization lin =
        LinearizeLinePose(problem_, inliers, best_rotation, best_translation);
    const double variance_factor =
        lin.num_residuals > 6
            ? std::max(kMinVarianceFactor,
                       lin.squared_error / (lin.num_residuals - 6))
            : 1.0;
    Eigen::Matrix<double, 6, 6> covariance =
        (lin.hessian / variance_factor)
            .ldlt()
            .solve(Eigen::Matrix<double, 6, 6>::Identity());
    covariance.diagonal().head<3>().array() +=
        std::pow(kMinSigmaRotationDeg * M_PI / 180.0, 2);
    covariance.diagonal().tail<3>().array() +=
        std::pow(kMinSigmaTranslationM, 2);
    result.information =
        covariance.ldlt().solve(Eigen::Matrix<double, 6, 6>::Identity());
    result.valid =
        result.num_inliers >= options_.relative_pose_min_inliers &&
        result.translation_conditioning >= kMinTranslationConditioning &&
        RotationAngleDeg(best_rotation * problem_.prior_rotation.transpose()) <=
            max_rotation_change_deg_;
    return cost;
  }

 private:
  static constexpr double kDistinctTranslationM = 0.3;
  static constexpr double kDistinctRotationDeg = 1.0;
  static constexpr int kScreeningIterations = 2;
  static constexpr int kFullHypotheses = 3;
  static constexpr int kRefinementRounds = 3;
  static constexpr double kMinVarianceFactor = 0.25;
  static constexpr double kMinSigmaRotationDeg = 0.03;
  static constexpr double kMinSigmaTranslationM = 0.005;
  // About two lines' worth of constraint along the weakest axis.
  static constexpr double kMinTranslationConditioning = 1.5;

  const LineMatchingOptions& options_;
  LinePoseProblem problem_;
  double sin_inlier_angle_ = 1.0;
  double inlier_distance_m_ = 0.1;
  double max_rotation_change_deg_ = 180.0;
};

}  // namespace

RelativeLinePose EstimateRelativeLinePose(const MatchingView& view1,
                                          const std::vector<int>& segments1,
                                          const MatchingView& view2,
                                          const LineMatchingOptions& options,
                                          const uint32_t seed) {
  Registration registration(view1, segments1, view2, options);
  return registration.Run(seed);
}

RelativeLinePose RefineRelativeLinePose(const MatchingView& view1,
                                        const std::vector<int>& segments1,
                                        const MatchingView& view2,
                                        const LineMatchingOptions& options,
                                        const Rigid3d& cam2_from_cam1) {
  Registration registration(view1, segments1, view2, options);
  return registration.RunFrom(cam2_from_cam1);
}

}  // namespace colmap_lidar
