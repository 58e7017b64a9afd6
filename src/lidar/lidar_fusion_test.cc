#include "src/lidar/lidar_fusion.h"

#include <cmath>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {

// Points on the plane z = 2.05 (world, mid-voxel), seen by scanners below it: the normals
// must be (0, 0, -1) (facing the scanners).
LidarScan PlaneScan(const Rigid3d& world_from_lidar, int n, double half_size,
                    std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(-half_size, half_size);
  const Rigid3d lidar_from_world = world_from_lidar.Inverse();
  LidarScan scan;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d point_in_world(uniform(*rng), uniform(*rng), 2.05);
    scan.points.push_back((lidar_from_world * point_in_world).cast<float>());
  }
  return scan;
}

TEST(LidarFusion, CountsNormalsAndVisibilityOnAPlane) {
  std::mt19937 rng(3);
  Rigid3d world_from_lidar0;
  Rigid3d world_from_lidar1(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())),
      Eigen::Vector3d(0.5, 0.0, 0.1));
  const LidarScan scan0 = PlaneScan(world_from_lidar0, 20000, 1.0, &rng);
  const LidarScan scan1 = PlaneScan(world_from_lidar1, 10000, 0.5, &rng);
  LidarFusionOptions options;
  options.voxel_size_m = 0.1;
  const FusedLidarCloud cloud = FuseLidarScans(
      {{3, &scan0, world_from_lidar0}, {7, &scan1, world_from_lidar1}},
      options);

  // 2 m x 2 m at 10 cm: 20 x 20 voxels in one layer.
  EXPECT_EQ(cloud.size(), 400u);
  size_t total = 0;
  size_t num_seen_by_both = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    total += cloud.counts[i];
    EXPECT_NEAR(cloud.points[i].z(), 2.05f, 1e-4);
    EXPECT_NEAR(cloud.normals[i].z(), -1.0f, 1e-3) << i;
    ASSERT_FALSE(cloud.visibility[i].empty());
    for (uint32_t idx : cloud.visibility[i]) {
      EXPECT_TRUE(idx == 3 || idx == 7);
    }
    if (cloud.visibility[i].size() == 2) {
      ++num_seen_by_both;
      // The frame with the most points first.
      const double x = cloud.points[i].x();
      const double y = cloud.points[i].y();
      if (std::abs(x) < 0.4 && std::abs(y) < 0.4) {
        EXPECT_EQ(cloud.visibility[i][0], 7u);  // 10000 / 1 m^2 > 20000 / 4 m^2
      }
    }
  }
  EXPECT_EQ(total, 30000u);
  EXPECT_EQ(num_seen_by_both, 100u);  // The inner 1 m x 1 m.

  // Density: a 10 cm voxel of the 2 m square gets ~50 points of scan0.
  options.min_points_per_voxel = 1000;
  EXPECT_EQ(FuseLidarScans({{0, &scan0, world_from_lidar0}}, options).size(),
            0u);
}

// One ring of a sparse scanner crossing a wall: a line of voxel centroids,
// whose plane (and normal) is undetermined; the normal stays unknown unless
// the test is off. A second ring 6 cm above spans the plane again.
TEST(LidarFusion, LineOfCentroidsHasNoNormal) {
  LidarScan ring;
  for (int i = 0; i < 40; ++i) {  // The wall z = 2.05, along x at y = 0.01.
    ring.points.emplace_back(-1.0f + 0.05f * i + 0.025f, 0.01f, 2.05f);
  }
  LidarFusionOptions options;
  options.voxel_size_m = 0.05;
  const Rigid3d world_from_lidar;
  FusedLidarCloud cloud =
      FuseLidarScans({{0, &ring, world_from_lidar}}, options);
  ASSERT_EQ(cloud.size(), 40u);
  for (const Eigen::Vector3f& normal : cloud.normals) {
    EXPECT_EQ(normal, Eigen::Vector3f::Zero());
  }
  options.normal_min_eigenvalue_ratio = 0.0;
  cloud = FuseLidarScans({{0, &ring, world_from_lidar}}, options);
  size_t num_known = 0;
  for (const Eigen::Vector3f& normal : cloud.normals) {
    num_known += normal.squaredNorm() > 0.5f ? 1 : 0;
  }
  EXPECT_GT(num_known, 30u);  // Some arbitrary direction across the line.

  options.normal_min_eigenvalue_ratio = 0.1;
  LidarScan two_rings = ring;
  for (const Eigen::Vector3f& point : ring.points) {
    two_rings.points.push_back(point + Eigen::Vector3f(0, 0.06f, 0));
  }
  cloud = FuseLidarScans({{0, &two_rings, world_from_lidar}}, options);
  ASSERT_EQ(cloud.size(), 80u);
  for (const Eigen::Vector3f& normal : cloud.normals) {
    EXPECT_NEAR(std::abs(normal.z()), 1.0f, 1e-3);
  }
}

