#include "src/lines/lsd_detector.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace colmap_lidar {
namespace {

TEST(LsdDetector, FindsTheSidesOfARectangleInColmapPixels) {
  // A bright rectangle covering pixels x in [100, 300), y in [80, 200): its
  // sides lie at x = 100 and x = 300 (COLMAP: pixel x covers [x, x+1)).
  cv::Mat image(300, 400, CV_8UC1, cv::Scalar(40));
  image(cv::Rect(100, 80, 200, 120)).setTo(200);
  LsdOptions options;
  const std::vector<LineSegment2D> segments = DetectLineSegments(image, options);
  ASSERT_GE(segments.size(), 4u);
  // Longest first.
  for (size_t i = 1; i < segments.size(); ++i) {
    EXPECT_GE(segments[i - 1].Length(), segments[i].Length());
  }
  int num_vertical_sides = 0;
  for (const LineSegment2D& segment : segments) {
    const Eigen::Vector2d mid = 0.5 * (segment.start + segment.end);
    if (std::abs(segment.Direction().x()) < 0.05 && segment.Length() > 80) {
      const double side = mid.x() < 200 ? 100.0 : 300.0;
      EXPECT_NEAR(mid.x(), side, 1.0);
      ++num_vertical_sides;
    }
  }
  EXPECT_EQ(num_vertical_sides, 2);
}

TEST(LsdDetector, MinimumLengthAndMaximumCount) {
  cv::Mat image(300, 400, CV_8UC1, cv::Scalar(40));
  image(cv::Rect(100, 80, 200, 120)).setTo(200);
  image(cv::Rect(20, 20, 15, 15)).setTo(200);  // a small square
  LsdOptions options;
  options.min_length_px = 0.0;
  const size_t num_all = DetectLineSegments(image, options).size();
  options.min_length_px = 50.0;
  const std::vector<LineSegment2D> long_segments =
      DetectLineSegments(image, options);
  EXPECT_LT(long_segments.size(), num_all);
  for (const LineSegment2D& segment : long_segments) {
    EXPECT_GE(segment.Length(), 50.0);
  }
  options.max_num_segments = 2;
  EXPECT_EQ(DetectLineSegments(image, options).size(), 2u);
  options.scale = 1.5;
  EXPECT_FALSE(options.Check());
}

}  // namespace
}  // namespace colmap_lidar
