#include "src/lines/line_extractor.h"

#include <gtest/gtest.h>

#include "src/lines/debug_overlay.h"
#include "src/lines/synthetic_view.h"

namespace colmap_lidar {
namespace {

TEST(LineExtractor, SyntheticViewEndToEnd) {
  SyntheticViewOptions view_options;
  view_options.boxes = DefaultSyntheticBoxes();
  view_options.paint_stripe = true;
  const SyntheticView view = MakeSyntheticView(view_options);
  const LineExtractionOptions options;
  ASSERT_TRUE(options.Check());
  const ViewLines lines = ExtractViewLines(view.image, view.scan, view.camera,
                                           view.cam_from_lidar, options);
  EXPECT_GT(lines.num_lsd_segments, 10);
  EXPECT_GT(lines.num_edge_points, 50);
  ASSERT_GE(lines.segments.size(), 3u);
  // Fusion only ever reduces the count.
  EXPECT_LE(static_cast<int>(lines.segments.size()), lines.num_lifted_segments);
  for (const ViewLineSegment& segment : lines.segments) {
    for (const Eigen::Vector3d& endpoint :
         {segment.start3D_in_cam, segment.end3D_in_cam}) {
      double best = 1e9;
      for (const auto& edge : view.edges_in_cam) {
        best = std::min(best,
                        DistanceToSegment3D(edge.first, edge.second, endpoint));
      }
      // Endpoints come from the LSD endpoints, which may overshoot a
      // corner by a pixel or two (~2 cm at 8 m): the 5 cm of the benchmark.
      EXPECT_LT(best, 0.05);
    }
    EXPECT_NE(segment.descriptor, LbdDescriptor{});
  }
  // One outcome per LSD segment; the lifted ones are those counted before
  // fusion, each with its 3D endpoints on the rays of its clipped 2D ends.
  ASSERT_EQ(static_cast<int>(lines.outcomes.size()), lines.num_lsd_segments);
  int num_lifted = 0;
  for (const SegmentOutcome& outcome : lines.outcomes) {
    // The plane lifting (on by default) tries what the edge points left.
    EXPECT_EQ(outcome.plane_result == PlaneLiftResult::kNotTried,
              outcome.edge_result == LiftResult::kLifted);
    if (!outcome.Lifted()) continue;
    ++num_lifted;
    EXPECT_LT((view.camera.ImgFromCam(outcome.start3D_in_cam) -
               outcome.lifted2D.start)
                  .norm(),
              1e-3);
  }
  EXPECT_EQ(num_lifted, lines.num_lifted_segments);
  // Longest first.
  for (size_t i = 1; i < lines.segments.size(); ++i) {
    EXPECT_GE(lines.segments[i - 1].segment2D.Length(),
              lines.segments[i].segment2D.Length());
  }

  // The overlay paints the inlier edge points in colour.
  const cv::Mat overlay = DrawLineOverlay(view.image, lines, view.camera);
  ASSERT_EQ(overlay.type(), CV_8UC3);
  const Eigen::Vector2d pixel =
      view.camera.ImgFromCam(lines.segments[0].start3D_in_cam);
  const cv::Vec3b color = overlay.at<cv::Vec3b>(
      static_cast<int>(pixel.y() - 0.5), static_cast<int>(pixel.x() - 0.5));
  EXPECT_GT(std::max({color[0], color[1], color[2]}) -
                std::min({color[0], color[1], color[2]}),
            100)
      << "no saturated colour at the first segment's endpoint";
}

TEST(LineExtractor, ImageSizeMustMatchTheCamera) {
  SyntheticViewOptions view_options;
  view_options.width = 320;
  view_options.height = 240;
  view_options.focal_length = 200;
  view_options.num_columns = 256;
  const SyntheticView view = MakeSyntheticView(view_options);
  const cv::Mat wrong(100, 100, CV_8UC1, cv::Scalar(0));
  EXPECT_THROW(ExtractViewLines(wrong, view.scan, view.camera,
                                view.cam_from_lidar, LineExtractionOptions()),
               Error);
  // No boxes: nothing to lift, an empty result, not an error.
  const ViewLines lines =
      ExtractViewLines(view.image, view.scan, view.camera, view.cam_from_lidar,
                       LineExtractionOptions());
  EXPECT_TRUE(lines.segments.empty());
}

TEST(LineExtractor, OptionsCheckNamesTheOption) {
  LineExtractionOptions options;
  options.association.ransac.min_inliers = 1;
  EXPECT_FALSE(options.Check());
  options = LineExtractionOptions();
  options.num_threads = 0;
  EXPECT_FALSE(options.Check());
}

}  // namespace
}  // namespace colmap_lidar
