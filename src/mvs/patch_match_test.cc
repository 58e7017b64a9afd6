#include "src/mvs/patch_match.h"

#include <gtest/gtest.h>

#include "src/mvs/interpolation.h"
#include "src/mvs/lidar_patch_match_stereo.h"
#include "src/mvs/mvs_test_scene.h"

namespace colmap_lidar {
namespace {

struct Scene {
  std::vector<MvsView> views;
  std::vector<float> gt;
  FusedLidarCloud lidar;
};

Scene MakeScene(int num_views) {
  const PlaneScene planes = MakeTestPlaneScene();
  const int width = 160, height = 120;
  const Eigen::Matrix3d K = TestCalibration(width, height);
  const std::vector<Rigid3d> poses = TestCameraPoses(num_views);
  Scene scene;
  for (int i = 0; i < num_views; ++i) {
    scene.views.push_back(planes.Render("v" + std::to_string(i), K, poses[i],
                                        width, height,
                                        i == 0 ? &scene.gt : nullptr));
  }
  // A sparse LIDAR (16 rings) 10 cm above the reference camera.
  planes.Scan(Eigen::Vector3d(0, -0.1, 0), Eigen::Vector3d::UnitZ(), 16, 120,
              0.8, 0.5, &scene.lidar.points, &scene.lidar.normals);
  return scene;
}

// Accuracy after each iteration for one initialisation.
std::vector<double> RunFromInit(const Scene& scene, const std::string& init,
                        int num_iterations) {
  LidarPatchMatchOptions options;
  options.init = init;
  options.num_threads = 2;
  const MvsView& ref = scene.views[0];
  std::vector<const MvsView*> srcs;
  for (size_t i = 1; i < scene.views.size(); ++i) srcs.push_back(&scene.views[i]);
  ReferenceInit reference =
      InitializeReference(ref, {}, &scene.lidar, 0, options);
  const PatchCostComputer cost(ref, srcs, options);
  PatchMatchProblem problem;
  problem.cost = &cost;
  problem.depth_min = 1.5f;
  problem.depth_max = 8.0f;
  std::vector<double> shares;
  if (init == "random") {
    RandomizePlaneMap(ref, problem.depth_min, problem.depth_max, 1,
                      &reference.state);
  }
  shares.push_back(ShareWithinTolerance(reference.state.depth, scene.gt, 0.05));
  RunPatchMatch(problem, options, num_iterations, 1, &reference.state,
                [&](int, const PlaneMap& map) {
                  shares.push_back(ShareWithinTolerance(map.depth, scene.gt, 0.05));
                });
  return shares;
}

TEST(PatchMatch, ConvergesAndLidarInitIsFaster) {
  const Scene scene = MakeScene(5);
  const std::vector<double> lidar = RunFromInit(scene, "lidar", 4);
  const std::vector<double> random = RunFromInit(scene, "random", 4);
  for (size_t i = 0; i < lidar.size(); ++i) {
    std::cout << "iteration " << i << ": lidar " << lidar[i] << " random "
              << random[i] << std::endl;
  }
  // Within 5 cm for most pixels after 4 iterations, both ways.
  EXPECT_GT(lidar.back(), 0.85);
  EXPECT_GT(random.back(), 0.75);
  // The LIDAR start is already good and stays ahead after one iteration.
  EXPECT_GT(lidar[0], 0.5);
  EXPECT_LT(random[0], 0.1);
  EXPECT_GT(lidar[1], random[1] + 0.05);
  EXPECT_GE(lidar[1], random.back() - 0.02);
}

TEST(PatchMatch, ResultDoesNotDependOnThreads) {
  const Scene scene = MakeScene(3);
  LidarPatchMatchOptions options;
  options.init = "random";
  const PatchCostComputer cost(scene.views[0], {&scene.views[1], &scene.views[2]},
                               options);
  PatchMatchProblem problem;
  problem.cost = &cost;
  problem.depth_min = 1.5f;
  problem.depth_max = 8.0f;
  PlaneMap a(160, 120), b(160, 120);
  options.num_threads = 1;
  RunPatchMatch(problem, options, 1, 5, &a);
  options.num_threads = 2;
  RunPatchMatch(problem, options, 1, 5, &b);
  EXPECT_EQ(a.depth, b.depth);
}

}  // namespace
}  // namespace colmap_lidar
