#include "src/matching/linear_assignment.h"

#include <algorithm>
#include <numeric>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Exhaustive minimum over injective row -> column maps.
double BruteForceMinimum(const Eigen::MatrixXd& cost) {
  std::vector<int> columns(cost.cols());
  std::iota(columns.begin(), columns.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {
    double total = 0.0;
    for (int r = 0; r < cost.rows(); ++r) total += cost(r, columns[r]);
    best = std::min(best, total);
  } while (std::next_permutation(columns.begin(), columns.end()));
  return best;
}

TEST(LinearAssignment, MatchesBruteForceOnRandomMatrices) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int cols = 1 + trial % 6;
    const int rows = 1 + (trial / 6) % cols;
    Eigen::MatrixXd cost(rows, cols);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) cost(r, c) = uniform(rng);
    const std::vector<int> assignment = SolveLinearAssignment(cost);
    ASSERT_EQ(assignment.size(), static_cast<size_t>(rows));
    std::set<int> used(assignment.begin(), assignment.end());
    EXPECT_EQ(used.size(), static_cast<size_t>(rows));
    double total = 0.0;
    for (int r = 0; r < rows; ++r) {
      ASSERT_GE(assignment[r], 0);
      ASSERT_LT(assignment[r], cols);
      total += cost(r, assignment[r]);
    }
    EXPECT_NEAR(total, BruteForceMinimum(cost), 1e-12) << "trial " << trial;
  }
}

TEST(LinearAssignment, PrefersTheGlobalOptimumOverGreedy) {
  // Greedy on row 0 takes column 0 (cost 0) and forces row 1 to pay 10.
  Eigen::MatrixXd cost(2, 2);
  cost << 0.0, 1.0, 1.0, 10.0;
  EXPECT_EQ(SolveLinearAssignment(cost), (std::vector<int>{1, 0}));
}

TEST(LinearAssignment, RefusesMoreRowsThanColumns) {
  EXPECT_THROW(SolveLinearAssignment(Eigen::MatrixXd::Zero(3, 2)), Error);
}

}  // namespace
}  // namespace colmap_lidar
