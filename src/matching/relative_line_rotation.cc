#include "src/matching/relative_line_rotation.h"

#include <Eigen/Dense>
#include <random>
#include <vector>

namespace colmap_lidar {
namespace relative_pose_internal {
namespace {

constexpr double kMinSampleAngleDeg = 20.0;
constexpr int kRotationSamples = 100;
// Second eigenvalue of the sum of x x^T over the direction inliers.
constexpr double kMinRotationConditioning = 1.0;

// The rotation taking directions x1, x2 onto y1, y2 (least squares over the
// two and their cross product).
Eigen::Matrix3d RotationFromTwoDirections(const Eigen::Vector3d& x1,
                                          const Eigen::Vector3d& x2,
                                          const Eigen::Vector3d& y1,
                                          const Eigen::Vector3d& y2) {
  const Eigen::Vector3d x3 = x1.cross(x2).normalized();
  const Eigen::Vector3d y3 = y1.cross(y2).normalized();
  const Eigen::Matrix3d covariance =
      y1 * x1.transpose() + y2 * x2.transpose() + y3 * x3.transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d fix = Eigen::Matrix3d::Identity();
  fix(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0
                  ? -1.0
                  : 1.0;
  return svd.matrixU() * fix * svd.matrixV().transpose();
}

}  // namespace

bool EstimateLineRotation(const LinePoseProblem& problem,
                          const LineMatchingOptions& options,
                          const double max_rotation_change_deg,
                          const uint32_t seed, Eigen::Matrix3d* rotation) {
  const std::vector<Candidate>& candidates = problem.candidates;
  const int num_candidates = static_cast<int>(candidates.size());
  std::vector<Eigen::Vector3d> from(num_candidates);
  for (int c = 0; c < num_candidates; ++c) {
    const Eigen::Vector3d& direction =
        problem.lines1[candidates[c].a].direction;
    from[c] = (problem.prior_rotation * direction)
                          .dot(candidates[c].direction_b) >= 0.0
                  ? direction
                  : Eigen::Vector3d(-direction);
  }
  const double cos_inlier =
      std::cos(options.relative_pose_inlier_angle_deg * M_PI / 180.0);
  const auto count_inliers = [&](const Eigen::Matrix3d& r,
                                 std::vector<int>* inliers) {
    int count = 0;
    if (inliers != nullptr) inliers->clear();
    for (int c = 0; c < num_candidates; ++c) {
      if ((r * from[c]).dot(candidates[c].direction_b) > cos_inlier) {
        ++count;
        if (inliers != nullptr) inliers->push_back(c);
      }
    }
    return count;
  };
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, num_candidates - 1);
  int best_count = 0;
  Eigen::Matrix3d best = problem.prior_rotation;
  for (int sample = 0; sample < kRotationSamples; ++sample) {
    const int c1 = pick(rng);
    const int c2 = pick(rng);
    if (AngleDeg(from[c1], from[c2]) < kMinSampleAngleDeg ||
        AngleDeg(candidates[c1].direction_b, candidates[c2].direction_b) <
            kMinSampleAngleDeg) {
      continue;
    }
    const Eigen::Matrix3d r = RotationFromTwoDirections(
        from[c1], from[c2], candidates[c1].direction_b,
        candidates[c2].direction_b);
    if (RotationAngleDeg(r * problem.prior_rotation.transpose()) >
        max_rotation_change_deg) {
      continue;
    }
    const int count = count_inliers(r, nullptr);
    if (count > best_count) {
      best_count = count;
      best = r;
    }
  }
  if (best_count < 2) return false;
  // Least squares over the inliers (Kabsch on directions).
  std::vector<int> inliers;
  for (int round = 0; round < 2; ++round) {
    count_inliers(best, &inliers);
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
    for (const int c : inliers) {
      covariance += candidates[c].direction_b * from[c].transpose();
      spread += from[c] * from[c].transpose();
    }
    // Two directions at least: the second eigenvalue of the spread.
    if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(spread).eigenvalues()(
            1) < kMinRotationConditioning) {
      return false;
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
        covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d fix = Eigen::Matrix3d::Identity();
    fix(2, 2) =
        (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0
                                                                        : 1.0;
    best = svd.matrixU() * fix * svd.matrixV().transpose();
  }
  *rotation = best;
  return true;
}

}  // namespace relative_pose_internal
}  // namespace colmap_lidar
