#include "src/eval/pose_alignment.h"

#include <cmath>

#include <Eigen/SVD>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

TrajectoryAlignment AlignCentresAndAxes(
    const std::vector<Eigen::Vector3d>& centres_est,
    const std::vector<Eigen::Quaterniond>& world_from_cam_est,
    const std::vector<Eigen::Vector3d>& centres_gt,
    const std::vector<Eigen::Quaterniond>& world_from_cam_gt,
    bool with_scale, double axes_weight) {
  const size_t n = centres_est.size();
  THROW_CHECK(n > 0, "Trajectory alignment: no matched camera");
  THROW_CHECK(world_from_cam_est.size() == n && centres_gt.size() == n &&
                  world_from_cam_gt.size() == n,
              "Trajectory alignment: " << n << " estimated centres but "
                                       << world_from_cam_est.size() << ", "
                                       << centres_gt.size() << ", "
                                       << world_from_cam_gt.size()
                                       << " other inputs");
  THROW_CHECK(axes_weight >= 0.0 && std::isfinite(axes_weight),
              "Trajectory alignment: axes_weight must be >= 0, got "
                  << axes_weight);

  Eigen::Vector3d mean_est = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_gt = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    mean_est += centres_est[i];
    mean_gt += centres_gt[i];
  }
  mean_est /= static_cast<double>(n);
  mean_gt /= static_cast<double>(n);
  double spread_est2 = 0.0;  // sum of squared distances to the centroid
  double spread_gt2 = 0.0;
  Eigen::Matrix3d cross_positions = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d cross_axes = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d x = centres_est[i] - mean_est;
    const Eigen::Vector3d y = centres_gt[i] - mean_gt;
    spread_est2 += x.squaredNorm();
    spread_gt2 += y.squaredNorm();
    cross_positions += y * x.transpose();
    cross_axes += world_from_cam_gt[i].normalized().toRotationMatrix() *
                  world_from_cam_est[i].normalized().toRotationMatrix()
                      .transpose();
  }
  THROW_CHECK(!with_scale || spread_est2 > 0.0,
              "Trajectory alignment with scale: all estimated camera centres "
              "coincide");
  Eigen::Matrix3d cross = axes_weight * cross_axes / static_cast<double>(n);
  // sigma_x sigma_y N = sqrt(spread_est2 * spread_gt2).
  const double normaliser = std::sqrt(spread_est2 * spread_gt2);
  if (normaliser > 0.0) {
    cross += cross_positions / normaliser;
  }
  THROW_CHECK(cross.squaredNorm() > 0.0,
              "Trajectory alignment: the rotation is undetermined (coincident "
              "centres and axes_weight 0)");

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d sign = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) {
    sign(2, 2) = -1.0;
  }
  TrajectoryAlignment alignment;
  alignment.rotation = svd.matrixU() * sign * svd.matrixV().transpose();
  if (with_scale) {
    // Least-squares scale of the centres given the rotation.
    alignment.scale = (alignment.rotation.transpose() * cross_positions)
                          .trace() /
                      spread_est2;
    THROW_CHECK(alignment.scale > 0.0,
                "Trajectory alignment with scale: the centres give a "
                "non-positive scale ("
                    << alignment.scale
                    << "); the orientations disagree with the centres");
  }
  alignment.translation =
      mean_gt - alignment.scale * alignment.rotation * mean_est;
  return alignment;
}

}  // namespace colmap_lidar
