#include "colmap_ext/mvs/workspace.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/mvs/dense_maps.h"
#include "colmap_ext/mvs/fused_vis.h"
#include "colmap_ext/mvs/stereo_config.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

template <typename Function>
void ExpectErrorContaining(const Function& function,
                           const std::string& fragment) {
  try {
    function();
    ADD_FAILURE() << "no exception; expected one naming " << fragment;
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos)
        << "'" << error.what() << "' does not name '" << fragment << "'";
  }
}

TEST(DenseWorkspace, Paths) {
  const DenseWorkspace workspace("/data/ws");
  EXPECT_EQ(workspace.ImagesDir(), "/data/ws/images");
  EXPECT_EQ(workspace.SparseDir(), "/data/ws/sparse");
  EXPECT_EQ(workspace.StereoDir(), "/data/ws/stereo");
  EXPECT_EQ(workspace.PatchMatchConfigPath(), "/data/ws/stereo/patch-match.cfg");
  EXPECT_EQ(workspace.FusionConfigPath(), "/data/ws/stereo/fusion.cfg");
  EXPECT_EQ(workspace.FusedPlyPath(), "/data/ws/fused.ply");
  EXPECT_EQ(workspace.FusedVisPath(), "/data/ws/fused.ply.vis");
  EXPECT_EQ(workspace.PoissonMeshPath(), "/data/ws/meshed-poisson.ply");
  EXPECT_EQ(workspace.DelaunayMeshPath(), "/data/ws/meshed-delaunay.ply");
  EXPECT_EQ(workspace.ImagePath("cam0/a.png"), "/data/ws/images/cam0/a.png");
  EXPECT_EQ(workspace.DepthMapPath("cam0/a.png", DenseMapType::kGeometric),
            "/data/ws/stereo/depth_maps/cam0/a.png.geometric.bin");
  EXPECT_EQ(workspace.NormalMapPath("a.jpg", DenseMapType::kPhotometric),
            "/data/ws/stereo/normal_maps/a.jpg.photometric.bin");
  EXPECT_EQ(
      workspace.ConsistencyGraphPath("a.jpg", DenseMapType::kPhotometric),
      "/data/ws/stereo/consistency_graphs/a.jpg.photometric.bin");
  EXPECT_EQ(DenseMapTypeFromString("GEOMETRIC"), DenseMapType::kGeometric);
  EXPECT_EQ(DenseMapTypeFromString("photometric"),
            DenseMapType::kPhotometric);
  EXPECT_THROW(DenseMapTypeFromString("fused"), Error);
}

TEST(DenseWorkspace, LayoutMirrorsImageFolders) {
  const std::string root = testing::CreateTestDir();
  const std::string path = JoinPaths(root, "dense");
  const std::vector<std::string> names = {"a.png", "cam0/b.png",
                                          "cam1/sub/c.png"};
  CreateDenseWorkspaceLayout(path, names);
  const DenseWorkspace workspace(path);
  for (const std::string& dir :
       {workspace.DepthMapsDir(), workspace.NormalMapsDir(),
        workspace.ConsistencyGraphsDir(), workspace.ImagesDir()}) {
    EXPECT_TRUE(ExistsDir(JoinPaths(dir, "cam0"))) << dir;
    EXPECT_TRUE(ExistsDir(JoinPaths(dir, "cam1/sub"))) << dir;
  }
  EXPECT_TRUE(ExistsDir(workspace.SparseDir()));
  WriteDefaultStereoConfigs(workspace, names, 7);
  EXPECT_EQ(ReadTextFile(workspace.FusionConfigPath()),
            "a.png\ncam0/b.png\ncam1/sub/c.png\n");
  const std::vector<PatchMatchEntry> entries =
      ReadPatchMatchConfig(workspace.PatchMatchConfigPath());
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[2].ref_image_name, "cam1/sub/c.png");
  EXPECT_EQ(entries[2].num_auto_src_images, 7);
  // No model yet: Validate names the sparse folder.
  ExpectErrorContaining([&] { workspace.Validate(DenseMapType::kGeometric); },
                        workspace.SparseDir());
}

// --- End-to-end with stock `colmap stereo_fusion` -------------------------
//
// Scene: the ground z = 0 and a wall x = kWallX, seen from five PINHOLE
// cameras on the x < kWallX, z > 0 side. For such cameras the nearest hit of
// the two infinite planes is the visible surface of the "room corner".

constexpr double kWallX = 2.0;
constexpr int kWidth = 320;
constexpr int kHeight = 240;

struct Plane {
  Eigen::Vector3d normal;  // Unit, facing the cameras.
  double offset;           // normal . X = offset.
};

