#include "src/matching/relative_line_pose.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <numeric>

#include "src/matching/candidate_views.h"
#include "src/matching/synthetic_line_views.h"

namespace colmap_lidar {
namespace {

struct PoseError {
  double rotation_deg = 0.0;
  double translation_m = 0.0;
};

PoseError Error(const Rigid3d& estimate, const Rigid3d& truth) {
  PoseError error;
  error.rotation_deg =
      Eigen::AngleAxisd(estimate.rotation * truth.rotation.inverse()).angle() *
      180.0 / M_PI;
  error.translation_m = (estimate.translation - truth.translation).norm();
  return error;
}

LineMatchingOptions NoisyPriorOptions() {
  LineMatchingOptions options;
  options.pose_sigma_t_m = 0.5;
  options.pose_sigma_r_deg = 5.0;
  return options;
}

// The segments of view1 that the (prior) poses place in view2.
std::vector<int> VisibleSegments(const MatchingView& view1,
                                 const MatchingView& view2,
                                 const LineMatchingOptions& options) {
  std::vector<int> visible;
  for (size_t a = 0; a < view1.segments.size(); ++a) {
    if (ProjectSegmentIntoView(view1.segments[a].start_in_world,
                               view1.segments[a].end_in_world, view2, options)
            .visible) {
      visible.push_back(static_cast<int>(a));
    }
  }
  return visible;
}

TEST(RelativeLinePose, RegistersNeighboursOfAPeriodicFacadeFromNoisyPriors) {
  const SyntheticLineScene scene = MakeSyntheticLineScene({});
  const std::vector<Rigid3d> noisy =
      PerturbPoses(scene.cam_from_world, 0.5, 5.0, /*seed=*/2);
  const std::vector<MatchingView> views = MakeSyntheticViews(scene, noisy);
  const LineMatchingOptions options = NoisyPriorOptions();
  int num_pairs = 0;
  int num_accurate = 0;
  double prior_rotation_error = 0.0;
  for (size_t v = 0; v + 1 < views.size(); ++v) {
    const Rigid3d truth =
        scene.cam_from_world[v + 1] * scene.cam_from_world[v].Inverse();
    const RelativeLinePose pose = EstimateRelativeLinePose(
        views[v], VisibleSegments(views[v], views[v + 1], options),
        views[v + 1], options, /*seed=*/1);
    ++num_pairs;
    prior_rotation_error +=
        Error(views[v + 1].cam_from_world * views[v].cam_from_world.Inverse(),
              truth)
            .rotation_deg;
    if (!pose.valid) continue;
    EXPECT_GE(pose.num_inliers, options.relative_pose_min_inliers);
    EXPECT_LE(pose.cost, pose.runner_up_cost);
    const PoseError error = Error(pose.cam2_from_cam1, truth);
    // Window columns are 2.5 m apart: a wrong registration is off by
    // metres; a right one by the noise.
    if (error.rotation_deg < 0.5 && error.translation_m < 0.05) ++num_accurate;
  }
  std::cout << num_accurate << " of " << num_pairs
            << " neighbour pairs registered within 0.5 deg / 5 cm (prior "
               "rotation error "
            << prior_rotation_error / num_pairs << " deg on average)"
            << std::endl;
  EXPECT_GE(num_accurate, num_pairs * 3 / 4);
}

TEST(RelativeLinePose, RefinementFromTheTruthStaysThere) {
  const SyntheticLineScene scene = MakeSyntheticLineScene({});
  const std::vector<MatchingView> views =
      MakeSyntheticViews(scene, scene.cam_from_world);
  const LineMatchingOptions options = NoisyPriorOptions();
  const Rigid3d truth =
      scene.cam_from_world[3] * scene.cam_from_world[2].Inverse();
  const RelativeLinePose pose = RefineRelativeLinePose(
      views[2], VisibleSegments(views[2], views[3], options), views[3], options,
      truth);
  ASSERT_TRUE(pose.valid);
  const PoseError error = Error(pose.cam2_from_cam1, truth);
  EXPECT_LT(error.rotation_deg, 0.2);
  EXPECT_LT(error.translation_m, 0.02);
  // The information matrix is usable by the pose graph.
  const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(pose.information);
  EXPECT_EQ(llt.info(), Eigen::Success);
}

TEST(RelativeLinePose, ParallelSegmentsOnlyDoNotRegister) {
  // Only the vertical edges: the rotation about the vertical and the
  // vertical translation are free.
  SyntheticLineScene scene = MakeSyntheticLineScene({});
  for (size_t v = 0; v < scene.segments.size(); ++v) {
    std::vector<LineSegmentRecord> vertical;
    for (const LineSegmentRecord& record : scene.segments[v]) {
      const Eigen::Vector2d d = record.end2D - record.start2D;
      if (std::abs(d.x()) < 0.2 * std::abs(d.y())) vertical.push_back(record);
    }
    scene.segments[v] = vertical;
  }
  const std::vector<MatchingView> views =
      MakeSyntheticViews(scene, scene.cam_from_world);
  ASSERT_GE(views[2].segments.size(), 6u);
  const LineMatchingOptions options = NoisyPriorOptions();
  std::vector<int> all(views[2].segments.size());
  std::iota(all.begin(), all.end(), 0);
  EXPECT_FALSE(
      EstimateRelativeLinePose(views[2], all, views[3], options, 1).valid);
}

}  // namespace
}  // namespace colmap_lidar
