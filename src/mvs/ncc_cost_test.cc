#include "src/mvs/ncc_cost.h"

#include <algorithm>

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
  EXPECT_TRUE(cost.Textureless(15, 20));
  EXPECT_TRUE(cost.Textureless(0, 0));
  // A checker pattern is textured everywhere.
  std::vector<float> checker(width * height);
  for (int i = 0; i < width * height; ++i) {
    checker[i] = ((i % width) / 2 + (i / width) / 2) % 2 ? 0.7f : 0.3f;
  }
  const MvsView textured =
      MakeMvsView("textured", K, poses[0], width, height, checker);
  const PatchCostComputer textured_cost(textured, {&other}, options);
  EXPECT_FALSE(textured_cost.Textureless(15, 20));
  EXPECT_FALSE(textured_cost.Textureless(0, 0));
}

// Ground 1.5 m below two cameras looking along it, the source 2 m behind the
// reference; the source map holds the ground's exact depth and normal at its
// pixel centres. A reference pixel at its true depth projects between the
// source's pixel centres: read at the sub-pixel projection from the nearest
// pixel's plane, the source agrees exactly; the nearest pixel's own depth is
// off by up to half a pixel of a steep depth gradient.
TEST(NccCost, SourceDepthFromThePlaneAtTheSubPixelProjection) {
  const int width = 160, height = 120;
  const float ground_y = 1.5f;
  // The source 2 m behind the reference.
  const GroundViewPair pair(width, height, ground_y,
                            Eigen::Vector3d(0.0, 0.0, -2.0));
  const MvsView& ref = pair.ref;
  const MvsView& src = pair.src;
  const PlaneMap& src_map = pair.src_map;
  const auto errors = [&](bool plane_depth, float* max_depth_error,
                          float* max_reprojection_error) {
    LidarPatchMatchOptions options;
    options.source_plane_depth = plane_depth;
    PatchCostComputer cost(ref, {&src}, options);
    cost.SetSourceMaps({&src_map});
    *max_depth_error = 0.0f;
    *max_reprojection_error = 0.0f;
    int num_checked = 0;
    // Reference ground pixels 2.5-9 m ahead (4.5-11 m from the source).
    for (int row = 0; row < height; ++row) {
      for (int col = 0; col < width; ++col) {
        const Eigen::Vector3f ray = ref.Ray(static_cast<float>(row),
                                            static_cast<float>(col));
        if (ray.y() < ground_y / 9.0f || ray.y() > ground_y / 2.5f) continue;
        const float depth = ground_y / ray.y();
        if (!cost.SourceSees(0, row, col, depth)) continue;
        *max_depth_error = std::max(*max_depth_error,
                                    cost.SourceDepthError(0, row, col, depth));
        *max_reprojection_error =
            std::max(*max_reprojection_error,
                     cost.ReprojectionError(0, row, col, depth));
        ++num_checked;
      }
    }
    return num_checked;
  };
  float plane_depth_error, plane_reprojection_error;
  ASSERT_GT(errors(true, &plane_depth_error, &plane_reprojection_error), 1000);
  EXPECT_LT(plane_depth_error, 1e-4f);
  EXPECT_LT(plane_reprojection_error, 0.01f);
  float pixel_depth_error, pixel_reprojection_error;
  errors(false, &pixel_depth_error, &pixel_reprojection_error);
  // Nearest-pixel depth: more than the filter's 1 % at the far end.
  EXPECT_GT(pixel_depth_error, 0.01f);
  EXPECT_GT(pixel_reprojection_error, 0.3f);

  // A source map 1 % too deep: the reprojection error is the parallax of a
  // 1 % depth step, 0 on the baseline (the optical axis) and growing with
  // the triangulation angle.
  PlaneMap deeper = src_map;
  for (float& depth : deeper.depth) depth *= 1.01f;
  LidarPatchMatchOptions options;
  PatchCostComputer cost(ref, {&src}, options);
  cost.SetSourceMaps({&deeper});
  EXPECT_LT(cost.DepthErrorParallax(0, height / 2, width / 2, 5.0f, 0.01f),
            1e-4f);
  float max_parallax = 0.0f;
  for (int row = height / 2 + 10; row < height; row += 7) {
    for (int col = 0; col < width; col += 7) {
      const float depth =
          ground_y / ref.Ray(static_cast<float>(row), static_cast<float>(col)).y();
      if (!cost.SourceSees(0, row, col, depth)) continue;
      const float parallax = cost.DepthErrorParallax(0, row, col, depth, 0.01f);
      EXPECT_NEAR(cost.ReprojectionError(0, row, col, depth), parallax,
                  0.02f + 0.02f * parallax)
          << row << " " << col;
      max_parallax = std::max(max_parallax, parallax);
    }
  }
  EXPECT_GT(max_parallax, 0.3f);
}

}  // namespace
}  // namespace colmap_lidar