const std::vector<Plane>& ScenePlanes() {
  static const std::vector<Plane> planes = {
      {Eigen::Vector3d(0, 0, 1), 0.0}, {Eigen::Vector3d(-1, 0, 0), -kWallX}};
  return planes;
}

Eigen::Matrix3d SceneK() {
  Eigen::Matrix3d K;
  K << 280, 0, 160, 0, 280, 120, 0, 0, 1;
  return K;
}

// cam_from_world looking from `center` at `target`, camera y down.
Rigid3d LookAt(const Eigen::Vector3d& center, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - center).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d(0, 0, 1)).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R.row(0) = x;
  R.row(1) = y;
  R.row(2) = z;
  return Rigid3d(Eigen::Quaterniond(R).normalized(), -R * center);
}

// Distance of a world point to the visible surface.
double SurfaceDistance(const Eigen::Vector3d& point) {
  double distance =
      std::min(std::abs(point.z()), std::abs(point.x() - kWallX));
  // Points below the ground or behind the wall are off the visible surface.
  distance = std::max({distance, -point.z(), point.x() - kWallX});
  return distance;
}

// The nearest plane hit along the MVS ray of pixel (row, col); false when
// nothing is hit within 30 m.
bool CastRay(const Rigid3d& cam_from_world, int row, int col, double* depth,
             Eigen::Vector3d* normal_in_world) {
  const Eigen::Vector3d ray_in_cam = MvsPixelRay(SceneK(), row, col);
  const Eigen::Matrix3d R = cam_from_world.rotation.toRotationMatrix();
  const Eigen::Vector3d ray_in_world = R.transpose() * ray_in_cam;
  const Eigen::Vector3d center = cam_from_world.Inverse().translation;
  double best = 30.0;
  bool hit = false;
  for (const Plane& plane : ScenePlanes()) {
    const double denominator = plane.normal.dot(ray_in_world);
    if (std::abs(denominator) < 1e-12) {
      continue;
    }
    // Because ray_in_cam has z = 1, the ray parameter is the z-depth.
    const double t = (plane.offset - plane.normal.dot(center)) / denominator;
    if (t > 0 && t < best) {
      best = t;
      *normal_in_world = plane.normal;
      hit = true;
    }
  }
  *depth = best;
  return hit;
}

struct SyntheticWorkspace {
  Reconstruction model;
  std::vector<std::string> names;
};

