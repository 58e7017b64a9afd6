#include "src/sfm/lidar_pose_graph.h"

#include <cmath>
#include <memory>
#include <random>

#include <ceres/gradient_checker.h>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"
#include "src/lidar/lidar_test_scene.h"

namespace colmap_lidar {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The rigs' camera: z forward, LIDAR x forward, 10 cm apart.
Rigid3d CamFromLidar() {
  Eigen::Matrix3x4d matrix;
  matrix << 0, -1, 0, 0, 0, 0, -1, -0.1, 1, 0, 0, -0.04;
  return Rigid3d::FromMatrix(matrix);
}

// A courtyard (ground, four walls of different heights, a ramp and two
// blocks), sampled afresh per scan.
std::vector<Eigen::Vector3d> SampleCourtyard(unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Eigen::Vector3d> points;
  const double d = 12.0;
  SampleRectangle({-20, -15, 0}, {40, 0, 0}, {0, 30, 0}, d, &rng, &points);
  SampleRectangle({-20, -15, 0}, {40, 0, 0}, {0, 0, 8}, d, &rng, &points);
  SampleRectangle({-20, 15, 0}, {40, 0, 0}, {0, 0, 5}, d, &rng, &points);
  SampleRectangle({-20, -15, 0}, {0, 30, 0}, {0, 0, 6}, d, &rng, &points);
  SampleRectangle({20, -15, 0}, {0, 30, 0}, {0, 0, 9}, d, &rng, &points);
  SampleRectangle({-6, 4, 0}, {8, 0, 0}, {0, 3, 2}, d, &rng, &points);
  SampleRectangle({5, -8, 0}, {3, 0, 0}, {0, 0, 3}, d, &rng, &points);
  SampleRectangle({5, -8, 0}, {0, 2, 0}, {0, 0, 3}, d, &rng, &points);
  SampleRectangle({-12, -6, 0}, {0, 4, 0}, {0, 0, 2}, d, &rng, &points);
  return points;
}

struct Sequence {
  std::vector<Rigid3d> world_from_cam_gt;
  std::vector<LidarScan> scans;
  std::vector<LidarPoseGraphFrame> frames;
};

// A walk of `n` frames (1 m steps, turning) with priors of 0.5 m / 5 deg
// noise, as the synthesizer draws them.
std::unique_ptr<Sequence> MakeSequence(int n, unsigned seed) {
  auto sequence = std::make_unique<Sequence>();
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Rigid3d cam_from_lidar = CamFromLidar();
  sequence->scans.resize(n);
  for (int k = 0; k < n; ++k) {
    const double yaw = 8.0 * k;
    const Rigid3d world_from_lidar =
        PoseFromYawRoll(yaw, 0.0, {-8.0 + 1.0 * k, -4.0 + 0.15 * k, 1.5});
    const Rigid3d world_from_cam = world_from_lidar * cam_from_lidar.Inverse();
    sequence->world_from_cam_gt.push_back(world_from_cam);
    std::normal_distribution<double> range_noise(0.0, 0.015);
    for (const Eigen::Vector3d& point : SampleCourtyard(seed * 100 + k)) {
      const Eigen::Vector3d p = world_from_lidar.Inverse() * point;
      if (p.norm() < 40) {
        sequence->scans[k].points.push_back(
            (p + range_noise(rng) * p.normalized()).cast<float>());
      }
    }
    const Eigen::Vector3d axis =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const double angle = 5.0 * kPi / 180 * normal(rng);
    Rigid3d prior;
    prior.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis)) *
                     world_from_cam.rotation;
    prior.translation = world_from_cam.translation +
                        0.5 * Eigen::Vector3d(normal(rng), normal(rng),
                                              normal(rng));
    LidarPoseGraphFrame frame;
    frame.name = "frame " + std::to_string(k);
    frame.prior_world_from_cam = prior;
    frame.cam_from_lidar = cam_from_lidar;
    sequence->frames.push_back(frame);
  }
  for (int k = 0; k < n; ++k) {
    sequence->frames[k].scan = &sequence->scans[k];
  }
  return sequence;
}

