#include "src/eval/real_data_evaluator.h"

#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"
#include "src/lidar/lidar_test_scene.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {

// A scan of the street scene (fresh samples per scan, as a real sensor
// never hits one point twice) seen from `world_from_lidar`, with range
// noise, up to 30 m.
LidarScan MakeScan(const Rigid3d& world_from_lidar, double noise_m,
                   unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_m);
  const Rigid3d lidar_from_world = world_from_lidar.Inverse();
  LidarScan scan;
  for (const Eigen::Vector3d& point : SampleStreetScene(seed, 10.0)) {
    const Eigen::Vector3d p = lidar_from_world * point;
    if (p.norm() < 30.0) {
      scan.points.push_back((p + noise(rng) * p.normalized()).cast<float>());
    }
  }
  return scan;
}

// Frames driving along x with a slight turn.
std::vector<Rigid3d> TruePoses(int num_frames) {
  std::vector<Rigid3d> poses;
  for (int k = 0; k < num_frames; ++k) {
    poses.push_back(PoseFromYawRoll(3.0 * k, 0.0, {1.2 * k, 0.1 * k, 0.0}));
  }
  return poses;
}

struct Recording {
  std::vector<LidarScan> scans;
  std::vector<RealDataFrame> frames;
};

// Refined poses = the truth; priors = the truth with 0.3 m / 3 deg errors.
Recording MakeRecording(int num_frames) {
  Recording recording;
  const std::vector<Rigid3d> truth = TruePoses(num_frames);
  for (size_t k = 0; k < truth.size(); ++k) {
    recording.scans.push_back(MakeScan(truth[k], 0.01, 100 + k));
  }
  for (size_t k = 0; k < truth.size(); ++k) {
    RealDataFrame frame;
    frame.name = "frame" + std::to_string(k);
    frame.scan = &recording.scans[k];
    frame.refined_world_from_lidar = truth[k];
    frame.has_prior = true;
    const double sign = (k % 2 == 0) ? 1.0 : -1.0;
    frame.prior_world_from_lidar =
        truth[k] * PoseFromYawRoll(3.0 * sign, 0.0, {0.2 * sign, 0.2, 0.1});
    recording.frames.push_back(frame);
  }
  return recording;
}

RealDataEvaluationOptions TestOptions() {
  RealDataEvaluationOptions options;
  options.num_threads = 2;
  options.crispness_max_queries_per_scan = 3000;
  return options;
}

TEST(RealDataEvaluator, CrispWithTruePosesAndBlurredByAMisposedScan) {
  const Recording recording = MakeRecording(5);
  const RealDataEvaluationOptions options = TestOptions();
  const double voxel = CrispnessVoxelSize(recording.scans[0], options);
  EXPECT_GE(voxel, 0.05);
  EXPECT_LE(voxel, 0.3);
  std::vector<std::vector<Eigen::Vector3d>> thinned;
  std::vector<Rigid3d> poses;
  for (const RealDataFrame& frame : recording.frames) {
    thinned.push_back(ThinScan(*frame.scan, voxel, options));
    poses.push_back(frame.refined_world_from_lidar);
  }
  const double radius = options.crispness_radius_voxels * voxel;
  const CrispnessStats crisp =
      EvaluateCrispness(thinned, poses, radius, options);
  EXPECT_GT(crisp.coverage, 0.5);
  EXPECT_LT(crisp.median_m, 0.02);
  EXPECT_LT(crisp.p90_m, 0.05);

  // Frame 2 off by 0.15 m and 1.5 deg.
  poses[2] = poses[2] * PoseFromYawRoll(1.5, 0.0, {0.1, 0.1, 0.1});
  const CrispnessStats blurred =
      EvaluateCrispness(thinned, poses, radius, options);
  ASSERT_EQ(blurred.frame_median_m.size(), 5u);
  EXPECT_GT(blurred.frame_median_m[2], 3.0 * crisp.frame_median_m[2]);
  EXPECT_GT(blurred.frame_median_m[2], 0.05);
  EXPECT_GT(blurred.median_m, crisp.median_m);
  EXPECT_GT(blurred.p90_m, 1.5 * crisp.p90_m);

  EXPECT_THROW(EvaluateCrispness({thinned[0]}, {poses[0]}, radius, options),
               Error);
}

