#include "src/matching/pose_graph.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cmath>
#include <numeric>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
// First scale of the graduated non-convexity, whitened residual units.
constexpr double kInitialScale = 64.0;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d skew;
  skew << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return skew;
}

Eigen::Vector3d Log(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd angle_axis(rotation);
  return angle_axis.angle() * angle_axis.axis();
}

Eigen::Matrix3d Exp(const Eigen::Vector3d& omega) {
  const double angle = omega.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
}

struct State {
  std::vector<Eigen::Matrix3d> rotation;  // cam_from_world
  std::vector<Eigen::Vector3d> center;    // camera centre, world
};

// The whitened residual of an edge and its Jacobians with respect to
// (theta_1, c_1, theta_2, c_2).
struct EdgeLinearization {
  Eigen::Matrix<double, 6, 1> residual;
  Eigen::Matrix<double, 6, 6> jacobian1;
  Eigen::Matrix<double, 6, 6> jacobian2;
};

EdgeLinearization LinearizeEdge(const State& state, const PoseGraphEdge& edge,
                                const Eigen::Matrix3d& measured_rotation,
                                const Eigen::Matrix<double, 6, 6>& whitening) {
  const int i = edge.view1;
  const int j = edge.view2;
  const Eigen::Matrix3d& r_i = state.rotation[i];
  const Eigen::Matrix3d& r_j = state.rotation[j];
  const Eigen::Matrix3d relative = r_j * r_i.transpose();
  const Eigen::Vector3d baseline = r_j * (state.center[i] - state.center[j]);
  Eigen::Matrix<double, 6, 1> residual;
  residual.head<3>() = Log(relative * measured_rotation.transpose());
  residual.tail<3>() = baseline - edge.cam2_from_cam1.translation;
  Eigen::Matrix<double, 6, 6> jacobian1 = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 6> jacobian2 = Eigen::Matrix<double, 6, 6>::Zero();
  jacobian1.block<3, 3>(0, 0) = -relative;
  jacobian1.block<3, 3>(3, 3) = r_j;
  jacobian2.block<3, 3>(0, 0).setIdentity();
  jacobian2.block<3, 3>(3, 0) = -Skew(baseline);
  jacobian2.block<3, 3>(3, 3) = -r_j;
  EdgeLinearization lin;
  lin.residual = whitening * residual;
  lin.jacobian1 = whitening * jacobian1;
  lin.jacobian2 = whitening * jacobian2;
  return lin;
}

}  // namespace

bool PoseGraphOptions::Check() const {
  bool ok = true;
  for (const double value : {prior_sigma_t_m, prior_sigma_r_deg, edge_sigma_t_m,
                             edge_sigma_r_deg, max_edge_residual}) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      LOG(ERROR) << "PoseGraphOptions: sigmas and max_edge_residual must be "
                    "> 0, got "
                 << value;
      ok = false;
    }
  }
  return ok;
}