void ExpectGradientsMatch(const ceres::CostFunction& cost_function,
                          const std::vector<const ceres::Manifold*>& manifolds,
                          std::vector<double*> parameters) {
  ceres::GradientChecker checker(&cost_function, &manifolds,
                                 ceres::NumericDiffOptions());
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(parameters.data(), 1e-5, &results))
      << results.error_log;
  EXPECT_TRUE(results.return_value);
}

TEST(WorldPosePriorCostFunctor, ResidualAndGradients) {
  Rigid3d prior = PoseFromYawRoll(30, 5, {1, 2, 3});
  Rigid3d pose = prior;
  pose.translation += Eigen::Vector3d(0.5, 0, 0);
  const std::unique_ptr<ceres::CostFunction> cost(
      WorldPosePriorCostFunctor::Create(prior, 0.25, 0.1));
  double residuals[6];
  const double* parameters[2] = {pose.rotation.coeffs().data(),
                                 pose.translation.data()};
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  EXPECT_NEAR(residuals[0], 2.0, 1e-12);
  for (int k = 1; k < 6; ++k) EXPECT_NEAR(residuals[k], 0.0, 1e-12);
  pose = PoseFromYawRoll(33, 4, {1.2, 2.1, 2.9});
  const ceres::EigenQuaternionManifold quaternion_manifold;
  ExpectGradientsMatch(*cost, {&quaternion_manifold, nullptr},
                       {pose.rotation.coeffs().data(), pose.translation.data()});
}

TEST(RelativePoseCostFunctor, ZeroWhenConsistentAndGradientsMatch) {
  const Rigid3d cam_from_lidar = CamFromLidar();
  Rigid3d world_from_cam_i = PoseFromYawRoll(20, 3, {1, 0, 0.5});
  Rigid3d world_from_cam_j = PoseFromYawRoll(28, -2, {2.2, 0.4, 0.6});
  const Rigid3d measured = (world_from_cam_i * cam_from_lidar).Inverse() *
                           (world_from_cam_j * cam_from_lidar);
  // Dense (no structural zeros, which the relative gradient check cannot
  // judge) and positive definite.
  Eigen::Matrix<double, 6, 6> mixing;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) {
      mixing(r, c) = std::sin(1.0 + 7 * r + 3 * c);
    }
  }
  const Eigen::Matrix<double, 6, 6> information =
      100.0 * (mixing.transpose() * mixing +
               Eigen::Matrix<double, 6, 6>::Identity());
  const Eigen::Matrix<double, 6, 6> sqrt_information =
      SqrtInformation(information);
  EXPECT_TRUE((sqrt_information.transpose() * sqrt_information)
                  .isApprox(information, 1e-9));
  const std::unique_ptr<ceres::CostFunction> cost(
      RelativePoseCostFunctor::Create(measured, cam_from_lidar, cam_from_lidar,
                                      sqrt_information));
  double residuals[6];
  const double* parameters[4] = {
      world_from_cam_i.rotation.coeffs().data(),
      world_from_cam_i.translation.data(),
      world_from_cam_j.rotation.coeffs().data(),
      world_from_cam_j.translation.data()};
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(residuals[k], 0.0, 1e-9);
  // A 1 cm shift of frame j along the LIDAR's x (the camera's z) gives
  // a translation error of 1 cm in lidar_j, whitened by 10 per metre.
  Rigid3d moved_j = world_from_cam_j;
  moved_j.translation += world_from_cam_j.rotation * Eigen::Vector3d(0, 0, 0.01);
  parameters[2] = moved_j.rotation.coeffs().data();
  parameters[3] = moved_j.translation.data();
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  const Eigen::Matrix<double, 6, 1> error =
      (Eigen::Matrix<double, 6, 1>() << 0, 0, 0, 0.01, 0, 0).finished();
  const Eigen::Matrix<double, 6, 1> expected = sqrt_information * error;
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(residuals[k], expected[k], 1e-9);

  world_from_cam_j = PoseFromYawRoll(25, 1, {2.0, 0.5, 0.7});
  const ceres::EigenQuaternionManifold quaternion_manifold;
  ExpectGradientsMatch(
      *cost, {&quaternion_manifold, nullptr, &quaternion_manifold, nullptr},
      {world_from_cam_i.rotation.coeffs().data(),
       world_from_cam_i.translation.data(),
       world_from_cam_j.rotation.coeffs().data(),
       world_from_cam_j.translation.data()});
}