TEST(RealDataEvaluator, TrajectoryAgreesWithOdometryUnlessStretched) {
  Recording recording = MakeRecording(4);
  const RealDataEvaluationOptions options = TestOptions();
  const TrajectoryComparison good =
      CompareTrajectoryWithOdometry(recording.frames, options);
  ASSERT_EQ(good.num_steps, 3u);
  EXPECT_NEAR(good.odometry_length_m, good.refined_length_m, 0.03);
  EXPECT_NEAR(good.length_ratio, 1.0, 0.01);
  EXPECT_LT(good.max_step_difference_m, 0.02);
  EXPECT_EQ(good.num_failed_registrations, 0u);
  EXPECT_GT(good.prior_length_m, 0.0);

  // The refined trajectory 30 % too long (a wrong scale), one step more so.
  for (RealDataFrame& frame : recording.frames) {
    frame.refined_world_from_lidar.translation *= 1.3;
  }
  recording.frames[3].refined_world_from_lidar.translation.x() += 0.5;
  const TrajectoryComparison stretched =
      CompareTrajectoryWithOdometry(recording.frames, options);
  EXPECT_GT(stretched.length_ratio, 1.3);
  EXPECT_GT(stretched.max_step_difference_m, 0.5);
  EXPECT_EQ(stretched.max_step_difference_frame, "frame2");
  EXPECT_NEAR(stretched.odometry_length_m, good.odometry_length_m, 1e-6);
}

