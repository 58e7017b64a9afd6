#include "src/synth/synthesize.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "colmap_ext/mvs/dense_maps.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/calibration.h"
#include "src/dataset/poses.h"
#include "src/lidar/scan_io.h"
#include "src/synth/scene_presets.h"

namespace colmap_lidar {
namespace {

SynthesisOptions TinyOptions() {
  SynthesisOptions options;
  options.num_frames = 3;
  options.image_width = 96;
  options.image_height = 64;
  options.supersampling = 1;
  options.lidar_rings = 16;
  options.lidar_columns = 256;
  options.survey_num_stations = 1;
  options.survey_angular_step_deg = 1.0;
  options.survey_voxel_size_m = 0.1;
  options.num_threads = 2;
  return options;
}

TEST(Synthesize, WritesACompleteDataset) {
  const std::string dir = JoinPaths(testing::CreateTestDir(), "quad");
  const SynthesisOptions options = TinyOptions();
  const SynthesisSummary summary = SynthesizeDataset(options, dir);
  EXPECT_EQ(summary.num_frames, 3);
  EXPECT_GT(summary.num_reference_points, 1000u);
  EXPECT_GT(summary.num_crease_edges, 500u);

  const RigCalibration calibration =
      ReadCalibration(JoinPaths(dir, "calibration.yaml"));
  EXPECT_EQ(calibration.camera.ModelName(), "PINHOLE");
  EXPECT_EQ(calibration.camera.width, 96u);
  ASSERT_EQ(calibration.camera.params.size(), 4u);
  EXPECT_NEAR(calibration.camera.params[0], 48.0, 1e-9);  // 90 deg HFOV.
  EXPECT_NEAR(calibration.camera.params[3], 32.0, 1e-9);
  ASSERT_TRUE(calibration.lidar.has_value());
  EXPECT_EQ(calibration.lidar->rings, 16);
  EXPECT_TRUE(calibration.cam_from_lidar.translation.isApprox(
      SynthCamFromLidar().translation, 1e-12));

  const std::vector<FramePose> gt = ReadPoses(JoinPaths(dir, "poses_gt.txt"));
  const std::vector<FramePose> prior =
      ReadPoses(JoinPaths(dir, "poses_prior.txt"));
  ASSERT_EQ(gt.size(), 3u);
  ASSERT_EQ(prior.size(), 3u);
  EXPECT_EQ(gt[2].frame, "000002");
  EXPECT_GT((gt[0].world_from_cam.translation -
             prior[0].world_from_cam.translation).norm(), 1e-3);

  size_t num_lidar_points = 0;
  for (const FramePose& pose : gt) {
    const cv::Mat image =
        cv::imread(JoinPaths(dir, "images/" + pose.frame + ".png"),
                   cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(image.empty());
    EXPECT_EQ(image.cols, 96);
    EXPECT_EQ(image.rows, 64);
    EXPECT_EQ(image.channels(), 3);
    const LidarScan scan =
        ReadLidarScan(JoinPaths(dir, "lidar/" + pose.frame + ".ply"));
    EXPECT_TRUE(scan.HasRings());
    EXPECT_TRUE(scan.HasIntensities());
    num_lidar_points += scan.size();
    const DepthMap depth = DepthMap::Read(
        JoinPaths(dir, "ground_truth/depth_maps/" + pose.frame + ".bin"));
    EXPECT_EQ(depth.GetWidth(), 96u);
    EXPECT_EQ(depth.GetHeight(), 64u);
    EXPECT_GT(depth.NumValid(), 96u * 64u / 2);
  }
  EXPECT_EQ(num_lidar_points, summary.num_lidar_points);

  EXPECT_EQ(ReadPly(JoinPaths(dir, "reference.ply")).NumVertices(),
            summary.num_reference_points);
  const PlyData mesh = ReadPly(JoinPaths(dir, "ground_truth/scene.ply"));
  EXPECT_EQ(mesh.faces.size(), summary.num_triangles);
  EXPECT_NE(mesh.FindColumn("material"), nullptr);
  const std::vector<CreaseEdge> edges =
      ReadCreaseEdges(JoinPaths(dir, "ground_truth/crease_edges.txt"));
  EXPECT_EQ(edges.size(), summary.num_crease_edges);
  EXPECT_TRUE(ExistsFile(JoinPaths(dir, "ground_truth/README.md")));
}

// The two sensors agree as the files say they do: each scan, taken to the
// camera with calibration.yaml's cam_from_lidar (p_cam = T * p_lidar), lands
// on the ground-truth depth of that frame's image. Read from the files only,
// as a user of the dataset would.
TEST(Synthesize, LidarAndCameraAgreeThroughTheCalibration) {
  const std::string dir = JoinPaths(testing::CreateTestDir(), "quad");
  SynthesisOptions options = TinyOptions();
  options.image_width = 212;
  options.image_height = 120;
  options.lidar_range_noise_m = 0.0;
  options.survey_num_stations = 0;
  SynthesizeDataset(options, dir);
  const RigCalibration calibration =
      ReadCalibration(JoinPaths(dir, "calibration.yaml"));
  const Camera& camera = calibration.camera;
  for (const FramePose& pose : ReadPoses(JoinPaths(dir, "poses_gt.txt"))) {
    const LidarScan scan =
        ReadLidarScan(JoinPaths(dir, "lidar/" + pose.frame + ".ply"));
    const DepthMap depth = DepthMap::Read(
        JoinPaths(dir, "ground_truth/depth_maps/" + pose.frame + ".bin"));
    int num_in_image = 0;
    int num_consistent = 0;
    for (const Eigen::Vector3f& point : scan.points) {
      const Eigen::Vector3d in_cam =
          calibration.cam_from_lidar * point.cast<double>();
      if (in_cam.z() < 1.0) continue;
      // MVS convention of the depth maps: pixel (col, row) is the image
      // point (col, row), without the +0.5 of the SfM convention.
      const Eigen::Vector2d pixel =
          camera.ImgFromCam(in_cam) - Eigen::Vector2d(0.5, 0.5);
      const int col = static_cast<int>(std::lround(pixel.x()));
      const int row = static_cast<int>(std::lround(pixel.y()));
      if (col < 1 || row < 1 || col + 1 >= static_cast<int>(camera.width) ||
          row + 1 >= static_cast<int>(camera.height)) {
        continue;
      }
      ++num_in_image;
      if (std::abs(depth.Get(row, col) - in_cam.z()) < 0.05 * in_cam.z()) {
        ++num_consistent;
      }
    }
    EXPECT_GT(num_in_image, 100) << pose.frame;
    EXPECT_GT(num_consistent, 0.8 * num_in_image) << pose.frame;
  }
}

// A SIMPLE_RADIAL camera and a VLP-16 with dropout: calibration.yaml
// carries the model, its parameters and the LIDAR's rings and vertical
// field; the distorted depth maps agree with the scans projected by the
// camera model (depth pixel (col, row) = image point (col, row)).
TEST(Synthesize, DistortedCameraAndVelodyneThroughTheFiles) {
  const std::string dir = JoinPaths(testing::CreateTestDir(), "quad");
  SynthesisOptions options = TinyOptions();
  const SynthesisOptions defaults;
  options.lidar_model = "VLP-16";
  options.lidar_rings = defaults.lidar_rings;
  options.lidar_columns = defaults.lidar_columns;
  options.lidar_dropout_probability = 0.1;
  options.lidar_range_noise_m = 0.0;
  options.camera_model = "SIMPLE_RADIAL";
  options.camera_k1 = -0.1;
  options.image_width = 212;
  options.image_height = 120;
  options.num_frames = 2;
  options.survey_num_stations = 0;
  const SynthesisSummary summary = SynthesizeDataset(options, dir);
  // 16 x 1800 beams per scan, 10% dropped, some escape to the sky.
  EXPECT_LT(summary.num_lidar_points, 2u * 16u * 1800u * 91u / 100u);
  EXPECT_GT(summary.num_lidar_points, 2u * 16u * 1800u / 2u);
  const RigCalibration calibration =
      ReadCalibration(JoinPaths(dir, "calibration.yaml"));
  const Camera& camera = calibration.camera;
  ASSERT_EQ(camera.ModelName(), "SIMPLE_RADIAL");
  ASSERT_EQ(camera.params.size(), 4u);
  EXPECT_NEAR(camera.params[0], 106.0, 1e-9);  // 90 deg of the pinhole.
  EXPECT_NEAR(camera.params[1], 106.0, 1e-9);
  EXPECT_NEAR(camera.params[2], 60.0, 1e-9);
  EXPECT_NEAR(camera.params[3], -0.1, 1e-12);
  ASSERT_TRUE(calibration.lidar.has_value());
  EXPECT_EQ(calibration.lidar->rings, 16);
  EXPECT_NEAR(calibration.lidar->vertical_fov_min_deg, -15.0, 1e-9);
  EXPECT_NEAR(calibration.lidar->vertical_fov_max_deg, 15.0, 1e-9);
  for (const FramePose& pose : ReadPoses(JoinPaths(dir, "poses_gt.txt"))) {
    const LidarScan scan =
        ReadLidarScan(JoinPaths(dir, "lidar/" + pose.frame + ".ply"));
    ASSERT_TRUE(scan.HasRings());
    EXPECT_EQ(*std::max_element(scan.rings.begin(), scan.rings.end()), 15);
    const DepthMap depth = DepthMap::Read(
        JoinPaths(dir, "ground_truth/depth_maps/" + pose.frame + ".bin"));
    ASSERT_EQ(depth.GetWidth(), 212u);
    int num_in_image = 0;
    int num_consistent = 0;
    int num_folded = 0;
    for (const Eigen::Vector3f& point : scan.points) {
      const Eigen::Vector3d in_cam =
          calibration.cam_from_lidar * point.cast<double>();
      if (in_cam.z() < 1.0) continue;
      const Eigen::Vector2d pixel = camera.ImgFromCam(in_cam);
      // The polynomial maps some rays far outside the field of view into
      // the image as well (it is not monotonic there): a point is seen at
      // `pixel` only when the pixel's ray is the point's.
      const Eigen::Vector2d ray = camera.CamFromImg(pixel);
      if ((ray - in_cam.hnormalized()).norm() > 1e-6) {
        num_folded += pixel.x() >= 0 && pixel.y() >= 0 &&
                      pixel.x() < camera.width && pixel.y() < camera.height;
        continue;
      }
      const int col = static_cast<int>(std::floor(pixel.x()));
      const int row = static_cast<int>(std::floor(pixel.y()));
      if (col < 1 || row < 1 || col + 2 >= static_cast<int>(camera.width) ||
          row + 2 >= static_cast<int>(camera.height)) {
        continue;
      }
      ++num_in_image;
      // One of the four depth pixels around the projection (depth edges and
      // grazing ground change within a pixel).
      double best = 1e9;
      for (int dr = 0; dr < 2; ++dr) {
        for (int dc = 0; dc < 2; ++dc) {
          best = std::min(best,
                          std::abs(depth.Get(row + dr, col + dc) - in_cam.z()));
        }
      }
      if (best < 0.01 * in_cam.z()) ++num_consistent;
    }
    EXPECT_GT(num_in_image, 200) << pose.frame;
    EXPECT_GT(num_consistent, 0.95 * num_in_image) << pose.frame;
    // Points outside the field of view that the barrel polynomial folds
    // back into the image (r > 1 / sqrt(3 |k1|)); rejected above.
    EXPECT_GT(num_folded, 100) << pose.frame;
  }
}

TEST(Synthesize, DeterministicPerSeedAndRefusesToOverwrite) {
  const std::string root = testing::CreateTestDir();
  SynthesisOptions options = TinyOptions();
  options.preset = "street";
  options.write_depth_maps = false;
  options.survey_num_stations = 0;
  SynthesizeDataset(options, JoinPaths(root, "a"));
  SynthesizeDataset(options, JoinPaths(root, "b"));
  options.seed = 1;
  SynthesizeDataset(options, JoinPaths(root, "c"));
  for (const std::string file :
       {"images/000001.png", "lidar/000002.ply", "poses_prior.txt",
        "poses_gt.txt"}) {
    const std::string a = ReadTextFile(JoinPaths(root, "a/" + file));
    EXPECT_EQ(a, ReadTextFile(JoinPaths(root, "b/" + file))) << file;
    EXPECT_NE(a, ReadTextFile(JoinPaths(root, "c/" + file))) << file;
  }
  EXPECT_FALSE(ExistsFile(JoinPaths(root, "a/reference.ply")));
  EXPECT_FALSE(ExistsDir(JoinPaths(root, "a/ground_truth/depth_maps")));

  // A non-empty folder is kept unless overwrite is set.
  EXPECT_THROW(SynthesizeDataset(options, JoinPaths(root, "a")), Error);
  EXPECT_EQ(ReadTextFile(JoinPaths(root, "a/poses_prior.txt")),
            ReadTextFile(JoinPaths(root, "b/poses_prior.txt")));
  options.overwrite = true;
  SynthesizeDataset(options, JoinPaths(root, "a"));
  EXPECT_EQ(ReadTextFile(JoinPaths(root, "a/poses_prior.txt")),
            ReadTextFile(JoinPaths(root, "c/poses_prior.txt")));
}

// The scans of a dataset in the world frame (ground-truth poses and the
// calibration of the files); `sizes` gets the point count per frame.
std::vector<Eigen::Vector3d> WorldScanPoints(const std::string& dir,
                                             std::vector<size_t>* sizes) {
  const RigCalibration calibration =
      ReadCalibration(JoinPaths(dir, "calibration.yaml"));
  std::vector<Eigen::Vector3d> points;
  for (const FramePose& pose : ReadPoses(JoinPaths(dir, "poses_gt.txt"))) {
    const LidarScan scan =
        ReadLidarScan(JoinPaths(dir, "lidar/" + pose.frame + ".ply"));
    sizes->push_back(scan.size());
    for (const Eigen::Vector3f& point : scan.points) {
      points.push_back(pose.world_from_cam *
                       (calibration.cam_from_lidar * point.cast<double>()));
    }
  }
  return points;
}

// Share of the points on the road or the ground (z below 5 cm; the
// raised pavements are above).
double GroundShare(const std::vector<Eigen::Vector3d>& points) {
  size_t num_ground = 0;
  for (const Eigen::Vector3d& point : points) num_ground += point.z() < 0.05;
  return static_cast<double>(num_ground) / std::max<size_t>(1, points.size());
}

// The bent street: every frame sees the street, the paint borders are
// written beside the crease edges, the README says the pavements are
// raised.
TEST(Synthesize, StreetBentWritesPaintEdgesAndScans) {
  const std::string dir = JoinPaths(testing::CreateTestDir(), "street_bent");
  SynthesisOptions options = TinyOptions();
  options.preset = "street_bent";
  options.write_depth_maps = false;
  options.survey_num_stations = 0;
  const SynthesisSummary summary = SynthesizeDataset(options, dir);
  EXPECT_GT(summary.num_crease_edges, 1000u);
  EXPECT_GT(summary.num_paint_edges, 40u);
  const std::vector<PaintEdge> paint =
      ReadPaintEdges(JoinPaths(dir, "ground_truth/paint_edges.txt"));
  EXPECT_EQ(paint.size(), summary.num_paint_edges);
  std::vector<size_t> sizes;
  const std::vector<Eigen::Vector3d> points = WorldScanPoints(dir, &sizes);
  ASSERT_EQ(sizes.size(), 3u);
  // 16 x 256 beams per scan; the canyon returns most of them.
  for (const size_t size : sizes) EXPECT_GT(size, 16u * 256u / 2);
  // Points on the pavements' tops, 13 cm above the road.
  size_t num_on_pavement = 0;
  for (const Eigen::Vector3d& point : points) {
    num_on_pavement += std::abs(point.z() - 0.13) < 0.03 &&
                       std::abs(point.y()) > 3.6 && point.x() < -5.0;
  }
  EXPECT_GT(num_on_pavement, 20u);
  EXPECT_NE(ReadTextFile(JoinPaths(dir, "ground_truth/README.md"))
                .find("z = 0.13"),
            std::string::npos);
  // Without paint (quad, street, corridor) there is no paint_edges.txt.
  const std::string quad = JoinPaths(testing::CreateTestDir(), "quad");
  options.preset = "quad";
  options.num_frames = 1;
  EXPECT_EQ(SynthesizeDataset(options, quad).num_paint_edges, 0u);
  EXPECT_FALSE(ExistsFile(JoinPaths(quad, "ground_truth/paint_edges.txt")));
}

// The open square: every frame sees something, and much of what the LIDAR
// sees is ground (its upper beams hit the facades 20-45 m away or the sky),
// far more than in the enclosed courtyard (0.45 vs 0.26 of the returns
// with these options).
TEST(Synthesize, SquareSeesMostlyGround) {
  const std::string root = testing::CreateTestDir();
  SynthesisOptions options = TinyOptions();
  options.write_depth_maps = false;
  options.survey_num_stations = 0;
  options.preset = "square";
  SynthesizeDataset(options, JoinPaths(root, "square"));
  options.preset = "quad";
  SynthesizeDataset(options, JoinPaths(root, "quad"));
  std::vector<size_t> square_sizes;
  std::vector<size_t> quad_sizes;
  const double square_ground =
      GroundShare(WorldScanPoints(JoinPaths(root, "square"), &square_sizes));
  const double quad_ground =
      GroundShare(WorldScanPoints(JoinPaths(root, "quad"), &quad_sizes));
  for (const size_t size : square_sizes) EXPECT_GT(size, 16u * 256u / 4);
  EXPECT_GT(square_ground, 0.4);
  EXPECT_GT(square_ground, 1.5 * quad_ground);
}

TEST(Synthesize, RejectsBadOptions) {
  SynthesisOptions options = TinyOptions();
  options.preset = "moon";
  EXPECT_FALSE(options.Check());
  for (const std::string& preset : ScenePresetNames()) {
    options.preset = preset;
    EXPECT_TRUE(options.Check()) << preset;
  }
  EXPECT_EQ(ScenePresetNamesText(),
            "quad, street, corridor, street_bent or square");
  options.preset = "moon";
  EXPECT_THROW(SynthesizeDataset(options, testing::CreateTestDir() + "/x"),
               Error);
  options = TinyOptions();
  options.supersampling = 0;
  EXPECT_FALSE(options.Check());
  options = TinyOptions();
  options.lidar_min_range_m = 200.0;
  EXPECT_FALSE(options.Check());
  options = TinyOptions();
  options.lidar_model = "OS1-128";  // TinyOptions sets custom rings.
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(SynthesizeDataset(options, testing::CreateTestDir() + "/y"),
               Error);
  options = TinyOptions();
  options.camera_model = "OPENCV";
  options.camera_k1 = -0.5;  // Folds over inside the image.
  EXPECT_FALSE(options.Check());
  // Only street_bent can be made longer, and not shorter.
  options = TinyOptions();
  options.preset = "street_bent";
  options.length_factor = 3.0;
  EXPECT_TRUE(options.Check());
  options.length_factor = 0.5;
  EXPECT_FALSE(options.Check());
  options.length_factor = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(options.Check());
  options.length_factor = 2.0;
  options.preset = "quad";
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(SynthesizeDataset(options, testing::CreateTestDir() + "/z"),
               Error);
  EXPECT_TRUE(TinyOptions().Check());
}

}  // namespace
}  // namespace colmap_lidar