TEST(LidarPoseGraph, RecoversRelativePosesFromNoisyPriors) {
  const int n = 8;
  const std::unique_ptr<Sequence> sequence = MakeSequence(n, 7);
  LidarPoseGraphOptions options;
  options.num_threads = 2;
  const LidarPoseGraphResult result =
      SolveLidarPoseGraph(sequence->frames, options);
  LOG(INFO) << result.Format() << "\n" << result.FormatEdges();
  ASSERT_EQ(result.world_from_cam.size(), static_cast<size_t>(n));
  EXPECT_EQ(result.num_isolated_frames, 0);
  EXPECT_GE(result.num_used_edges, n - 1);
  EXPECT_GT(result.num_used_loops, 0);
  double max_prior_error_m = 0.0;
  for (int k = 0; k + 1 < n; ++k) {
    const Rigid3d gt = sequence->world_from_cam_gt[k].Inverse() *
                       sequence->world_from_cam_gt[k + 1];
    const Rigid3d solved =
        result.world_from_cam[k].Inverse() * result.world_from_cam[k + 1];
    const Rigid3d prior = sequence->frames[k].prior_world_from_cam.Inverse() *
                          sequence->frames[k + 1].prior_world_from_cam;
    max_prior_error_m = std::max(
        max_prior_error_m, (prior.translation - gt.translation).norm());
    EXPECT_LT((solved.translation - gt.translation).norm(), 0.02) << k;
    EXPECT_LT(RotationErrorDeg(solved, gt), 0.1) << k;
  }
  // The priors' relative poses were far off: the test can fail.
  EXPECT_GT(max_prior_error_m, 0.3);
  // The loops measured the edges' noise (clean synthetic scans: below the
  // floor), and every used edge carries a finite, symmetric, positive
  // semi-definite information.
  EXPECT_TRUE(result.edge_noise.estimated);
  EXPECT_GE(result.edge_noise.num_closures, 5);
  for (const LidarPoseGraphEdge& edge : result.edges) {
    if (!edge.used) continue;
    EXPECT_TRUE(edge.information.allFinite());
    EXPECT_LT((edge.information - edge.information.transpose()).norm(),
              1e-9 * edge.information.norm());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> solver(
        edge.information);
    EXPECT_GE(solver.eigenvalues().minCoeff(),
              -1e-9 * solver.eigenvalues().maxCoeff());
  }
}