// A 10 x 10 m square at z = 0; LIDAR points on its left half and 0.3 m
// above its right half.
TEST(RealDataEvaluator, MeshVsLidarShares) {
  const std::vector<Eigen::Vector3d> vertices = {
      {0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  const std::vector<Eigen::Vector3i> triangles = {{0, 1, 2}, {0, 2, 3}};
  std::vector<Eigen::Vector3d> lidar;
  for (double x = 0.025; x < 10.0; x += 0.05) {
    for (double y = 0.025; y < 10.0; y += 0.05) {
      lidar.emplace_back(x, y, x < 5.0 ? 0.0 : 0.3);
    }
  }
  const RealDataEvaluationOptions options = TestOptions();
  const MeshVsLidar result =
      EvaluateMeshVsLidar(vertices, triangles, lidar, options);
  ASSERT_EQ(result.thresholds_m.size(), 2u);
  EXPECT_NEAR(result.mesh_area_m2, 100.0, 1e-9);
  EXPECT_NEAR(result.num_mesh_samples, 10000u, 1u);
  EXPECT_NEAR(result.lidar_within[0], 0.5, 0.01);   // 0.1 m
  EXPECT_NEAR(result.lidar_within[1], 1.0, 1e-9);   // 0.5 m
  EXPECT_NEAR(result.mesh_within[0], 0.5, 0.03);
  EXPECT_NEAR(result.mesh_within[1], 1.0, 1e-9);
  EXPECT_THROW(EvaluateMeshVsLidar(vertices, {}, lidar, options), Error);
  EXPECT_TRUE(result.lidar_in_view_within.empty());

  // A camera 5 m above (2.5, 5) looking straight down (53 deg field) sees
  // x in [0, 5), y in (2.5, 7.5]: 100 x 100 points of the grid, all on the
  // mesh (the lifted half x >= 5 is outside its image).
  Reconstruction model;
  model.cameras[1] =
      Camera::FromModelName("PINHOLE", 100, 100, {100, 100, 50, 50});
  Image image;
  image.image_id = 1;
  image.camera_id = 1;
  image.name = "down.png";
  // Camera z (forward) = world -z, x = world x, y = world -y.
  image.cam_from_world.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  image.cam_from_world.translation =
      -(image.cam_from_world.rotation * Eigen::Vector3d(2.5, 5.0, 5.0));
  model.images.push_back(image);
  const std::vector<bool> in_view = InCameraView(model, lidar, 20.0);
  const MeshVsLidar viewed =
      EvaluateMeshVsLidar(vertices, triangles, lidar, options, in_view);
  EXPECT_EQ(viewed.num_lidar_points_in_view, 100u * 100u);
  ASSERT_EQ(viewed.lidar_in_view_within.size(), 2u);
  EXPECT_DOUBLE_EQ(viewed.lidar_in_view_within[0], 1.0);
  EXPECT_EQ(InCameraView(model, lidar, 4.0),
            std::vector<bool>(lidar.size(), false));  // All 5 m deep.
  EXPECT_THROW(EvaluateMeshVsLidar(vertices, triangles, lidar, options,
                                   std::vector<bool>(3, true)),
               Error);
}

TEST(RealDataEvaluator, WritesTheKeysTheMatrixTableReads) {
  const Recording recording = MakeRecording(3);
  RealDataEvaluation evaluation =
      EvaluateRealDataFrames(recording.frames, TestOptions());
  EXPECT_TRUE(evaluation.has_prior);
  // Priors 0.2-0.3 m off, near the radius: fewer planes found (the median
  // alone saturates, and the ground plane hides shifts along it).
  EXPECT_LT(evaluation.prior_crispness.coverage,
            evaluation.refined_crispness.coverage);
  // The odometry chain stacks the scans as well as the true poses.
  EXPECT_LT(evaluation.odometry_crispness.median_m,
            1.2 * evaluation.refined_crispness.median_m);
  evaluation.has_mesh = true;
  evaluation.mesh_vs_lidar.thresholds_m = {0.1, 0.5};
  evaluation.mesh_vs_lidar.lidar_within = {0.25, 0.5};
  evaluation.mesh_vs_lidar.mesh_within = {0.75, 1.0};
  const std::string path =
      (std::filesystem::temp_directory_path() /
       ("real_data_evaluator_test_" + std::to_string(::getpid()) + ".json"))
          .string();
  WriteRealDataJson(path, evaluation);
  const Json json = ReadJsonFile(path);
  std::filesystem::remove(path);
  EXPECT_EQ(json.at("num_frames"), evaluation.num_frames);
  const Json& crispness = json.at("crispness");
  for (const char* key :
       {"voxel_size_m", "radius_m", "num_queries", "refined_median_m",
        "refined_p90_m", "refined_coverage", "refined_num_planes",
        "refined_frame_median_m", "prior_median_m", "odometry_median_m"}) {
    EXPECT_TRUE(crispness.contains(key)) << key;
  }
  EXPECT_EQ(crispness.at("refined_median_m").get<double>(),
            evaluation.refined_crispness.median_m);
  EXPECT_EQ(crispness.at("prior_frame_median_m"),
            Json(evaluation.prior_crispness.frame_median_m));
  for (const char* key :
       {"odometry_length_m", "refined_length_m", "prior_length_m",
        "length_ratio", "max_step_difference_m",
        "max_step_difference_frame", "fitness"}) {
    EXPECT_TRUE(json.at("trajectory").contains(key)) << key;
  }
  EXPECT_EQ(json.at("trajectory").at("length_ratio").get<double>(),
            evaluation.trajectory.length_ratio);
  const Json& mesh = json.at("mesh_vs_lidar");
  EXPECT_EQ(mesh.at("lidar_within_0.1m"), 0.25);
  EXPECT_EQ(mesh.at("mesh_within_0.1m"), 0.75);
  EXPECT_EQ(mesh.at("lidar_within_0.5m"), 0.5);
  EXPECT_EQ(mesh.at("mesh_within_0.5m"), 1.0);
  EXPECT_FALSE(FormatRealDataEvaluation(evaluation).empty());
}

// The camera looks along the LIDAR's x (forward), 20 cm above and 10 cm
// behind it: cam x = -lidar y, cam y = -lidar z, cam z = lidar x.
Rigid3d CamFromLidar() {
  Eigen::Matrix3d rotation;
  rotation << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  Rigid3d cam_from_lidar;
  cam_from_lidar.rotation = Eigen::Quaterniond(rotation);
  cam_from_lidar.translation = Eigen::Vector3d(0.0, 0.2, -0.1);
  return cam_from_lidar;
}

std::string ErrorOf(const std::function<void()>& body) {
  try {
    body();
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

// What EvaluateRealData reads, written into a workspace folder: the
// recording's scans as PLYs under lidar/ (paths relative to the database),
// the database (images, ext_lidar_scans with cam_from_lidar), the refined
// and prior models (images posed as camera = LIDAR pose * lidar_from_cam),
// a ground-plane mesh (z = -1.7, the street scene's ground, x in [-10, 30],
// y in [-10, 10]) and a LIDAR cloud on it for x < 10 and 0.3 m above it
// beyond. The refined model also has an image without a scan (skipped).
struct RealDataFiles {
  std::string dir;
  std::vector<Eigen::Vector3d> mesh_vertices;
  std::vector<Eigen::Vector3i> mesh_triangles;
  std::vector<Eigen::Vector3d> lidar_cloud;
  RealDataEvaluationInput input;
};

RealDataFiles WriteRealDataFiles(const Recording& recording) {
  const std::string dir = testing::CreateTestDir();
  CreateDirIfNotExists(JoinPaths(dir, "lidar"));
  RealDataFiles files;
  files.dir = dir;
  RealDataEvaluationInput& input = files.input;
  input.database_path = JoinPaths(dir, "database.db");
  input.prior_model_path = JoinPaths(dir, "sparse/prior");
  input.refined_model_path = JoinPaths(dir, "sparse/refined");
  input.mesh_path = JoinPaths(dir, "mesh.ply");
  input.lidar_cloud_path = JoinPaths(dir, "lidar_fused.ply");

  Database database(input.database_path);
  Camera camera =
      Camera::FromModelName("PINHOLE", 200, 100, {100, 100, 100, 50});
  camera.camera_id = database.WriteCamera(camera);
  Reconstruction refined;
  refined.cameras[camera.camera_id] = camera;
  Reconstruction prior = refined;
  const size_t num_frames = recording.frames.size();
  for (size_t k = 0; k <= num_frames; ++k) {
    DatabaseImage db_image;
    db_image.image_id = static_cast<image_t>(k + 1);
    db_image.name = "00000" + std::to_string(k) + ".png";
    db_image.camera_id = camera.camera_id;
    database.WriteImage(db_image);
    Image image;
    image.image_id = db_image.image_id;
    image.camera_id = camera.camera_id;
    image.name = db_image.name;
    if (k == num_frames) {
      // Registered, but without a scan.
      refined.images.push_back(image);
      break;
    }
    const RealDataFrame& frame = recording.frames[k];
    const std::string relative_path =
        "lidar/00000" + std::to_string(k) + ".ply";
    WriteLidarScanPly(JoinPaths(dir, relative_path), *frame.scan);
    LidarScanRecord record;
    record.image_id = db_image.image_id;
    record.path = relative_path;
    record.num_points = frame.scan->size();
    record.cam_from_lidar = CamFromLidar();
    database.WriteLidarScan(record);
    image.cam_from_world =
        CamFromLidar() * frame.refined_world_from_lidar.Inverse();
    refined.images.push_back(image);
    image.cam_from_world =
        CamFromLidar() * frame.prior_world_from_lidar.Inverse();
    prior.images.push_back(image);
  }
  WriteReconstruction(input.refined_model_path, refined, ModelFormat::kBinary);
  WriteReconstruction(input.prior_model_path, prior, ModelFormat::kBinary);

  files.mesh_vertices = {
      {-10, -10, -1.7}, {30, -10, -1.7}, {30, 10, -1.7}, {-10, 10, -1.7}};
  files.mesh_triangles = {{0, 1, 2}, {0, 2, 3}};
  testing::WriteXyzPly(input.mesh_path, files.mesh_vertices,
                       {{0, 1, 2}, {0, 2, 3}});
  for (double x = -9.9; x < 30.0; x += 0.2) {
    for (double y = -9.9; y < 10.0; y += 0.2) {
      files.lidar_cloud.emplace_back(x, y, x < 10.0 ? -1.7 : -1.4);
    }
  }
  testing::WriteXyzPly(input.lidar_cloud_path, files.lidar_cloud);
  return files;
}

// The workspace-level entry reads the scans, poses and mesh back and gives
// the figures of the frames-level evaluation of the same recording, and
// the mesh figures of the cloud it was given; a missing or corrupt input
// is named.
TEST(RealDataEvaluator, ReadsTheWorkspaceFilesAndNamesABadOne) {
  const Recording recording = MakeRecording(3);
  const RealDataFiles files = WriteRealDataFiles(recording);
  RealDataEvaluationOptions options = TestOptions();
  const RealDataEvaluation in_memory =
      EvaluateRealDataFrames(recording.frames, options);
  const RealDataEvaluation evaluation = EvaluateRealData(files.input, options);

  EXPECT_EQ(evaluation.num_frames, 3u);  // Not the image without a scan.
  EXPECT_TRUE(evaluation.has_prior);
  ASSERT_TRUE(evaluation.has_trajectory);
  EXPECT_EQ(evaluation.crispness_voxel_size_m,
            in_memory.crispness_voxel_size_m);
  EXPECT_EQ(evaluation.refined_crispness.num_queries,
            in_memory.refined_crispness.num_queries);
  EXPECT_NEAR(evaluation.refined_crispness.median_m,
              in_memory.refined_crispness.median_m, 1e-6);
  EXPECT_NEAR(evaluation.prior_crispness.median_m,
              in_memory.prior_crispness.median_m, 1e-6);
  EXPECT_LT(evaluation.refined_crispness.median_m, 0.02);
  // Priors 0.2-0.3 m off: fewer planes found than with the true poses.
  EXPECT_LT(evaluation.prior_crispness.coverage,
            evaluation.refined_crispness.coverage);
  EXPECT_EQ(evaluation.trajectory.num_steps, 2u);
  EXPECT_NEAR(evaluation.trajectory.refined_length_m,
              in_memory.trajectory.refined_length_m, 1e-9);
  EXPECT_NEAR(evaluation.trajectory.length_ratio, 1.0, 0.01);
  EXPECT_EQ(evaluation.trajectory.step_frames[0], "000000.png");

  // The mesh figures: those of the in-memory function on the same data,
  // with the cameras' view of the refined model.
  ASSERT_TRUE(evaluation.has_mesh);
  const MeshVsLidar direct = EvaluateMeshVsLidar(
      files.mesh_vertices, files.mesh_triangles, files.lidar_cloud, options,
      InCameraView(ReadReconstruction(files.input.refined_model_path),
                   files.lidar_cloud, options.mesh_view_max_depth_m));
  const MeshVsLidar& mesh = evaluation.mesh_vs_lidar;
  EXPECT_EQ(mesh.num_lidar_points, files.lidar_cloud.size());
  EXPECT_EQ(mesh.lidar_within, direct.lidar_within);
  EXPECT_EQ(mesh.mesh_within, direct.mesh_within);
  EXPECT_EQ(mesh.num_lidar_points_in_view, direct.num_lidar_points_in_view);
  EXPECT_GT(mesh.num_lidar_points_in_view, 0u);
  EXPECT_LT(mesh.num_lidar_points_in_view, mesh.num_lidar_points);
  EXPECT_EQ(mesh.lidar_in_view_within, direct.lidar_in_view_within);
  // The cloud lies on the mesh for x < 10 (half of it), 0.3 m off beyond.
  ASSERT_EQ(mesh.thresholds_m, std::vector<double>({0.1, 0.5}));
  EXPECT_NEAR(mesh.lidar_within[0], 0.5, 0.01);
  EXPECT_DOUBLE_EQ(mesh.lidar_within[1], 1.0);
  EXPECT_NEAR(mesh.mesh_area_m2, 800.0, 1e-9);

  // Without the cloud (or the mesh): no mesh figures.
  RealDataEvaluationInput input = files.input;
  input.lidar_cloud_path = JoinPaths(testing::CreateTestDir(), "none.ply");
  EXPECT_FALSE(EvaluateRealData(input, options).has_mesh);

  // Missing inputs.
  input = files.input;
  input.database_path = JoinPaths(testing::CreateTestDir(), "none.db");
  EXPECT_NE(ErrorOf([&] { EvaluateRealData(input, options); }).find("none.db"),
            std::string::npos);
  input = files.input;
  input.refined_model_path = JoinPaths(testing::CreateTestDir(), "none");
  EXPECT_NE(ErrorOf([&] {
              EvaluateRealData(input, options);
            }).find("No refined model in " + input.refined_model_path),
            std::string::npos);
  // Only one frame has a scan when the model is the prior's first image.
  input = files.input;
  Reconstruction one = ReadReconstruction(files.input.prior_model_path);
  one.images.resize(1);
  input.refined_model_path = JoinPaths(testing::CreateTestDir(), "one");
  WriteReconstruction(input.refined_model_path, one, ModelFormat::kBinary);
  EXPECT_NE(ErrorOf([&] {
              EvaluateRealData(input, options);
            }).find("1 images of the refined model"),
            std::string::npos);
  options.crispness_radius_voxels = 1.0;
  EXPECT_THROW(EvaluateRealData(files.input, options), Error);

  // Corrupt files: a scan, then the mesh (read after the scans' figures).
  const RealDataEvaluationOptions valid = TestOptions();
  const std::string scan_path = JoinPaths(files.dir, "lidar/000001.ply");
  std::ofstream(scan_path) << "ply\nformat ascii 1.0\nelement vertex 2\n";
  EXPECT_NE(
      ErrorOf([&] { EvaluateRealData(files.input, valid); }).find("000001.ply"),
      std::string::npos);
  WriteLidarScanPly(scan_path, *recording.frames[1].scan);
  std::ofstream(files.input.mesh_path) << "ply\nformat ascii 1.0\nelement";
  EXPECT_NE(ErrorOf([&] {
              EvaluateRealData(files.input, valid);
            }).find(files.input.mesh_path),
            std::string::npos);
}

TEST(RealDataEvaluator, RejectsBadOptions) {
  RealDataEvaluationOptions options;
  EXPECT_TRUE(options.Check());
  options.crispness_radius_voxels = 1.0;
  EXPECT_FALSE(options.Check());
  options = RealDataEvaluationOptions();
  options.mesh_thresholds_m = {0.5, 0.1};
  EXPECT_FALSE(options.Check());
  options = RealDataEvaluationOptions();
  options.registration.max_range_m = -1.0;
  EXPECT_FALSE(options.Check());
}

}  // namespace
}  // namespace colmap_lidar
