#include "src/eval/eval_stats.h"

#include <cmath>

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

TEST(EvalStats, ErrorStats) {
  const ErrorStats stats = ComputeErrorStats({3, 1, 4, 1, 5, 9});
  EXPECT_EQ(stats.count, 6u);
  EXPECT_DOUBLE_EQ(stats.mean, 23.0 / 6.0);
  EXPECT_DOUBLE_EQ(stats.median, 3.5);
  EXPECT_DOUBLE_EQ(stats.rmse, std::sqrt(133.0 / 6.0));
  EXPECT_DOUBLE_EQ(stats.max, 9.0);
  EXPECT_DOUBLE_EQ(ComputeErrorStats({2, 7, 1}).median, 2.0);
  EXPECT_EQ(ComputeErrorStats({}).count, 0u);
  EXPECT_DOUBLE_EQ(ComputeErrorStats({}).mean, 0.0);
}

TEST(EvalStats, ShareBelowIsStrictAndWeighted) {
  EXPECT_DOUBLE_EQ(ShareBelow({0.1, 0.2, 0.3, 0.4}, 0.3), 0.5);
  EXPECT_DOUBLE_EQ(ShareBelow({0.1, 0.5}, 0.3, {3.0, 1.0}), 0.75);
  EXPECT_DOUBLE_EQ(ShareBelow({0.1, 0.5}, 0.3, {}, 4.0), 0.25);
  EXPECT_DOUBLE_EQ(ShareBelow({}, 0.3), 0.0);
  EXPECT_DOUBLE_EQ(FScore(0.5, 1.0), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(FScore(0.0, 0.0), 0.0);
}

TEST(EvalStats, CheckThresholds) {
  EXPECT_TRUE(CheckThresholds({0.1, 0.2}, "x"));
  EXPECT_FALSE(CheckThresholds({}, "x"));
  EXPECT_FALSE(CheckThresholds({0.2, 0.1}, "x"));
  EXPECT_FALSE(CheckThresholds({0.1, 0.1}, "x"));
  EXPECT_FALSE(CheckThresholds({0.0, 0.1}, "x"));
  EXPECT_FALSE(CheckThresholds({NAN}, "x"));
  EXPECT_FALSE(CheckThresholds({INFINITY}, "x"));
}

}  // namespace
}  // namespace colmap_lidar