TEST(LidarFusion, CapsVisibilityAndSkipsRanges) {
  std::mt19937 rng(4);
  std::vector<LidarScan> scans;
  for (int i = 0; i < 5; ++i) {
    scans.push_back(PlaneScan(Rigid3d(), 500, 0.2, &rng));
  }
  std::vector<LidarFusionInput> inputs;
  for (int i = 0; i < 5; ++i) {
    inputs.push_back({static_cast<uint32_t>(i), &scans[i], Rigid3d()});
  }
  LidarFusionOptions options;
  options.voxel_size_m = 1.0;
  options.max_num_visible_images = 2;
  FusedLidarCloud cloud = FuseLidarScans(inputs, options);
  ASSERT_GE(cloud.size(), 1u);
  for (const auto& vis : cloud.visibility) {
    EXPECT_LE(vis.size(), 2u);
  }
  options.max_range_m = 1.5;  // All points are >= 2 m away.
  EXPECT_EQ(FuseLidarScans(inputs, options).size(), 0u);
  options.voxel_size_m = 0;
  EXPECT_FALSE(options.Check());
  options.voxel_size_m = 1.0;
  options.normal_min_eigenvalue_ratio = 1.0;  // [0, 1).
  EXPECT_FALSE(options.Check());
  options.normal_min_eigenvalue_ratio = -0.1;
  EXPECT_FALSE(options.Check());
}

TEST(LidarFusion, FilesRoundTrip) {
  std::mt19937 rng(5);
  const LidarScan scan = PlaneScan(Rigid3d(), 2000, 0.5, &rng);
  LidarFusionOptions options;
  options.voxel_size_m = 0.1;
  const FusedLidarCloud cloud =
      FuseLidarScans({{2, &scan, Rigid3d()}}, options);
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "lidar_fused.ply");
  WriteFusedLidarCloud(path, cloud);
  const FusedLidarCloud read = ReadFusedLidarCloud(path);
  ASSERT_EQ(read.size(), cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(read.points[i], cloud.points[i]);
    EXPECT_EQ(read.normals[i], cloud.normals[i]);
    EXPECT_EQ(read.counts[i], cloud.counts[i]);
    EXPECT_EQ(read.visibility[i], cloud.visibility[i]);
  }
  const std::string header = ReadTextFile(path).substr(0, 300);
  EXPECT_NE(header.find("property uint count"), std::string::npos) << header;

  WriteLidarOrigins(JoinPaths(dir, "lidar_origins.txt"),
                    {{"a.png", Eigen::Vector3d(1, 2, 3.5)}});
  const auto origins = ReadLidarOriginList(JoinPaths(dir, "lidar_origins.txt"));
  ASSERT_EQ(origins.size(), 1u);
  EXPECT_EQ(origins[0].image_name, "a.png");
  EXPECT_EQ(origins[0].position_in_world, Eigen::Vector3d(1, 2, 3.5));
}


// ---- RunLidarFuser on files: a database with ext_lidar_scans, the scans as
// PLY beside it and a sparse model, written with the project's writers.

// Frames of the workspace below: a.png sees the left half of the plane
// z = 2.05 (x in [-0.98, -0.02]), b.png the right half (x in [0.02, 0.98]),
// both y in [-0.98, 0.98]; c.png has no scan. At 10 cm voxels each half is
// 10 x 20 voxels in one layer.
constexpr int kPointsPerScan = 20000;
const char* const kFrameNames[3] = {"a.png", "b.png", "c.png"};

