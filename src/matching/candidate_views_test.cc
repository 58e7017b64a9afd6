#include "src/matching/candidate_views.h"

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

MatchingView MakeView() {
  return MakeMatchingView(
      1, "a.png",
      Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240}),
      Rigid3d(), {LineSegmentRecord()});
}

TEST(CandidateViews, FieldOfViewAndDepth) {
  const MatchingView view = MakeView();
  const LineMatchingOptions options;
  // In front, inside.
  SegmentInView in = ProjectSegmentIntoView({-1, 0, 5}, {1, 0, 5}, view, options);
  EXPECT_TRUE(in.visible);
  EXPECT_NEAR(in.depth, 5.0, 1e-12);
  EXPECT_NEAR(in.start2D.x(), 220.0, 1e-9);
  EXPECT_NEAR(in.end2D.x(), 420.0, 1e-9);
  // Behind the camera.
  EXPECT_FALSE(
      ProjectSegmentIntoView({-1, 0, -5}, {1, 0, -5}, view, options).visible);
  // Beside the image.
  EXPECT_FALSE(
      ProjectSegmentIntoView({10, 0, 5}, {12, 0, 5}, view, options).visible);
  // Mostly outside: 2 of 9 samples inside is below 0.3.
  in = ProjectSegmentIntoView({2.5, 0, 5}, {10.5, 0, 5}, view, options);
  EXPECT_FALSE(in.visible);
  EXPECT_GT(in.visible_fraction, 0.0);
  // Crossing the camera plane: clipped at min_depth, still visible.
  in = ProjectSegmentIntoView({0.1, 0.1, -3}, {0.1, 0.1, 20}, view, options);
  EXPECT_TRUE(in.visible);
  EXPECT_TRUE(in.start2D.allFinite());
}

TEST(CandidateViews, LidarDepthHidesSegmentsBehindASurface) {
  MatchingView view = MakeView();
  LineMatchingOptions options;
  // A LIDAR wall at depth 4 over the whole image.
  std::vector<Eigen::Vector3d> wall;
  for (double x = -3.0; x <= 3.0; x += 0.01) {
    for (double y = -2.0; y <= 2.0; y += 0.05) wall.emplace_back(x, y, 4.0);
  }
  view.lidar_depth = LidarDepthGrid(wall, view.camera, 8, 0.2);
  // On the wall: visible; 2 m behind it: hidden; in front: visible.
  EXPECT_TRUE(ProjectSegmentIntoView({-1, 0, 4.02}, {1, 0, 4.02}, view,
                                     options).visible);
  EXPECT_FALSE(
      ProjectSegmentIntoView({-1, 0, 6}, {1, 0, 6}, view, options).visible);
  EXPECT_TRUE(
      ProjectSegmentIntoView({-1, 0, 3}, {1, 0, 3}, view, options).visible);
  // With a pose uncertainty of 0.5 m / 5 deg, 1 m behind is tolerated.
  EXPECT_FALSE(ProjectSegmentIntoView({-1, 0, 5}, {1, 0, 5}, view, options)
                   .visible);
  options.pose_sigma_t_m = 0.5;
  options.pose_sigma_r_deg = 5.0;
  EXPECT_TRUE(
      ProjectSegmentIntoView({-1, 0, 5}, {1, 0, 5}, view, options).visible);
}

TEST(CandidateViews, ThresholdsGrowWithThePoseUncertainty) {
  LineMatchingOptions options;
  const MatchingThresholds exact = EffectiveThresholds(options, 10.0, 400.0);
  EXPECT_EQ(exact.theta_deg, options.t_theta_deg);
  EXPECT_EQ(exact.dP_px, options.t_dP_px);
  EXPECT_EQ(exact.dO_m, options.t_dO_m);
  options.pose_sigma_t_m = 0.5;
  options.pose_sigma_r_deg = 5.0;
  options.pose_uncertainty_scale = 1.0;
  const MatchingThresholds noisy = EffectiveThresholds(options, 10.0, 400.0);
  const double k = std::sqrt(2.0);
  const double sigma_r = 5.0 * M_PI / 180.0;
  EXPECT_NEAR(noisy.theta_deg, options.t_theta_deg + k * 5.0, 1e-12);
  EXPECT_NEAR(noisy.dO_m, options.t_dO_m + k * (0.5 + 10.0 * sigma_r), 1e-12);
  EXPECT_NEAR(noisy.dP_px,
              options.t_dP_px + k * 400.0 * (sigma_r + 0.5 / 10.0), 1e-9);
}

}  // namespace
}  // namespace colmap_lidar
