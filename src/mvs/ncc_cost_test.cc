#include "src/mvs/ncc_cost.h"

#include <gtest/gtest.h>

#include "src/mvs/mvs_test_scene.h"

namespace colmap_lidar {
namespace {

TEST(NccCost, MinimalAtTheTrueDepthOfATexturedPlane) {
  const PlaneScene scene = MakeTestPlaneScene();
  const int width = 160, height = 120;
  const Eigen::Matrix3d K = TestCalibration(width, height);
  const std::vector<Rigid3d> poses = TestCameraPoses(3);
  std::vector<float> gt;
  const MvsView ref = scene.Render("ref", K, poses[0], width, height, &gt);
  const MvsView src1 = scene.Render("src1", K, poses[1], width, height);
  const MvsView src2 = scene.Render("src2", K, poses[2], width, height);
  LidarPatchMatchOptions options;
  options.window_radius = 5;  // 36 samples: a clear minimum on the wall.
  const PatchCostComputer cost(ref, {&src1, &src2}, options);
  RefPatch patch;
  int num_checked = 0;
  // Pixels on the wall (normal -z in the camera) and on the slanted plane.
  for (const auto& [row, col] : std::vector<std::pair<int, int>>{
           {60, 130}, {30, 140}, {90, 120}, {60, 50}, {75, 45}}) {
    const float depth = gt[row * width + col];
    ASSERT_GT(depth, 0);
    // True normal by ray casting, in the camera frame.
    double t;
    Eigen::Vector3d normal_world;
    const Rigid3d world_from_cam = poses[0].Inverse();
    const Eigen::Vector3d ray = K.inverse() * Eigen::Vector3d(col, row, 1);
    ASSERT_TRUE(scene.Intersect(world_from_cam.translation,
                                world_from_cam.rotation * ray, &t,
                                &normal_world, nullptr));
    const Eigen::Vector3f normal =
        (poses[0].rotation * normal_world).cast<float>();
    cost.PrepareRefPatch(row, col, &patch);
    const float at_truth = cost.Cost(patch, depth, normal);
    EXPECT_LT(at_truth, 0.15f) << row << " " << col;
    // 3 % of depth is 0.15 px of disparity on the wall: the cost rises
    // gently near the truth and clearly at 10 %.
    for (float factor : {0.95f, 0.97f, 1.03f, 1.05f}) {
      EXPECT_GT(cost.Cost(patch, depth * factor, normal), at_truth)
          << row << " " << col << " factor " << factor;
    }
    for (float factor : {0.85f, 0.9f, 1.1f, 1.15f}) {
      EXPECT_GT(cost.Cost(patch, depth * factor, normal), at_truth + 0.05f)
          << row << " " << col << " factor " << factor;
    }
    // A wrong normal costs more too.
    const Eigen::Vector3f tilted =
        (normal + Eigen::Vector3f(0.6f, 0.0f, 0.0f)).normalized();
    EXPECT_GT(cost.Cost(patch, depth, tilted), at_truth);
    ++num_checked;
  }
  EXPECT_EQ(num_checked, 5);
}

TEST(NccCost, TexturelessWindowsAndOutOfViewCostTheMaximum) {
  const int width = 40, height = 30;
  const Eigen::Matrix3d K = TestCalibration(width, height);
  const std::vector<Rigid3d> poses = TestCameraPoses(2);
  const MvsView flat = MakeMvsView("flat", K, poses[0], width, height,
                                   std::vector<float>(width * height, 0.5f));
  const MvsView other = MakeMvsView("other", K, poses[1], width, height,
                                    std::vector<float>(width * height, 0.5f));
  LidarPatchMatchOptions options;
  const PatchCostComputer cost(flat, {&other}, options);
  RefPatch patch;
  cost.PrepareRefPatch(15, 20, &patch);
  EXPECT_EQ(cost.Cost(patch, 3.0f, Eigen::Vector3f(0, 0, -1)), kMaxCost);
}

}  // namespace
}  // namespace colmap_lidar