Rigid3d CamFromLidar() {
  return Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX())),
      Eigen::Vector3d(0.0, -0.1, 0.05));
}

Rigid3d WorldFromCam(int frame) {
  return Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.2 * frame, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(0.3 * frame, -0.2, 0.1 * frame));
}

// Points of the plane z = 2.05 with x in [x_min, x_max], |y| <= 0.98, in the
// frame of a LIDAR at `world_from_lidar`.
LidarScan HalfPlaneScan(const Rigid3d& world_from_lidar, double x_min,
                        double x_max, std::mt19937* rng) {
  std::uniform_real_distribution<double> x(x_min, x_max);
  std::uniform_real_distribution<double> y(-0.98, 0.98);
  const Rigid3d lidar_from_world = world_from_lidar.Inverse();
  LidarScan scan;
  for (int i = 0; i < kPointsPerScan; ++i) {
    const Eigen::Vector3d point_in_world(x(*rng), y(*rng), 2.05);
    scan.points.push_back((lidar_from_world * point_in_world).cast<float>());
  }
  return scan;
}

Reconstruction ModelWithImages(const Camera& camera,
                               const std::vector<int>& frames) {
  Reconstruction model;
  model.cameras[camera.camera_id] = camera;
  for (int frame : frames) {
    Image image;
    image.image_id = static_cast<image_t>(frame + 1);
    image.name = kFrameNames[frame];
    image.camera_id = camera.camera_id;
    image.cam_from_world = WorldFromCam(frame).Inverse();
    model.images.push_back(image);
  }
  return model;
}

// <root>/database.db (camera, images a b c, scans of a and b with paths
// relative to the database's folder), <root>/lidar/*.ply and the model
// <root>/sparse/0 with the images in the order a, b, c.
struct FuserWorkspace {
  std::string root;
  std::string database_path;
  std::string model_path;
  std::string output_path;
  Camera camera;
};

FuserWorkspace WriteFuserWorkspace() {
  FuserWorkspace ws;
  ws.root = testing::CreateTestDir();
  ws.database_path = JoinPaths(ws.root, "database.db");
  ws.model_path = JoinPaths(ws.root, "sparse/0");
  ws.output_path = JoinPaths(ws.root, "dense");
  CreateDirIfNotExists(JoinPaths(ws.root, "lidar"));
  std::mt19937 rng(6);
  Database database(ws.database_path);
  ws.camera = Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
  ws.camera.camera_id = database.WriteCamera(ws.camera);
  for (int frame = 0; frame < 3; ++frame) {
    DatabaseImage image;
    image.image_id = static_cast<image_t>(frame + 1);
    image.name = kFrameNames[frame];
    image.camera_id = ws.camera.camera_id;
    database.WriteImage(image);
    if (frame == 2) {
      continue;  // c.png: no scan.
    }
    const Rigid3d world_from_lidar = WorldFromCam(frame) * CamFromLidar();
    const LidarScan scan =
        frame == 0 ? HalfPlaneScan(world_from_lidar, -0.98, -0.02, &rng)
                   : HalfPlaneScan(world_from_lidar, 0.02, 0.98, &rng);
    const std::string relative_path =
        std::string("lidar/") + kFrameNames[frame] + ".ply";
    WriteLidarScanPly(JoinPaths(ws.root, relative_path), scan);
    LidarScanRecord record;
    record.image_id = image.image_id;
    record.path = relative_path;
    record.num_points = scan.size();
    record.cam_from_lidar = CamFromLidar();
    database.WriteLidarScan(record);
  }
  WriteReconstruction(ws.model_path, ModelWithImages(ws.camera, {0, 1, 2}),
                      ModelFormat::kBinary);
  return ws;
}

LidarFusionOptions TenCentimetreVoxels() {
  LidarFusionOptions options;
  options.voxel_size_m = 0.1;
  return options;
}