PoseGraphResult OptimizePoseGraph(
    const std::vector<Rigid3d>& prior_cam_from_world,
    const std::vector<PoseGraphEdge>& edges, const PoseGraphOptions& options) {
  THROW_CHECK(options.Check(), "Invalid PoseGraphOptions");
  const int num_views = static_cast<int>(prior_cam_from_world.size());
  const int num_edges = static_cast<int>(edges.size());
  for (const PoseGraphEdge& edge : edges) {
    THROW_CHECK(edge.view1 >= 0 && edge.view1 < num_views && edge.view2 >= 0 &&
                    edge.view2 < num_views && edge.view1 != edge.view2,
                "Pose graph edge (" << edge.view1 << ", " << edge.view2
                                    << ") invalid for " << num_views
                                    << " views");
  }
  State prior;
  for (const Rigid3d& pose : prior_cam_from_world) {
    prior.rotation.push_back(pose.rotation.toRotationMatrix());
    prior.center.push_back(pose.Inverse().translation);
  }
  std::vector<Eigen::Matrix3d> measured_rotation;
  // L^T with L L^T = information.
  std::vector<Eigen::Matrix<double, 6, 6>> whitening;
  for (const PoseGraphEdge& edge : edges) {
    measured_rotation.push_back(
        edge.cam2_from_cam1.rotation.toRotationMatrix());
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(edge.information);
    THROW_CHECK(llt.info() == Eigen::Success,
                "Pose graph edge (" << edge.view1 << ", " << edge.view2
                                    << "): information not positive definite");
    whitening.push_back(llt.matrixU());
  }
  Eigen::Matrix<double, 6, 6> uniform_whitening =
      Eigen::Matrix<double, 6, 6>::Zero();
  uniform_whitening.diagonal().head<3>().setConstant(
      1.0 / (options.edge_sigma_r_deg * kDegToRad));
  uniform_whitening.diagonal().tail<3>().setConstant(1.0 /
                                                     options.edge_sigma_t_m);
  bool use_information = false;
  const double prior_sigma_r = options.prior_sigma_r_deg * kDegToRad;
  const double prior_sigma_t = options.prior_sigma_t_m;

  State state = prior;
  std::vector<double> weights(num_edges, 1.0);
  const auto residual_norm = [&](int e) {
    return LinearizeEdge(state, edges[e], measured_rotation[e],
                         uniform_whitening)
        .residual.norm();
  };
  const auto gauss_newton_step = [&]() {
    const int n = 6 * num_views;
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::VectorXd gradient = Eigen::VectorXd::Zero(n);
    const auto add_block = [&](int row_view, int col_view,
                               const Eigen::Matrix<double, 6, 6>& block) {
      for (int r = 0; r < 6; ++r) {
        for (int c = 0; c < 6; ++c) {
          if (block(r, c) != 0.0) {
            triplets.emplace_back(6 * row_view + r, 6 * col_view + c,
                                  block(r, c));
          }
        }
      }
    };
    for (int v = 0; v < num_views; ++v) {
      Eigen::Matrix<double, 6, 1> residual;
      residual.head<3>() =
          Log(state.rotation[v] * prior.rotation[v].transpose()) /
          prior_sigma_r;
      residual.tail<3>() = (state.center[v] - prior.center[v]) / prior_sigma_t;
      Eigen::Matrix<double, 6, 6> jacobian =
          Eigen::Matrix<double, 6, 6>::Zero();
      jacobian.block<3, 3>(0, 0).diagonal().setConstant(1.0 / prior_sigma_r);
      jacobian.block<3, 3>(3, 3).diagonal().setConstant(1.0 / prior_sigma_t);
      add_block(v, v, jacobian.transpose() * jacobian);
      gradient.segment<6>(6 * v) += jacobian.transpose() * residual;
    }
    for (int e = 0; e < num_edges; ++e) {
      if (weights[e] <= 0.0) continue;
      const EdgeLinearization lin =
          LinearizeEdge(state, edges[e], measured_rotation[e],
                        use_information ? whitening[e] : uniform_whitening);
      const double w = weights[e];
      const int i = edges[e].view1;
      const int j = edges[e].view2;
      add_block(i, i, w * lin.jacobian1.transpose() * lin.jacobian1);
      add_block(j, j, w * lin.jacobian2.transpose() * lin.jacobian2);
      add_block(i, j, w * lin.jacobian1.transpose() * lin.jacobian2);
      add_block(j, i, w * lin.jacobian2.transpose() * lin.jacobian1);
      gradient.segment<6>(6 * i) +=
          w * lin.jacobian1.transpose() * lin.residual;
      gradient.segment<6>(6 * j) +=
          w * lin.jacobian2.transpose() * lin.residual;
    }
    Eigen::SparseMatrix<double> hessian(n, n);
    hessian.setFromTriplets(triplets.begin(), triplets.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(hessian);
    if (solver.info() != Eigen::Success) return;
    const Eigen::VectorXd step = solver.solve(-gradient);
    if (!step.allFinite()) return;
    for (int v = 0; v < num_views; ++v) {
      state.rotation[v] = Exp(step.segment<3>(6 * v)) * state.rotation[v];
      state.center[v] += step.segment<3>(6 * v + 3);
    }
  };

  // Graduated non-convexity: Geman-McClure weights (s^2 / (e^2 + s^2))^2
  // with a shrinking scale s, from nearly least squares to the inlier
  // threshold.
  for (double scale = kInitialScale; scale >= options.max_edge_residual;
       scale *= 0.5) {
    for (int iteration = 0; iteration < 3; ++iteration) {
      for (int e = 0; e < num_edges; ++e) {
        const double r = residual_norm(e);
        const double w = scale * scale / (r * r + scale * scale);
        weights[e] = w * w;
      }
      gauss_newton_step();
    }
  }
  PoseGraphResult result;
  result.inlier.assign(num_edges, false);
  result.residual.assign(num_edges, 0.0);
  for (int e = 0; e < num_edges; ++e) {
    result.residual[e] = residual_norm(e);
    result.inlier[e] = result.residual[e] < options.max_edge_residual;
    weights[e] = result.inlier[e] ? 1.0 : 0.0;
  }
  use_information = true;
  for (int iteration = 0; iteration < 3; ++iteration) gauss_newton_step();
  for (int e = 0; e < num_edges; ++e) {
    result.residual[e] = residual_norm(e);
  }

  // Components of the inlier edges.
  std::vector<int> parent(num_views);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (int e = 0; e < num_edges; ++e) {
    if (!result.inlier[e]) continue;
    ++result.num_inlier_edges;
    parent[find(edges[e].view1)] = find(edges[e].view2);
  }
  result.component.resize(num_views);
  for (int v = 0; v < num_views; ++v) result.component[v] = find(v);
  result.cam_from_world.resize(num_views);
  for (int v = 0; v < num_views; ++v) {
    const Eigen::Quaterniond rotation(state.rotation[v]);
    result.cam_from_world[v] =
        Rigid3d(rotation.normalized(), -(state.rotation[v] * state.center[v]));
  }
  return result;
}

}  // namespace colmap_lidar
