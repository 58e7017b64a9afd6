#include "src/optim/line_manifold.h"

#include <random>

#include <ceres/manifold_test_utils.h>
#include <gtest/gtest.h>

#include "src/optim/line_geometry.h"

namespace colmap_lidar {
namespace {

Eigen::VectorXd RandomOrthonormalLine(std::mt19937* rng) {
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  Eigen::VectorXd x(6);
  x.head<4>() = Eigen::Quaterniond::UnitRandom().coeffs();
  const double phi = angle(*rng);
  x.tail<2>() << std::cos(phi), std::sin(phi);
  return x;
}

Eigen::VectorXd RandomTangent(std::mt19937* rng, double scale) {
  std::uniform_real_distribution<double> uniform(-scale, scale);
  Eigen::VectorXd delta(4);
  for (int i = 0; i < 4; ++i) delta[i] = uniform(*rng);
  return delta;
}

TEST(OrthonormalLineManifold, InvariantsHold) {
  // Ceres' invariant macro names its matchers and ceres::Vector unqualified.
  using namespace ceres;  // NOLINT(build/namespaces)
  std::srand(4);  // Eigen's UnitRandom uses std::rand.
  std::mt19937 rng(4);
  const OrthonormalLineManifold manifold;
  EXPECT_EQ(manifold.AmbientSize(), 6);
  EXPECT_EQ(manifold.TangentSize(), 4);
  constexpr double kTolerance = 1e-9;
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd x = RandomOrthonormalLine(&rng);
    const Eigen::VectorXd delta = RandomTangent(&rng, 0.5);
    // y near x so that Minus stays in the injectivity region.
    Eigen::VectorXd y(6);
    const Eigen::VectorXd small = RandomTangent(&rng, 0.8);
    ASSERT_TRUE(manifold.Plus(x.data(), small.data(), y.data()));
    EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, kTolerance);
  }
}

TEST(OrthonormalLineManifold, PlusStaysOnTheManifold) {
  std::mt19937 rng(5);
  const OrthonormalLineManifold manifold;
  Eigen::VectorXd x = RandomOrthonormalLine(&rng);
  for (int step = 0; step < 1000; ++step) {
    const Eigen::VectorXd delta = RandomTangent(&rng, 1.0);
    Eigen::VectorXd next(6);
    ASSERT_TRUE(manifold.Plus(x.data(), delta.data(), next.data()));
    x = next;
  }
  EXPECT_NEAR(x.head<4>().norm(), 1.0, 1e-12);
  EXPECT_NEAR(x.tail<2>().norm(), 1.0, 1e-12);
  Eigen::Vector3d d, m;
  OrthonormalToPluckerUnnormalized(x.data(), d.data(), m.data());
  EXPECT_NEAR(d.dot(m), 0.0, 1e-12);
}

TEST(OrthonormalLineManifold, TangentDirectionsMoveTheLineIndependently) {
  // The 4 tangent directions must change the Pluecker line in 4 independent
  // ways (rank 4 of d(normalised Pluecker)/d(delta)); a degenerate
  // parameterisation (e.g. a rotation about the line itself) would not.
  std::mt19937 rng(6);
  const OrthonormalLineManifold manifold;
  for (int trial = 0; trial < 10; ++trial) {
    Eigen::VectorXd x = RandomOrthonormalLine(&rng);
    if (std::abs(x[5]) < 0.1) continue;
    const Vector6d base = OrthonormalToPlucker(x);
    Eigen::Matrix<double, 6, 4> jacobian;
    constexpr double kStep = 1e-6;
    for (int k = 0; k < 4; ++k) {
      Eigen::VectorXd delta = Eigen::VectorXd::Zero(4);
      delta[k] = kStep;
      Eigen::VectorXd moved(6);
      manifold.Plus(x.data(), delta.data(), moved.data());
      jacobian.col(k) = (OrthonormalToPlucker(moved) - base) / kStep;
    }
    Eigen::JacobiSVD<Eigen::Matrix<double, 6, 4>> svd(jacobian);
    EXPECT_GT(svd.singularValues()[3], 1e-3) << svd.singularValues().transpose();
  }
}

TEST(OrthonormalLineManifold, BrokenJacobianIsDetected) {
  // The invariant matcher used above must be able to fail: a manifold with
  // a wrong PlusJacobian sign does not pass it.
  class BrokenManifold : public OrthonormalLineManifold {
   public:
    bool PlusJacobian(const double* x, double* jacobian) const override {
      OrthonormalLineManifold::PlusJacobian(x, jacobian);
      for (int i = 0; i < 24; ++i) jacobian[i] = -jacobian[i];
      return true;
    }
  };
  std::mt19937 rng(7);
  const BrokenManifold manifold;
  const Eigen::VectorXd x = RandomOrthonormalLine(&rng);
  EXPECT_THAT(manifold, ::testing::Not(ceres::HasCorrectPlusJacobianAt(x, 1e-9)));
}

}  // namespace
}  // namespace colmap_lidar