TEST(RunLidarFuser, WritesCloudVisibilityAndOriginsOfTheFramesWithScans) {
  const FuserWorkspace ws = WriteFuserWorkspace();
  const LidarFuserSummary summary =
      RunLidarFuser(ws.database_path, ws.model_path, ws.output_path,
                    TenCentimetreVoxels());
  EXPECT_EQ(summary.num_frames, 3u);
  EXPECT_EQ(summary.num_frames_without_scan, 1u);  // c.png
  EXPECT_EQ(summary.num_raw_points, 2u * kPointsPerScan);
  EXPECT_EQ(summary.num_voxels, 400u);

  const std::string ply_path = JoinPaths(ws.output_path, "lidar_fused.ply");
  ASSERT_TRUE(ExistsFile(ply_path));
  ASSERT_TRUE(ExistsFile(ply_path + ".vis"));
  const FusedLidarCloud cloud = ReadFusedLidarCloud(ply_path);
  ASSERT_EQ(cloud.size(), 400u);
  ASSERT_EQ(cloud.visibility.size(), 400u);
  size_t total = 0;
  size_t num_left = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    total += cloud.counts[i];
    EXPECT_NEAR(cloud.points[i].z(), 2.05f, 1e-4);
    EXPECT_NEAR(cloud.normals[i].z(), -1.0f, 1e-3) << i;
    // Without a dense model the .vis indices follow sparse/0: a=0, b=1.
    ASSERT_EQ(cloud.visibility[i].size(), 1u) << i;
    const bool left = cloud.points[i].x() < 0;
    num_left += left ? 1 : 0;
    EXPECT_EQ(cloud.visibility[i][0], left ? 0u : 1u) << i;
  }
  EXPECT_EQ(total, 2u * kPointsPerScan);
  EXPECT_EQ(num_left, 200u);

  // One origin per frame with a scan: world_from_cam * cam_from_lidar * 0.
  const std::vector<LidarOrigin> origins =
      ReadLidarOriginList(JoinPaths(ws.output_path, "lidar_origins.txt"));
  ASSERT_EQ(origins.size(), 2u);
  for (int frame = 0; frame < 2; ++frame) {
    EXPECT_EQ(origins[frame].image_name, kFrameNames[frame]);
    EXPECT_LT((origins[frame].position_in_world -
               (WorldFromCam(frame) * CamFromLidar()).translation)
                  .norm(),
              1e-9);
  }
}

TEST(RunLidarFuser, VisibilityFollowsTheDenseWorkspaceImageOrder) {
  const FuserWorkspace ws = WriteFuserWorkspace();
  // The dense workspace's model lists c, b, a: b is .vis index 1, a is 2.
  WriteReconstruction(JoinPaths(ws.output_path, "sparse"),
                      ModelWithImages(ws.camera, {2, 1, 0}),
                      ModelFormat::kBinary);
  const LidarFuserSummary summary =
      RunLidarFuser(ws.database_path, ws.model_path, ws.output_path,
                    TenCentimetreVoxels());
  EXPECT_EQ(summary.num_frames_without_scan, 1u);
  const FusedLidarCloud cloud =
      ReadFusedLidarCloud(JoinPaths(ws.output_path, "lidar_fused.ply"));
  ASSERT_EQ(cloud.size(), 400u);
  for (size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_EQ(cloud.visibility[i].size(), 1u) << i;
    EXPECT_EQ(cloud.visibility[i][0], cloud.points[i].x() < 0 ? 2u : 1u)
        << i;
  }
  // The origins come in the dense order too: b before a.
  const std::vector<LidarOrigin> origins =
      ReadLidarOriginList(JoinPaths(ws.output_path, "lidar_origins.txt"));
  ASSERT_EQ(origins.size(), 2u);
  EXPECT_EQ(origins[0].image_name, "b.png");
  EXPECT_EQ(origins[1].image_name, "a.png");
}

