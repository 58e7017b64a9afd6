#include "src/lines/segment_fusion.h"

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

const Camera kCamera =
    Camera::FromModelName("PINHOLE", 848, 480, {420, 420, 424, 240});

// A view segment between two 3D points (camera frame) with its projection,
// supported by points sampled on it (appended to *points).
ViewLineSegment MakeSegment(const Eigen::Vector3d& start,
                            const Eigen::Vector3d& end,
                            std::vector<Eigen::Vector3d>* points) {
  ViewLineSegment segment;
  segment.start3D_in_cam = start;
  segment.end3D_in_cam = end;
  segment.segment2D.start = kCamera.ImgFromCam(start);
  segment.segment2D.end = kCamera.ImgFromCam(end);
  for (int i = 0; i <= 10; ++i) {
    segment.inlier_point_idxs.push_back(static_cast<int>(points->size()));
    segment.inlier_points_in_cam.push_back(start + (end - start) * (i / 10.0));
    points->push_back(start + (end - start) * (i / 10.0));
  }
  return segment;
}

TEST(SegmentFusion, SplitCollinearSegmentsMerge) {
  std::vector<Eigen::Vector3d> points;
  // A vertical edge at x = 1, z = 8 from y = -1 to 1, split in three pieces
  // with small gaps (as LSD splits a line), plus an unrelated segment.
  std::vector<ViewLineSegment> segments = {
      MakeSegment({1, -1.0, 8}, {1, -0.4, 8}, &points),
      MakeSegment({1, -0.3, 8}, {1, 0.3, 8}, &points),
      MakeSegment({1, 0.35, 8}, {1, 1.0, 8}, &points),
      MakeSegment({-2, 0, 6}, {-1, 0, 6}, &points),
  };
  const std::vector<ViewLineSegment> fused =
      FuseSegments(segments, points, kCamera, {}, 5.0);
  ASSERT_EQ(fused.size(), 2u);
  const ViewLineSegment& edge = fused[0];
  EXPECT_EQ(edge.NumInliers(), 33);
  const double top = std::min(edge.start3D_in_cam.y(), edge.end3D_in_cam.y());
  const double bottom =
      std::max(edge.start3D_in_cam.y(), edge.end3D_in_cam.y());
  EXPECT_NEAR(top, -1.0, 1e-6);
  EXPECT_NEAR(bottom, 1.0, 1e-6);
  EXPECT_NEAR(edge.start3D_in_cam.x(), 1.0, 1e-6);
  EXPECT_NEAR(edge.end3D_in_cam.z(), 8.0, 1e-6);
  EXPECT_NEAR(edge.segment2D.Length(),
              (kCamera.ImgFromCam({1, 1, 8}) - kCamera.ImgFromCam({1, -1, 8}))
                  .norm(),
              1e-6);
}

TEST(SegmentFusion, ParallelOrDistantSegmentsStaySeparate) {
  std::vector<Eigen::Vector3d> points;
  const ViewLineSegment a = MakeSegment({1, -1, 8}, {1, 0, 8}, &points);
  // Parallel, 10 cm beside.
  const ViewLineSegment b = MakeSegment({1.1, -0.5, 8}, {1.1, 0.5, 8}, &points);
  // Collinear but 1 m further along.
  const ViewLineSegment c = MakeSegment({1, 1.0, 8}, {1, 2.0, 8}, &points);
  // Overlapping, 10 degrees off.
  const ViewLineSegment d =
      MakeSegment({1, -1, 8}, {1 + std::tan(0.17), 0, 8}, &points);
  SegmentFusionOptions options;
  EXPECT_FALSE(AreFusable(a, b, options));
  EXPECT_FALSE(AreFusable(a, c, options));
  EXPECT_FALSE(AreFusable(a, d, options));
  options.max_gap = 1.5;
  EXPECT_TRUE(AreFusable(a, c, options));
  EXPECT_EQ(FuseSegments({a, b, d}, points, kCamera, {}, 5.0).size(), 3u);
}

}  // namespace
}  // namespace colmap_lidar
