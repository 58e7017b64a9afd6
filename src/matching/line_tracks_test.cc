#include "src/matching/line_tracks.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

TEST(LineTracks, FitPluckerLineOfKnownLine) {
  const Eigen::Vector3d point(1.0, 2.0, 3.0);
  const Eigen::Vector3d direction = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  std::vector<Eigen::Vector3d> points;
  for (const double t : {-2.0, 0.5, 3.0, 1.0}) {
    points.push_back(point + t * direction);
  }
  Eigen::Vector3d start, end;
  const Eigen::Matrix<double, 6, 1> plucker =
      FitPluckerLine(points, &start, &end);
  // Oriented from the first to the last point: +direction.
  EXPECT_NEAR((plucker.head<3>() - direction).norm(), 0.0, 1e-9);
  // The moment of a line through `point`: m = p x d, orthogonal to d.
  EXPECT_NEAR((plucker.tail<3>() - point.cross(direction)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(plucker.head<3>().dot(plucker.tail<3>()), 0.0, 1e-12);
  EXPECT_NEAR((start - (point - 2.0 * direction)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((end - (point + 3.0 * direction)).norm(), 0.0, 1e-9);
  EXPECT_THROW(FitPluckerLine({point}, nullptr, nullptr), Error);
  EXPECT_THROW(FitPluckerLine({point, point}, nullptr, nullptr), Error);
}

TEST(LineTracks, BuildTracksFromClusters) {
  const Camera camera =
      Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
  LineSegmentRecord a;
  a.start3D_in_cam = {0, 0, 5};
  a.end3D_in_cam = {1, 0, 5};
  LineSegmentRecord b;
  b.start3D_in_cam = {0.5, 0, 5};
  b.end3D_in_cam = {2, 0, 5};
  // View 1 at the origin, view 2 shifted by 1 m along x (so its camera-frame
  // x is world x - 1).
  std::vector<MatchingView> views = {
      MakeMatchingView(7, "a", camera, Rigid3d(), {a, b}),
      MakeMatchingView(3, "b", camera,
                       Rigid3d(Eigen::Quaterniond::Identity(), {-1, 0, 0}),
                       {a})};
  const std::vector<TrackObservation> observations = {{0, 0}, {0, 1}, {1, 0}};
  const std::vector<LineTrackRecord> tracks =
      BuildLineTracks(views, observations, {5, 2, 5}, 2);
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_EQ(tracks[0].line3D_id, 1u);
  ASSERT_EQ(tracks[0].elements.size(), 2u);
  // Sorted by image id.
  EXPECT_EQ(tracks[0].elements[0].image_id, 3u);
  EXPECT_EQ(tracks[0].elements[1].image_id, 7u);
  EXPECT_NEAR(tracks[0].start_in_world.x(), 0.0, 1e-9);
  EXPECT_NEAR(tracks[0].end_in_world.x(), 2.0, 1e-9);
  EXPECT_NEAR(std::abs(tracks[0].plucker.x()), 1.0, 1e-9);
  // Singletons are kept with min_track_length... never below 2 here; a
  // cluster with two observations of one view throws.
  EXPECT_THROW(BuildLineTracks(views, observations, {1, 1, 2}, 2), Error);
  EXPECT_EQ(BuildLineTracks(views, observations, {1, -1, 1}, 3).size(), 0u);
}

}  // namespace
}  // namespace colmap_lidar
