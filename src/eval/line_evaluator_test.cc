#include "src/eval/line_evaluator.h"

#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"
#include "src/eval/nearest_neighbor.h"

namespace colmap_lidar {
namespace {

Segment3D Segment(const Eigen::Vector3d& start, const Eigen::Vector3d& end) {
  Segment3D segment;
  segment.start = start;
  segment.end = end;
  return segment;
}

std::vector<Segment3D> Edges() {
  return {Segment({0, 0, 0}, {1, 0, 0}), Segment({0, 0, 0}, {0, 0, 2.5}),
          Segment({3, 1, 0}, {3, 1, 1})};
}

TEST(LineEvaluator, IdenticalSegmentsArePerfect) {
  const LineEvaluation evaluation =
      EvaluateLines(Edges(), Edges(), LineEvaluationOptions());
  EXPECT_EQ(evaluation.num_estimated_segments, 3u);
  EXPECT_NEAR(evaluation.estimated_length_m, 4.5, 1e-12);
  EXPECT_NEAR(evaluation.ground_truth_length_m, 4.5, 1e-12);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(evaluation.length_precisions[k], 1.0, 1e-12);
    EXPECT_NEAR(evaluation.length_recalls[k], 1.0, 1e-12);
    EXPECT_EQ(evaluation.num_inlier_segments[k], 3u);
    EXPECT_DOUBLE_EQ(evaluation.inlier_segment_shares[k], 1.0);
  }
}

// GT: 1 m along x. Estimate: its first half, shifted by 0.03 m in y. Every
// estimate point is 0.03 from the GT; a GT point at x > 0.5 is
// sqrt((x-0.5)^2 + 0.03^2) from the estimate, < 0.05 for x < 0.54. So
// precision is 0 at 0.02 and 1 at 0.05; recall 0 at 0.02 and 0.54 at 0.05
// (the half plus 4 cm past the end), 0.5 + sqrt(0.1^2 - 0.03^2) at 0.1.
TEST(LineEvaluator, HalfCoveredShiftedEdge) {
  const std::vector<Segment3D> gt = {Segment({0, 0, 0}, {1, 0, 0})};
  const std::vector<Segment3D> estimate = {
      Segment({0, 0.03, 0}, {0.5, 0.03, 0})};
  LineEvaluationOptions options;
  options.thresholds_m = {0.02, 0.05, 0.1};
  options.sample_step_m = 0.001;
  const LineEvaluation evaluation = EvaluateLines(estimate, gt, options);
  EXPECT_NEAR(evaluation.estimated_length_m, 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(evaluation.length_precisions[0], 0.0);
  EXPECT_NEAR(evaluation.length_precisions[1], 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(evaluation.length_recalls[0], 0.0);
  EXPECT_NEAR(evaluation.length_recalls[1], 0.54, 1e-3);
  EXPECT_NEAR(evaluation.length_recalls[2], 0.5 + std::sqrt(0.01 - 0.0009),
              1e-3);
  EXPECT_EQ(evaluation.num_inlier_segments[0], 0u);
  EXPECT_EQ(evaluation.num_inlier_segments[1], 1u);

  // A second estimate, 1 m long, tilted away from the GT: only partly
  // within, so it is never an inlier segment at 0.05.
  std::vector<Segment3D> two = estimate;
  two.push_back(Segment({0, 0, 0}, {0, 1, 0}));
  const LineEvaluation tilted = EvaluateLines(two, gt, options);
  EXPECT_EQ(tilted.num_inlier_segments[1], 1u);
  EXPECT_DOUBLE_EQ(tilted.inlier_segment_shares[1], 0.5);
  // Of its length, [0, 0.05) is within 0.05 of the GT: (0.5 + 0.05) / 1.5.
  EXPECT_NEAR(tilted.length_precisions[1], 0.55 / 1.5, 2e-3);
}

TEST(LineEvaluator, GridIndexMatchesBruteForce) {
  std::mt19937 generator(3);
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
  std::vector<Segment3D> segments;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d start(coordinate(generator), coordinate(generator),
                                coordinate(generator));
    const Eigen::Vector3d direction(coordinate(generator),
                                    coordinate(generator),
                                    coordinate(generator));
    segments.push_back(Segment(start, start + 0.5 * direction));
  }
  const double max_distance = 0.1;
  const SegmentDistanceIndex index(segments, max_distance);
  int num_within = 0;
  for (int q = 0; q < 20000; ++q) {
    const Eigen::Vector3d point(coordinate(generator), coordinate(generator),
                                coordinate(generator));
    double brute = std::numeric_limits<double>::infinity();
    for (const Segment3D& s : segments) {
      brute = std::min(brute, PointSegmentDistance(point, s.start, s.end));
    }
    const double distance = index.Distance(point);
    if (brute <= max_distance) {
      ++num_within;
      EXPECT_DOUBLE_EQ(distance, brute) << q;
    } else {
      EXPECT_TRUE(std::isinf(distance)) << q;
    }
  }
  EXPECT_GT(num_within, 500);
}

TEST(LineEvaluator, EmptyInputsAndOptions) {
  const LineEvaluation empty =
      EvaluateLines({}, Edges(), LineEvaluationOptions());
  EXPECT_DOUBLE_EQ(empty.length_precisions[0], 0.0);
  EXPECT_DOUBLE_EQ(empty.length_recalls[0], 0.0);
  EXPECT_THROW(EvaluateLines(Edges(), {}, LineEvaluationOptions()), Error);
  LineEvaluationOptions options;
  options.sample_step_m = 0.0;
  EXPECT_FALSE(options.Check());
  options = LineEvaluationOptions();
  options.thresholds_m = {0.1, 0.1};
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(EvaluateLines(Edges(), Edges(), options), Error);
}

TEST(LineEvaluator, JsonAndTable) {
  const LineEvaluation evaluation =
      EvaluateLines(Edges(), Edges(), LineEvaluationOptions());
  const std::string path = JoinPaths(testing::CreateTestDir(), "lines.json");
  WriteLineEvaluationJson(path, evaluation);
  const Json json = ReadJsonFile(path);
  EXPECT_EQ(json.at("evaluator"), "line");
  EXPECT_EQ(json.at("length_recall"), Json({1.0, 1.0, 1.0, 1.0}));
  EXPECT_EQ(json.at("thresholds_m"), Json({0.01, 0.02, 0.05, 0.1}));
  EXPECT_EQ(json.at("num_estimated_segments"), 3);
  EXPECT_EQ(json.at("estimated_length_m").get<double>(),
            evaluation.estimated_length_m);
  EXPECT_EQ(json.at("num_inlier_segments"),
            Json(evaluation.num_inlier_segments));
  EXPECT_TRUE(json.at("num_inlier_segments").at(0).is_number_unsigned());
  EXPECT_EQ(json.at("inlier_segment_share"),
            Json(evaluation.inlier_segment_shares));
  const std::string table = FormatLineEvaluation(evaluation);
  EXPECT_NE(table.find("3 estimated segments (4.5000 m)"), std::string::npos)
      << table;
}

}  // namespace
}  // namespace colmap_lidar
