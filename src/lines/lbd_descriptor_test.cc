#include "src/lines/lbd_descriptor.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "src/lines/lsd_detector.h"

namespace colmap_lidar {
namespace {

cv::Mat TexturedImage(int shift_x) {
  cv::Mat image(240, 320, CV_8UC1, cv::Scalar(60));
  cv::rectangle(image, cv::Rect(60 + shift_x, 40, 120, 100), cv::Scalar(200),
                cv::FILLED);
  cv::rectangle(image, cv::Rect(200 + shift_x, 150, 60, 60), cv::Scalar(120),
                cv::FILLED);
  cv::line(image, cv::Point(20 + shift_x, 220), cv::Point(300 + shift_x, 180),
           cv::Scalar(250), 3);
  return image;
}

TEST(LbdDescriptor, SameSegmentMatchesDifferentSegmentsDoNot) {
  const cv::Mat image = TexturedImage(0);
  const cv::Mat shifted = TexturedImage(7);
  const LineSegment2D left{{60.5, 50.0}, {60.5, 130.0}};
  // A ridge (thin bright line), not a step edge like `left`.
  const LineSegment2D ridge{{40.5, 217.6}, {280.5, 183.3}};
  const LineSegment2D small{{200.5, 155.0}, {200.5, 205.0}};
  const std::vector<LbdDescriptor> descriptors =
      ComputeLbdDescriptors(image, {left, ridge, small});
  ASSERT_EQ(descriptors.size(), 3u);
  const LineSegment2D left_shifted{{67.5, 50.0}, {67.5, 130.0}};
  const std::vector<LbdDescriptor> shifted_descriptors =
      ComputeLbdDescriptors(shifted, {left_shifted});
  EXPECT_LT(LbdHammingDistance(descriptors[0], shifted_descriptors[0]), 30);
  EXPECT_GT(LbdHammingDistance(descriptors[0], descriptors[1]), 40);
  EXPECT_GT(LbdHammingDistance(descriptors[0], descriptors[2]), 40);
  EXPECT_EQ(LbdHammingDistance(descriptors[1], descriptors[1]), 0);
  // Not all zero.
  EXPECT_NE(descriptors[0], LbdDescriptor{});
}

TEST(LbdDescriptor, OrderFollowsTheInput) {
  const cv::Mat image = TexturedImage(0);
  const LineSegment2D a{{60.5, 50.0}, {60.5, 130.0}};
  const LineSegment2D b{{70.0, 140.5}, {170.0, 140.5}};
  const std::vector<LbdDescriptor> ab = ComputeLbdDescriptors(image, {a, b});
  const std::vector<LbdDescriptor> ba = ComputeLbdDescriptors(image, {b, a});
  EXPECT_EQ(ab[0], ba[1]);
  EXPECT_EQ(ab[1], ba[0]);
  EXPECT_TRUE(ComputeLbdDescriptors(image, {}).empty());
}

}  // namespace
}  // namespace colmap_lidar