TEST(RunLidarFuser, CountsFramesOfTheModelWithoutScan) {
  const FuserWorkspace ws = WriteFuserWorkspace();
  {
    Database database(ws.database_path);
    database.DeleteLidarScan(2);  // b.png
  }
  const LidarFuserSummary summary =
      RunLidarFuser(ws.database_path, ws.model_path, ws.output_path,
                    TenCentimetreVoxels());
  EXPECT_EQ(summary.num_frames, 3u);
  EXPECT_EQ(summary.num_frames_without_scan, 2u);
  EXPECT_EQ(summary.num_raw_points, static_cast<size_t>(kPointsPerScan));
  EXPECT_EQ(summary.num_voxels, 200u);
  EXPECT_EQ(ReadLidarOriginList(
                JoinPaths(ws.output_path, "lidar_origins.txt")).size(),
            1u);
  // A model image that is not in the database counts as a frame without
  // scan as well.
  Reconstruction model = ReadReconstruction(ws.model_path);
  Image extra = model.images.back();
  extra.image_id = 10;
  extra.name = "not_in_database.png";
  model.images.push_back(extra);
  WriteReconstruction(ws.model_path, model, ModelFormat::kBinary);
  EXPECT_EQ(RunLidarFuser(ws.database_path, ws.model_path, ws.output_path,
                          TenCentimetreVoxels())
                .num_frames_without_scan,
            3u);
}

// Expects `run` to throw a colmap_lidar::Error whose message contains
// `needle`, and no output file in `output_path` afterwards.
template <typename Run>
void ExpectFailsWithoutOutput(const Run& run, const std::string& needle,
                              const std::string& output_path) {
  try {
    run();
    ADD_FAILURE() << "no exception; expected one naming " << needle;
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(needle), std::string::npos)
        << error.what();
  }
  for (const char* name :
       {"lidar_fused.ply", "lidar_fused.ply.vis", "lidar_origins.txt"}) {
    EXPECT_FALSE(ExistsFile(JoinPaths(output_path, name))) << name;
  }
}

TEST(RunLidarFuser, BadInputFailsNamingItAndWritesNothing) {
  const FuserWorkspace ws = WriteFuserWorkspace();
  // No model in the input folder.
  const std::string no_model = JoinPaths(ws.root, "sparse/none");
  CreateDirIfNotExists(no_model);
  ExpectFailsWithoutOutput(
      [&] {
        RunLidarFuser(ws.database_path, no_model, ws.output_path,
                      TenCentimetreVoxels());
      },
      no_model, ws.output_path);

  // Invalid options.
  LidarFusionOptions bad_options = TenCentimetreVoxels();
  bad_options.voxel_size_m = -1;
  ExpectFailsWithoutOutput(
      [&] {
        RunLidarFuser(ws.database_path, ws.model_path, ws.output_path,
                      bad_options);
      },
      "LidarFusion", ws.output_path);

  // A database that does not exist is refused, not created empty.
  const std::string no_database = JoinPaths(ws.root, "none.db");
  ExpectFailsWithoutOutput(
      [&] {
        RunLidarFuser(no_database, ws.model_path, ws.output_path,
                      TenCentimetreVoxels());
      },
      no_database, ws.output_path);
  EXPECT_FALSE(ExistsFile(no_database));

  // An image name that lidar_origins.txt cannot hold (COLMAP allows
  // spaces) fails before the cloud is written.
  Reconstruction spaced = ModelWithImages(ws.camera, {0, 1, 2});
  spaced.images[2].name = "c d.png";
  const std::string spaced_path = JoinPaths(ws.root, "sparse/spaced");
  WriteReconstruction(spaced_path, spaced, ModelFormat::kBinary);
  ExpectFailsWithoutOutput(
      [&] {
        RunLidarFuser(ws.database_path, spaced_path, ws.output_path,
                      TenCentimetreVoxels());
      },
      "c d.png", ws.output_path);

  // A scan file that the database names but that is gone.
  const std::string scan_b = JoinPaths(ws.root, "lidar/b.png.ply");
  ASSERT_TRUE(std::filesystem::remove(scan_b));
  ExpectFailsWithoutOutput(
      [&] {
        RunLidarFuser(ws.database_path, ws.model_path, ws.output_path,
                      TenCentimetreVoxels());
      },
      "b.png.ply", ws.output_path);

  // A scan file that is not a scan.
  WriteFileAtomically(
      scan_b, [](std::ostream& stream) { stream << "not a ply file\n"; },
      /*binary=*/false);
  ExpectFailsWithoutOutput(
      [&] {
        RunLidarFuser(ws.database_path, ws.model_path, ws.output_path,
                      TenCentimetreVoxels());
      },
      "b.png.ply", ws.output_path);
}

}  // namespace
}  // namespace colmap_lidar