// The loop registrations run in parallel: two solves give the same edges,
// bit for bit, in candidate order (frame i ascending), and the same poses.
TEST(LidarPoseGraph, ParallelLoopRegistrationsRepeatInOrder) {
  const int n = 7;
  const std::unique_ptr<Sequence> sequence = MakeSequence(n, 11);
  LidarPoseGraphOptions options;
  options.num_threads = 2;
  const LidarPoseGraphResult first =
      SolveLidarPoseGraph(sequence->frames, options);
  const LidarPoseGraphResult second =
      SolveLidarPoseGraph(sequence->frames, options);
  ASSERT_EQ(first.edges.size(), second.edges.size());
  int num_loops = 0;
  int previous_i = -1;
  for (size_t e = 0; e < first.edges.size(); ++e) {
    const LidarPoseGraphEdge& a = first.edges[e];
    const LidarPoseGraphEdge& b = second.edges[e];
    EXPECT_EQ(a.i, b.i);
    EXPECT_EQ(a.j, b.j);
    EXPECT_EQ(a.used, b.used);
    EXPECT_EQ(a.registration.target_from_source.ToMatrix(),
              b.registration.target_from_source.ToMatrix());
    EXPECT_EQ(a.registration.hessian, b.registration.hessian);
    EXPECT_EQ(a.information, b.information);
    if (a.loop) {
      ++num_loops;
      EXPECT_GE(a.i, previous_i);
      previous_i = a.i;
    }
  }
  EXPECT_GE(num_loops, 4);  // enough loops to run side by side
  for (int k = 0; k < n; ++k) {
    EXPECT_EQ(first.world_from_cam[k].ToMatrix(),
              second.world_from_cam[k].ToMatrix());
  }
}

TEST(LidarPoseGraph, EdgeNoiseOffUsesTheRegistrationInformation) {
  const int n = 6;
  const std::unique_ptr<Sequence> sequence = MakeSequence(n, 7);
  LidarPoseGraphOptions options;
  options.num_threads = 2;
  options.edge_noise.enabled = false;
  const LidarPoseGraphResult result =
      SolveLidarPoseGraph(sequence->frames, options);
  EXPECT_FALSE(result.edge_noise.estimated);
  for (const LidarPoseGraphEdge& edge : result.edges) {
    EXPECT_EQ(edge.information, edge.registration.information);
    // The registration's information is its Hessian capped at the floor.
    EXPECT_TRUE(edge.information.isApprox(
        CapInformation(edge.registration.hessian,
                       FloorSigma(options.registration)),
        1e-12));
  }
}

TEST(LidarPoseGraph, AWrongEdgeIsNotUsedOrDownweighted) {
  // A frame whose scan comes from elsewhere (a swapped file): its edges must
  // fail the fitness / prior checks or be downweighted, and the other
  // frames keep centimetre relative poses.
  const int n = 6;
  const std::unique_ptr<Sequence> sequence = MakeSequence(n, 9);
  LidarScan elsewhere;
  for (const Eigen::Vector3f& p : sequence->scans[0].points) {
    elsewhere.points.push_back(
        (Eigen::AngleAxisf(2.0f, Eigen::Vector3f::UnitZ()) * p) +
        Eigen::Vector3f(3, 0, 0));
  }
  sequence->scans[3] = elsewhere;
  LidarPoseGraphOptions options;
  options.num_threads = 2;
  const LidarPoseGraphResult result =
      SolveLidarPoseGraph(sequence->frames, options);
  LOG(INFO) << result.Format() << "\n" << result.FormatEdges();
  for (const LidarPoseGraphEdge& edge : result.edges) {
    if (edge.i == 3 || edge.j == 3) {
      EXPECT_TRUE(!edge.used || edge.downweighted) << edge.i << "->" << edge.j;
    }
  }
  const Rigid3d gt = sequence->world_from_cam_gt[0].Inverse() *
                     sequence->world_from_cam_gt[1];
  const Rigid3d solved =
      result.world_from_cam[0].Inverse() * result.world_from_cam[1];
  EXPECT_LT((solved.translation - gt.translation).norm(), 0.02);
}

TEST(LidarPoseGraph, RejectsBadInput) {
  LidarPoseGraphOptions options;
  EXPECT_TRUE(options.Check());
  options.min_fitness = 1.5;
  EXPECT_FALSE(options.Check());
  options = LidarPoseGraphOptions();
  std::vector<LidarPoseGraphFrame> frames(2);
  EXPECT_THROW(SolveLidarPoseGraph(frames, options), Error);
  frames.resize(1);
  EXPECT_THROW(SolveLidarPoseGraph(frames, options), Error);
}

}  // namespace
}  // namespace colmap_lidar