// Writes images, a TXT model with tracked points, fusion.cfg and analytic
// geometric depth and normal maps.
SyntheticWorkspace WriteSyntheticWorkspace(const DenseWorkspace& workspace) {
  SyntheticWorkspace scene;
  Camera camera = Camera::FromModelName("PINHOLE", kWidth, kHeight,
                                        {280, 280, 160, 120});
  camera.camera_id = 3;
  scene.model.cameras[camera.camera_id] = camera;
  // File order differs from id order, so that fusion's image_idx (file
  // position) is distinguishable from the image_id.
  const std::vector<image_t> image_ids = {5, 3, 1, 4, 2};
  const Eigen::Vector3d target(1.0, 0.3, 0.3);
  for (size_t i = 0; i < image_ids.size(); ++i) {
    Image image;
    image.image_id = image_ids[i];
    image.camera_id = camera.camera_id;
    image.name = "cam/img_" + std::to_string(image_ids[i]) + ".png";
    const Eigen::Vector3d center(-1.0 + 0.3 * i, -1.2 + 0.6 * i,
                                 2.4 + 0.1 * i);
    image.cam_from_world = LookAt(center, target);
    scene.model.images.push_back(image);
    scene.names.push_back(image.name);
  }

  // Sparse points on both planes that every image sees.
  std::vector<Eigen::Vector3d> candidates;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 5; ++j) {
      candidates.emplace_back(0.2 + 0.25 * i, -0.2 + 0.25 * j, 0.0);
      candidates.emplace_back(kWallX, -0.4 + 0.2 * i, 0.1 + 0.15 * j);
    }
  }
  point3D_t next_point3D_id = 100;
  for (const Eigen::Vector3d& point : candidates) {
    std::vector<Eigen::Vector2d> pixels;
    for (const Image& image : scene.model.images) {
      const Eigen::Vector3d in_cam = image.cam_from_world * point;
      const Eigen::Vector3d pixel = SceneK() * in_cam / in_cam.z();
      if (in_cam.z() > 0 && pixel.x() > 5 && pixel.x() < kWidth - 5 &&
          pixel.y() > 5 && pixel.y() < kHeight - 5) {
        pixels.push_back(pixel.head<2>());
      }
    }
    if (pixels.size() != scene.model.images.size() ||
        scene.model.points3D.size() >= 40) {
      continue;
    }
    Point3D point3D;
    point3D.xyz = point;
    point3D.color = Vector3ub(128, 128, 128);
    point3D.error = 0.1;
    const point3D_t point3D_id = next_point3D_id++;
    for (size_t i = 0; i < scene.model.images.size(); ++i) {
      Image& image = scene.model.images[i];
      Point2D point2D;
      point2D.xy = pixels[i];
      point2D.point3D_id = point3D_id;
      TrackElement element;
      element.image_id = image.image_id;
      element.point2D_idx = static_cast<point2D_t>(image.points2D.size());
      image.points2D.push_back(point2D);
      point3D.track.push_back(element);
    }
    scene.model.points3D[point3D_id] = point3D;
  }

  CreateDenseWorkspaceLayout(workspace.Path(), scene.names);
  WriteReconstruction(workspace.SparseDir(), scene.model, ModelFormat::kText);
  WriteDefaultStereoConfigs(workspace, scene.names);

  std::mt19937 rng(11);
  for (const Image& image : scene.model.images) {
    cv::Mat texture(kHeight, kWidth, CV_8UC3);
    cv::randu(texture, cv::Scalar::all(0), cv::Scalar::all(255));
    EXPECT_TRUE(cv::imwrite(workspace.ImagePath(image.name), texture));

    DepthMap depth_map(kWidth, kHeight);
    NormalMap normal_map(kWidth, kHeight);
    const Eigen::Matrix3d R = image.cam_from_world.rotation.toRotationMatrix();
    for (int row = 0; row < kHeight; ++row) {
      for (int col = 0; col < kWidth; ++col) {
        double depth;
        Eigen::Vector3d normal_in_world;
        if (!CastRay(image.cam_from_world, row, col, &depth,
                     &normal_in_world)) {
          continue;
        }
        depth_map.Set(row, col, static_cast<float>(depth));
        const Eigen::Vector3f ray =
            MvsPixelRay(SceneK(), row, col).cast<float>();
        normal_map.Set(row, col,
                       NormalMap::OrientTowardsCamera(
                           (R * normal_in_world).cast<float>(), ray));
      }
    }
    EXPECT_GT(depth_map.NumValid(), static_cast<size_t>(kWidth * kHeight * 0.9));
    depth_map.Write(
        workspace.DepthMapPath(image.name, DenseMapType::kGeometric));
    normal_map.Write(
        workspace.NormalMapPath(image.name, DenseMapType::kGeometric));
  }
  return scene;
}

