#include "src/matching/pose_graph.h"

#include <gtest/gtest.h>

#include <random>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Cameras on a circle of radius 8 m, looking outwards.
std::vector<Rigid3d> RingOfCameras(const int num_views) {
  std::vector<Rigid3d> cam_from_world;
  for (int v = 0; v < num_views; ++v) {
    const double angle = 2.0 * M_PI * v / num_views;
    const Eigen::Vector3d center(8.0 * std::cos(angle), 8.0 * std::sin(angle),
                                 1.5);
    // z (forward) outwards, y down.
    const Eigen::Vector3d z(std::cos(angle), std::sin(angle), 0.0);
    const Eigen::Vector3d y(0.0, 0.0, -1.0);
    Eigen::Matrix3d world_from_cam;
    world_from_cam << y.cross(z), y, z;
    const Eigen::Quaterniond rotation(world_from_cam.transpose());
    cam_from_world.emplace_back(rotation, -(rotation * center));
  }
  return cam_from_world;
}

std::vector<Rigid3d> Perturb(const std::vector<Rigid3d>& poses, double sigma_t,
                             double sigma_r_deg, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Rigid3d> perturbed;
  for (const Rigid3d& pose : poses) {
    const Eigen::Vector3d axis =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const Eigen::Quaterniond rotation =
        Eigen::Quaterniond(
            Eigen::AngleAxisd(sigma_r_deg * M_PI / 180.0 * normal(rng), axis)) *
        pose.rotation;
    const Eigen::Vector3d center =
        pose.Inverse().translation +
        sigma_t * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    perturbed.emplace_back(rotation.normalized(), -(rotation * center));
  }
  return perturbed;
}

TEST(PoseGraph, ConsistentRegistrationsFixRelativePosesAndDropAWrongOne) {
  const int num_views = 16;
  const std::vector<Rigid3d> truth = RingOfCameras(num_views);
  const std::vector<Rigid3d> priors = Perturb(truth, 0.5, 5.0, 3);
  // Registrations of the neighbours up to 3 apart, 1 cm / 0.05 deg noisy,
  // and one off by a window's width (2.4 m along the camera's x).
  const std::vector<Rigid3d> noise =
      Perturb(std::vector<Rigid3d>(3 * num_views), 0.01, 0.05, 4);
  std::vector<PoseGraphEdge> edges;
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  information.diagonal().head<3>().setConstant(
      1.0 / std::pow(0.05 * M_PI / 180.0, 2));
  information.diagonal().tail<3>().setConstant(1.0 / std::pow(0.01, 2));
  for (int v = 0; v < num_views; ++v) {
    for (int step = 1; step <= 3; ++step) {
      const int w = (v + step) % num_views;
      PoseGraphEdge edge;
      edge.view1 = v;
      edge.view2 = w;
      edge.cam2_from_cam1 =
          noise[3 * v + step - 1] * truth[w] * truth[v].Inverse();
      edge.information = information;
      edges.push_back(edge);
    }
  }
  const int wrong = 7;
  edges[wrong].cam2_from_cam1.translation += Eigen::Vector3d(2.4, 0.0, 0.0);

  const PoseGraphResult result =
      OptimizePoseGraph(priors, edges, PoseGraphOptions());
  ASSERT_EQ(result.cam_from_world.size(), truth.size());
  EXPECT_EQ(result.num_inlier_edges, static_cast<int>(edges.size()) - 1);
  EXPECT_FALSE(result.inlier[wrong]);
  for (int v = 0; v < num_views; ++v) {
    EXPECT_EQ(result.component[v], result.component[0]);
    const int w = (v + 1) % num_views;
    const Rigid3d estimate =
        result.cam_from_world[w] * result.cam_from_world[v].Inverse();
    const Rigid3d expected = truth[w] * truth[v].Inverse();
    EXPECT_LT((estimate.translation - expected.translation).norm(), 0.02);
    EXPECT_LT(Eigen::AngleAxisd(estimate.rotation * expected.rotation.inverse())
                      .angle() *
                  180.0 / M_PI,
              0.1);
  }
  // The priors alone are 0.5 m / 5 deg off.
  const Rigid3d prior_relative = priors[1] * priors[0].Inverse();
  EXPECT_GT(
      (prior_relative.translation - (truth[1] * truth[0].Inverse()).translation)
          .norm(),
      0.1);
}

TEST(PoseGraph, ViewsWithoutEdgesKeepTheirPriorsInTheirOwnComponent) {
  const std::vector<Rigid3d> truth = RingOfCameras(4);
  std::vector<PoseGraphEdge> edges(1);
  edges[0].view1 = 0;
  edges[0].view2 = 1;
  edges[0].cam2_from_cam1 = truth[1] * truth[0].Inverse();
  const PoseGraphResult result =
      OptimizePoseGraph(truth, edges, PoseGraphOptions());
  EXPECT_EQ(result.component[0], result.component[1]);
  EXPECT_NE(result.component[2], result.component[0]);
  EXPECT_NE(result.component[3], result.component[2]);
  EXPECT_LT(
      (result.cam_from_world[3].translation - truth[3].translation).norm(),
      1e-9);
}

TEST(PoseGraph, RejectsBadInput) {
  const std::vector<Rigid3d> poses = RingOfCameras(3);
  std::vector<PoseGraphEdge> edges(1);
  edges[0].view1 = 0;
  edges[0].view2 = 3;
  EXPECT_THROW(OptimizePoseGraph(poses, edges, PoseGraphOptions()), Error);
  edges[0].view2 = 1;
  edges[0].information.setZero();
  EXPECT_THROW(OptimizePoseGraph(poses, edges, PoseGraphOptions()), Error);
  PoseGraphOptions options;
  options.edge_sigma_t_m = 0.0;
  EXPECT_FALSE(options.Check());
}

}  // namespace
}  // namespace colmap_lidar
