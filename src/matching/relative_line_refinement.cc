#include "src/matching/relative_line_refinement.h"

#include <Eigen/Dense>

namespace colmap_lidar {
namespace relative_pose_internal {
namespace {

// Noise scales of the residuals: 3D endpoint to line, and endpoint to
// interpretation plane in pixels.
constexpr double kRefineSigma3DM = 0.05;
constexpr double kRefineSigmaPx = 1.0;

}  // namespace

LinePoseLinearization LinearizeLinePose(const LinePoseProblem& problem,
                                        const std::vector<int>& inliers,
                                        const Eigen::Matrix3d& rotation,
                                        const Eigen::Vector3d& translation) {
  const double weight_3d = 1.0 / kRefineSigma3DM;
  const double weight_plane2 = problem.focal_length2 / kRefineSigmaPx;
  const double weight_plane1 = problem.focal_length1 / kRefineSigmaPx;
  LinePoseLinearization lin;
  const auto add = [&](const auto& jacobian, const auto& residual) {
    lin.hessian += jacobian.transpose() * jacobian;
    lin.gradient += jacobian.transpose() * residual;
    lin.squared_error += residual.squaredNorm();
    lin.num_residuals += static_cast<int>(residual.size());
  };
  for (const int c : inliers) {
    const Line& a = problem.lines1[problem.candidates[c].a];
    const Line& b = problem.lines2[problem.candidates[c].b];
    const Eigen::Matrix3d projector = OrthogonalProjector(b.direction);
    for (const Eigen::Vector3d* point : {&a.start, &a.end}) {
      const Eigen::Vector3d moved = rotation * *point;
      const Eigen::Vector3d in_cam2 = moved + translation;
      // 3D endpoint to line.
      Eigen::Matrix<double, 3, 6> jacobian;
      jacobian.leftCols<3>() = -projector * Skew(moved);
      jacobian.rightCols<3>() = projector;
      add(weight_3d * jacobian,
          Eigen::Vector3d(weight_3d * projector * (in_cam2 - b.midpoint)));
      // Endpoint of a to b's interpretation plane, view 2.
      const double norm = in_cam2.norm();
      if (norm < 1e-9) continue;
      const Eigen::Matrix<double, 1, 3> d_residual =
          weight_plane2 * (b.plane_normal.transpose() / norm -
                           b.plane_normal.dot(in_cam2) * in_cam2.transpose() /
                               (norm * norm * norm));
      Eigen::Matrix<double, 1, 6> plane_jacobian;
      plane_jacobian.leftCols<3>() = -d_residual * Skew(moved);
      plane_jacobian.rightCols<3>() = d_residual;
      add(plane_jacobian,
          Eigen::Matrix<double, 1, 1>(weight_plane2 *
                                      b.plane_normal.dot(in_cam2) / norm));
    }
    // Endpoints of b to a's interpretation plane, view 1:
    // q = R^T (B - t); dq/dtheta = R^T [B - t]x, dq/dt = -R^T.
    for (const Eigen::Vector3d* point : {&b.start, &b.end}) {
      const Eigen::Vector3d offset = *point - translation;
      const Eigen::Vector3d in_cam1 = rotation.transpose() * offset;
      const double norm = in_cam1.norm();
      if (norm < 1e-9) continue;
      const Eigen::Matrix<double, 1, 3> d_residual =
          weight_plane1 * (a.plane_normal.transpose() / norm -
                           a.plane_normal.dot(in_cam1) * in_cam1.transpose() /
                               (norm * norm * norm));
      Eigen::Matrix<double, 1, 6> plane_jacobian;
      plane_jacobian.leftCols<3>() =
          d_residual * rotation.transpose() * Skew(offset);
      plane_jacobian.rightCols<3>() = -d_residual * rotation.transpose();
      add(plane_jacobian,
          Eigen::Matrix<double, 1, 1>(weight_plane1 *
                                      a.plane_normal.dot(in_cam1) / norm));
    }
  }
  return lin;
}

void RefineLinePose(const LinePoseProblem& problem,
                    const std::vector<int>& inliers, Eigen::Matrix3d* rotation,
                    Eigen::Vector3d* translation, const int num_iterations) {
  for (int iteration = 0; iteration < num_iterations; ++iteration) {
    const LinePoseLinearization lin =
        LinearizeLinePose(problem, inliers, *rotation, *translation);
    const Eigen::Matrix<double, 6, 1> step =
        lin.hessian.ldlt().solve(-lin.gradient);
    if (!step.allFinite()) return;
    const Eigen::Vector3d omega = step.head<3>();
    if (omega.norm() > 0.0) {
      *rotation = Eigen::AngleAxisd(omega.norm(), omega.normalized())
                      .toRotationMatrix() *
                  *rotation;
    }
    *translation += step.tail<3>();
    if (step.norm() < 1e-9) return;
  }
}

}  // namespace relative_pose_internal
}  // namespace colmap_lidar