TEST(DenseWorkspace, StockStereoFusionOnAnalyticMaps) {
  const std::string root = testing::CreateTestDir();
  const DenseWorkspace workspace(JoinPaths(root, "dense"));
  const SyntheticWorkspace scene = WriteSyntheticWorkspace(workspace);
  ASSERT_GE(scene.model.points3D.size(), 30u);

  workspace.Validate(DenseMapType::kGeometric);
  ExpectErrorContaining(
      [&] { workspace.Validate(DenseMapType::kPhotometric); },
      workspace.DepthMapPath(scene.names[0], DenseMapType::kPhotometric));

  const std::string log_path = JoinPaths(root, "fusion.log");
  const int code = testing::RunCommand(
      "colmap stereo_fusion --workspace_path " + workspace.Path() +
          " --workspace_format COLMAP --input_type geometric --output_path " +
          workspace.FusedPlyPath() + " --StereoFusion.num_threads 1",
      log_path);
  ASSERT_EQ(code, 0) << ReadTextFile(log_path);

  const std::vector<PlyPoint> points = ReadPlyPoints(workspace.FusedPlyPath());
  LOG(INFO) << "stereo_fusion fused " << points.size() << " points";
  ASSERT_GT(points.size(), 5000u) << ReadTextFile(log_path);

  // The model as colmap read it: its image order defines image_idx.
  const Reconstruction model = workspace.ReadModel();
  ASSERT_EQ(model.images.size(), 5u);
  for (size_t i = 0; i < model.images.size(); ++i) {
    ASSERT_EQ(model.images[i].image_id, scene.model.images[i].image_id);
  }
  const FusedVisibility visibility =
      ReadFusedVis(workspace.FusedVisPath(), points.size());
  CheckFusedVisIndices(visibility, model.images.size(),
                       workspace.FusedVisPath());

  constexpr double kBorderPx = 5.0;
  double max_distance = 0;
  size_t num_wall = 0;
  size_t num_views = 0;
  // Points outside some image's view make the per-index check below
  // discriminating: a wrong image_idx reading would list such images.
  size_t num_partially_seen = 0;
  for (size_t p = 0; p < points.size(); ++p) {
    const Eigen::Vector3d point = points[p].xyz.cast<double>();
    const double distance = SurfaceDistance(point);
    max_distance = std::max(max_distance, distance);
    const Eigen::Vector3d normal = points[p].normal.cast<double>();
    ASSERT_NEAR(normal.norm(), 1.0, 1e-3) << p;
    const bool on_wall = std::abs(point.x() - kWallX) < std::abs(point.z());
    num_wall += on_wall ? 1 : 0;
    const Eigen::Vector3d expected_normal =
        on_wall ? ScenePlanes()[1].normal : ScenePlanes()[0].normal;
    ASSERT_GT(normal.dot(expected_normal), 0.999) << p;

    size_t num_seeing = 0;
    for (const Image& image : model.images) {
      const Eigen::Vector3d pixel =
          SceneK() * (image.cam_from_world * point).normalized();
      const Eigen::Vector2d xy = pixel.head<2>() / pixel.z();
      num_seeing += (xy.x() >= 0 && xy.x() < kWidth && xy.y() >= 0 &&
                     xy.y() < kHeight)
                        ? 1
                        : 0;
    }
    num_partially_seen += num_seeing < model.images.size() ? 1 : 0;

    ASSERT_FALSE(visibility[p].empty()) << p;
    num_views += visibility[p].size();
    for (const uint32_t image_idx : visibility[p]) {
      // Each listed image sees the point, in front of it and facing it.
      const Image& image = model.images[image_idx];
      const Eigen::Vector3d in_cam = image.cam_from_world * point;
      const Eigen::Vector3d pixel = SceneK() * in_cam / in_cam.z();
      ASSERT_GT(in_cam.z(), 0) << p;
      // Fused positions are medians over pixels within fusion's 2 px
      // reprojection tolerance, so allow a few pixels beyond the border.
      ASSERT_GT(pixel.x(), -kBorderPx) << p << " in image " << image_idx;
      ASSERT_LT(pixel.x(), kWidth + kBorderPx) << p << " in image " << image_idx;
      ASSERT_GT(pixel.y(), -kBorderPx) << p << " in image " << image_idx;
      ASSERT_LT(pixel.y(), kHeight + kBorderPx)
          << p << " in image " << image_idx;
      ASSERT_GT(normal.dot(image.ProjectionCenter() - point), 0) << p;
    }
  }
  LOG(INFO) << "max distance to the surface " << max_distance << " m, "
            << static_cast<double>(num_views) / points.size()
            << " views per point, " << num_partially_seen
            << " points outside some image";
  EXPECT_LT(max_distance, 1e-4);
  EXPECT_GT(num_partially_seen, points.size() / 10);
  EXPECT_GT(num_wall, 500u);
  EXPECT_GT(points.size() - num_wall, 500u);
  EXPECT_GT(static_cast<double>(num_views) / points.size(), 2.0);

  // Our writer reproduces colmap's fused.ply byte for byte.
  const std::string rewritten = JoinPaths(root, "rewritten.ply");
  WriteColmapPlyPoints(rewritten, points);
  EXPECT_EQ(ReadTextFile(rewritten), ReadTextFile(workspace.FusedPlyPath()));
  // And our .vis writer reproduces colmap's.
  const std::string vis_copy = JoinPaths(root, "rewritten.ply.vis");
  WriteFusedVis(vis_copy, visibility);
  EXPECT_EQ(ReadTextFile(vis_copy), ReadTextFile(workspace.FusedVisPath()));

  // Validate names what is missing or inconsistent.
  const std::string normal_path =
      workspace.NormalMapPath(scene.names[2], DenseMapType::kGeometric);
  const std::string moved = normal_path + ".moved";
  std::filesystem::rename(normal_path, moved);
  ExpectErrorContaining([&] { workspace.Validate(DenseMapType::kGeometric); },
                        normal_path);
  // A depth map in the normal map's place has the wrong channel count.
  std::filesystem::copy_file(
      workspace.DepthMapPath(scene.names[2], DenseMapType::kGeometric),
      normal_path);
  ExpectErrorContaining([&] { workspace.Validate(DenseMapType::kGeometric); },
                        normal_path);
  std::filesystem::remove(normal_path);
  std::filesystem::rename(moved, normal_path);
  workspace.Validate(DenseMapType::kGeometric);
  WriteFusionConfig(workspace.FusionConfigPath(), {"cam/unknown.png"});
  ExpectErrorContaining([&] { workspace.Validate(DenseMapType::kGeometric); },
                        "cam/unknown.png");
}

}  // namespace
}  // namespace colmap_lidar
