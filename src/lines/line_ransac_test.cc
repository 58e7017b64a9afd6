#include "src/lines/line_ransac.h"

#include <gtest/gtest.h>

#include <random>

namespace colmap_lidar {
namespace {

TEST(LineRansac, RecoversTheLineAmongOutliers) {
  std::mt19937 generator(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  const Eigen::Vector3d point(1.0, -0.5, 8.0);
  const Eigen::Vector3d direction = Eigen::Vector3d(0.3, 1.0, 0.2).normalized();
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 30; ++i) {
    points.push_back(point + (i * 0.1 - 1.5) * direction +
                     Eigen::Vector3d(noise(generator), noise(generator),
                                     noise(generator)));
  }
  for (int i = 0; i < 20; ++i) {
    points.push_back(point + Eigen::Vector3d(uniform(generator),
                                             uniform(generator),
                                             uniform(generator)));
  }
  LineRansacOptions options;
  const LineRansacResult result = FitLineRansac(points, options);
  ASSERT_TRUE(result.success);
  EXPECT_GT(std::abs(result.line.direction.dot(direction)),
            std::cos(1.0 * M_PI / 180.0));
  EXPECT_LT(DistanceToLine(result.line, point), 0.01);
  int num_true_inliers = 0;
  for (const int idx : result.inliers) {
    num_true_inliers += idx < 30 ? 1 : 0;
  }
  EXPECT_GE(num_true_inliers, 28);
  EXPECT_LE(static_cast<int>(result.inliers.size()) - num_true_inliers, 2);
}

TEST(LineRansac, TooFewPointsOrNoLineFails) {
  LineRansacOptions options;
  options.min_inliers = 5;
  std::vector<Eigen::Vector3d> points = {Eigen::Vector3d(0, 0, 5),
                                         Eigen::Vector3d(1, 0, 5)};
  EXPECT_FALSE(FitLineRansac(points, options).success);
  // Points on a circle: no five of them are collinear within 5 cm.
  points.clear();
  for (int i = 0; i < 12; ++i) {
    points.emplace_back(std::cos(i * M_PI / 6), std::sin(i * M_PI / 6), 5.0);
  }
  EXPECT_FALSE(FitLineRansac(points, options).success);
}

TEST(LineRansac, Deterministic) {
  std::mt19937 generator(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 100; ++i) {
    points.emplace_back(i * 0.05, 0.0, 5.0);
    points.emplace_back(uniform(generator), uniform(generator),
                        5 + uniform(generator));
  }
  const LineRansacResult a = FitLineRansac(points, {});
  const LineRansacResult b = FitLineRansac(points, {});
  EXPECT_EQ(a.inliers, b.inliers);
  EXPECT_EQ(a.line.point, b.line.point);
}

}  // namespace
}  // namespace colmap_lidar
