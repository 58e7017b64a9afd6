#include "src/mvs/lidar_patch_match_stereo.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/mvs/workspace.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"
#include "src/mvs/mvs_test_scene.h"

namespace colmap_lidar {
namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 120;
constexpr int kNumViews = 5;

// Writes a dense workspace of the test plane scene: PNG images, a PINHOLE
// model with 60 tracked points (sampled from the ground truth), default
// stereo configs and lidar_fused.ply. Returns the ground-truth depth maps.
std::vector<std::vector<float>> WriteWorkspace(const std::string& path) {
  const PlaneScene scene = MakeTestPlaneScene();
  const Eigen::Matrix3d K = TestCalibration(kWidth, kHeight);
  const std::vector<Rigid3d> poses = TestCameraPoses(kNumViews);
  Reconstruction model;
  model.cameras[1] = Camera::FromModelName(
      "PINHOLE", kWidth, kHeight, {K(0, 0), K(1, 1), K(0, 2), K(1, 2)});
  model.cameras[1].camera_id = 1;
  std::vector<std::string> names;
  std::vector<std::vector<float>> gt(kNumViews);
  CreateDenseWorkspaceLayout(path, {});
  for (int i = 0; i < kNumViews; ++i) {
    const std::string name = "v" + std::to_string(i) + ".png";
    names.push_back(name);
    const MvsView view = scene.Render(name, K, poses[i], kWidth, kHeight, &gt[i]);
    cv::Mat image(kHeight, kWidth, CV_8UC1);
    for (int r = 0; r < kHeight; ++r) {
      for (int c = 0; c < kWidth; ++c) {
        image.at<uint8_t>(r, c) = cv::saturate_cast<uint8_t>(view.At(r, c) * 255.0f);
      }
    }
    cv::imwrite(JoinPaths(JoinPaths(path, "images"), name), image);
    Image model_image;
    model_image.image_id = 10 + i;
    model_image.name = name;
    model_image.camera_id = 1;
    model_image.cam_from_world = poses[i];
    model.images.push_back(model_image);
  }
  // Tracked points: random pixels of view 0, observed where visible.
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> col_dist(5, kWidth - 6), row_dist(5, kHeight - 6);
  for (point3D_t id = 1; id <= 60; ++id) {
    const int row = row_dist(rng), col = col_dist(rng);
    const double depth = gt[0][row * kWidth + col];
    if (!(depth > 0)) continue;
    const Eigen::Vector3d point_in_world =
        poses[0].Inverse() * (depth * (K.inverse() * Eigen::Vector3d(col, row, 1)));
    Point3D point;
    point.xyz = point_in_world;
    for (int i = 0; i < kNumViews; ++i) {
      const Eigen::Vector3d in_cam = poses[i] * point_in_world;
      const Eigen::Vector3d uv = K * in_cam / in_cam.z();
      const int c = static_cast<int>(std::lround(uv.x()));
      const int r = static_cast<int>(std::lround(uv.y()));
      if (c < 0 || r < 0 || c >= kWidth || r >= kHeight ||
          std::abs(gt[i][r * kWidth + c] - in_cam.z()) > 0.02) {
        continue;
      }
      Point2D point2D;
      point2D.xy = uv.head<2>() + Eigen::Vector2d(0.5, 0.5);
      point2D.point3D_id = id;
      model.images[i].points2D.push_back(point2D);
      point.track.push_back({model.images[i].image_id,
                             static_cast<point2D_t>(model.images[i].points2D.size() - 1)});
    }
    model.points3D[id] = point;
  }
  WriteReconstruction(JoinPaths(path, "sparse"), model, ModelFormat::kBinary);
  const DenseWorkspace workspace(path);
  WriteDefaultStereoConfigs(workspace, names, 20);
  // LIDAR scans from above each camera, fused.
  std::vector<LidarScan> scans(kNumViews);
  std::vector<LidarFusionInput> inputs;
  for (int i = 0; i < kNumViews; ++i) {
    const Eigen::Vector3d origin =
        poses[i].Inverse().translation + Eigen::Vector3d(0, -0.1, 0);
    scene.Scan(origin, Eigen::Vector3d::UnitZ(), 16, 150, 0.8, 0.5,
               &scans[i].points, nullptr);
    // Points stay in the world: the scan pose is a pure translation.
    for (Eigen::Vector3f& p : scans[i].points) p -= origin.cast<float>();
    inputs.push_back({static_cast<uint32_t>(i), &scans[i],
                      Rigid3d(Eigen::Quaterniond::Identity(), origin)});
  }
  LidarFusionOptions fusion_options;
  fusion_options.voxel_size_m = 0.03;
  WriteFusedLidarCloud(JoinPaths(path, "lidar_fused.ply"),
                       FuseLidarScans(inputs, fusion_options));
  return gt;
}

double DistanceToScene(const Eigen::Vector3d& point) {
  // Nearest of the wall z = 4 and the slanted plane of MakeTestPlaneScene.
  const PlaneScene scene = MakeTestPlaneScene();
  double best = 1e9;
  for (const TexturedPlane& plane : scene.planes) {
    const Eigen::Vector3d n = plane.u_axis.cross(plane.v_axis);
    best = std::min(best, std::abs(n.dot(point - plane.origin)));
  }
  return best;
}

// Few iterations (the LIDAR initialisation is close), 2 threads.
LidarPatchMatchOptions QuickOptions(int num_iterations) {
  LidarPatchMatchOptions options;
  options.num_iterations = num_iterations;
  options.num_geom_iterations = 1;
  options.num_threads = 2;
  return options;
}

TEST(LidarPatchMatchStereo, WritesMapsThatStockFusionTurnsIntoTheSurface) {
  const std::string path = JoinPaths(testing::CreateTestDir(), "dense");
  const std::vector<std::vector<float>> gt = WriteWorkspace(path);
  const LidarPatchMatchOptions options = QuickOptions(3);
  const LidarPatchMatchSummary summary = RunLidarPatchMatchStereo(path, options);
  EXPECT_EQ(summary.num_references, kNumViews);
  EXPECT_EQ(summary.num_photometric_computed, kNumViews);
  EXPECT_EQ(summary.num_geometric_computed, kNumViews);

  const DenseWorkspace workspace(path);
  workspace.Validate(DenseMapType::kGeometric);
  workspace.Validate(DenseMapType::kPhotometric);
  const DepthMap depth =
      DepthMap::Read(workspace.DepthMapPath("v0.png", DenseMapType::kGeometric));
  const NormalMap normals =
      NormalMap::Read(workspace.NormalMapPath("v0.png", DenseMapType::kGeometric));
  const Eigen::Matrix3d K = TestCalibration(kWidth, kHeight);
  size_t num_valid = 0, num_accurate = 0;
  for (int r = 0; r < kHeight; ++r) {
    for (int c = 0; c < kWidth; ++c) {
      if (!depth.IsValid(r, c)) {
        EXPECT_FALSE(normals.IsValid(r, c));
        continue;
      }
      ++num_valid;
      num_accurate += std::abs(depth.Get(r, c) - gt[0][r * kWidth + c]) < 0.05;
      // Unit normals facing the camera.
      const Eigen::Vector3f n = normals.Get(r, c);
      EXPECT_NEAR(n.norm(), 1.0f, 1e-4);
      EXPECT_LT(n.dot(MvsPixelRay(K, r, c).cast<float>()), 0.0f);
    }
  }
  std::cout << num_valid << " valid pixels, " << num_accurate
            << " within 5 cm" << std::endl;
  EXPECT_GT(num_valid, kWidth * kHeight / 2);
  EXPECT_GT(num_accurate, num_valid * 95 / 100);

  // Stock fusion of the geometric maps.
  const std::string fused = JoinPaths(path, "fused.ply");
  ASSERT_EQ(testing::RunCommand(
                "colmap stereo_fusion --workspace_path " + path +
                    " --input_type geometric --output_path " + fused +
                    " --StereoFusion.num_threads 1",
                JoinPaths(path, "fusion.log")),
            0);
  const std::vector<PlyPoint> points = ReadPlyPoints(fused);
  std::cout << points.size() << " fused points" << std::endl;
  EXPECT_GT(points.size(), 3000u);
  size_t num_on_surface = 0;
  for (const PlyPoint& point : points) {
    num_on_surface += DistanceToScene(point.xyz.cast<double>()) < 0.03;
  }
  EXPECT_GT(num_on_surface, points.size() * 97 / 100);

  // Resume: a second run skips everything and leaves the files alone.
  const std::string before = ReadTextFile(
      workspace.DepthMapPath("v3.png", DenseMapType::kGeometric));
  const LidarPatchMatchSummary again = RunLidarPatchMatchStereo(path, options);
  EXPECT_EQ(again.num_photometric_skipped, kNumViews);
  EXPECT_EQ(again.num_geometric_skipped, kNumViews);
  EXPECT_EQ(again.num_photometric_computed + again.num_geometric_computed, 0);
  EXPECT_EQ(before, ReadTextFile(workspace.DepthMapPath(
                        "v3.png", DenseMapType::kGeometric)));
}

// Valid pixels of view `index`'s geometric depth map; `num_accurate`: those
// within 5 cm of the ground truth `gt[index]`.
size_t CountValidPixels(const DenseWorkspace& workspace,
                        const std::vector<std::vector<float>>& gt, int index,
                        size_t* num_accurate) {
  const DepthMap depth = DepthMap::Read(workspace.DepthMapPath(
      "v" + std::to_string(index) + ".png", DenseMapType::kGeometric));
  size_t num_valid = 0;
  *num_accurate = 0;
  for (int r = 0; r < kHeight; ++r) {
    for (int c = 0; c < kWidth; ++c) {
      if (depth.IsValid(r, c)) {
        ++num_valid;
        *num_accurate +=
            std::abs(depth.Get(r, c) - gt[index][r * kWidth + c]) < 0.05;
      }
    }
  }
  return num_valid;
}

// The LIDAR as one more consistent view of the geometric filter: with more
// consistent views required than there are sources (4), only pixels that
// the LIDAR confirms can pass, and they lie on the surface.
TEST(LidarPatchMatchStereo, LidarCountsAsAConsistentView) {
  const std::string path = JoinPaths(testing::CreateTestDir(), "dense");
  const std::vector<std::vector<float>> gt = WriteWorkspace(path);
  LidarPatchMatchOptions options = QuickOptions(2);
  options.filter_min_num_consistent = kNumViews;
  // Every source counts, seeing the pixel or not (else pixels seen by fewer
  // sources would need fewer views, without the LIDAR).
  options.visible_sources_only = false;
  const DenseWorkspace workspace(path);
  const auto count = [&](size_t* num_accurate) {
    return CountValidPixels(workspace, gt, 2, num_accurate);
  };
  const std::string mask_path =
      JoinPaths(FusionMaskDir(path), "v2.png.png");
  options.filter_lidar_as_view = false;
  options.filter_reproj_parallax = false;
  RunLidarPatchMatchStereo(path, options);
  size_t num_accurate = 0;
  EXPECT_EQ(count(&num_accurate), 0u);
  // Nothing to keep out of fusion: no mask.
  EXPECT_FALSE(ExistsFile(mask_path));

  options.filter_lidar_as_view = true;
  options.overwrite = true;
  const LidarPatchMatchSummary summary =
      RunLidarPatchMatchStereo(path, options);
  const size_t num_valid = count(&num_accurate);
  // No pixel can pass on the images alone; some sources agree with each.
  EXPECT_EQ(summary.support.images_only + summary.support.images_and_lidar,
            0u);
  // Kept out of fusion: those and the textureless pixels filled.
  EXPECT_EQ(summary.support.lidar_and_views + summary.support.lidar_only +
                summary.num_filled,
            summary.num_not_fused);
  EXPECT_GT(summary.support.lidar_and_views, summary.support.lidar_only);
  std::cout << num_valid << " pixels confirmed by 4 views and the LIDAR, "
            << num_accurate << " within 5 cm" << std::endl;
  EXPECT_GT(num_valid, kWidth * kHeight / 4);
  EXPECT_GT(num_accurate, num_valid * 98 / 100);

  // Every one of them needed the LIDAR: the fusion mask excludes exactly
  // the valid pixels.
  const cv::Mat mask = cv::imread(mask_path, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(mask.empty()) << mask_path;
  ASSERT_EQ(mask.type(), CV_8UC1);
  ASSERT_EQ(mask.cols, kWidth);
  ASSERT_EQ(mask.rows, kHeight);
  const DepthMap depth = DepthMap::Read(
      workspace.DepthMapPath("v2.png", DenseMapType::kGeometric));
  for (int r = 0; r < kHeight; ++r) {
    for (int c = 0; c < kWidth; ++c) {
      ASSERT_EQ(mask.at<uint8_t>(r, c), depth.IsValid(r, c) ? 0 : 255)
          << r << " " << c;
    }
  }
}

// Sources that cannot see a pixel neither confirm nor refute it: counting
// only the sources whose image holds the point keeps the pixels that fewer
// sources see (the image sides of the outer views), and keeps them accurate.
TEST(LidarPatchMatchStereo, OnlyVisibleSourcesCount) {
  const std::string path = JoinPaths(testing::CreateTestDir(), "dense");
  const std::vector<std::vector<float>> gt = WriteWorkspace(path);
  const DenseWorkspace workspace(path);
  // Valid and accurate pixels of the outer view v0.
  const auto count = [&](size_t* num_accurate) {
    return CountValidPixels(workspace, gt, 0, num_accurate);
  };
  LidarPatchMatchOptions options = QuickOptions(2);
  // Every source must agree where it can see: the pixels of v0 that the
  // farthest source v4 does not see need the visible-sources count.
  options.filter_min_num_consistent = kNumViews - 1;
  options.filter_lidar_as_view = false;
  options.visible_sources_only = false;
  RunLidarPatchMatchStereo(path, options);
  size_t all_accurate = 0;
  const size_t all_valid = count(&all_accurate);
  options.visible_sources_only = true;
  options.overwrite = true;
  const LidarPatchMatchSummary summary =
      RunLidarPatchMatchStereo(path, options);
  // Without the LIDAR's vote every kept pixel rests on the images.
  EXPECT_EQ(summary.support.images_only, summary.support.Total());
  EXPECT_GT(summary.support.Total(), 0u);
  size_t visible_accurate = 0;
  const size_t visible_valid = count(&visible_accurate);
  std::cout << "v0: " << all_valid << " valid (" << all_accurate
            << " within 5 cm) counting every source, " << visible_valid
            << " (" << visible_accurate << ") counting the visible ones"
            << std::endl;
  // The views overlap widely here: the count gains 3 % of the image.
  EXPECT_GT(visible_valid, all_valid + kWidth * kHeight / 50);
  EXPECT_GT(visible_accurate, visible_valid * 98 / 100);
}

TEST(LidarPatchMatchStereo, LidarInitNeedsTheFusedCloud) {
  const std::string path = JoinPaths(testing::CreateTestDir(), "dense");
  WriteWorkspace(path);
  std::remove(JoinPaths(path, "lidar_fused.ply").c_str());
  LidarPatchMatchOptions options;
  EXPECT_THROW(RunLidarPatchMatchStereo(path, options), Error);
  options.init = "random";
  options.num_iterations = 1;
  options.geom_consistency = false;
  const LidarPatchMatchSummary summary = RunLidarPatchMatchStereo(path, options);
  EXPECT_EQ(summary.num_photometric_computed, kNumViews);
  EXPECT_EQ(summary.num_geometric_computed, 0);
}

}  // namespace
}  // namespace colmap_lidar
