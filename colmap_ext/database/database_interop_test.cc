// Interop with the stock colmap 3.8 binary: a database written by us, with
// cameras and images pre-inserted by name and one LIDAR scan row per image,
// goes through `colmap feature_extractor` and `colmap exhaustive_matcher`;
// we then read colmap's rows back and check our rows survived.
#include <gtest/gtest.h>

#include <filesystem>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/schema.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

constexpr camera_t kCameraId = 5;
// Non-contiguous ids show that colmap keeps ours.
const std::vector<std::pair<image_t, std::string>> kImages = {
    {1000, "0000000000.png"},
    {1003, "0000000001.png"},
    {1010, "0000000002.png"},
    {1020, "0000000003.png"}};

std::string RunColmap(const std::string& args, const std::string& log_path) {
  const int code = testing::RunCommand("colmap " + args, log_path);
  return code == 0
             ? std::string()
             : "exit " + std::to_string(code) + ": " + ReadTextFile(log_path);
}

TEST(DatabaseInterop, ColmapFillsFeaturesAndKeepsOurRows) {
  const std::string dir = testing::CreateTestDir();
  const std::string image_dir = JoinPaths(dir, "images");
  CreateDirIfNotExists(image_dir);
  const std::string kitti_dir =
      JoinPaths(testing::KittiSampleDir(), "2011_09_26/image_02/data");
  for (const auto& [id, name] : kImages) {
    std::filesystem::copy_file(JoinPaths(kitti_dir, name),
                               JoinPaths(image_dir, name));
  }
  const std::string path = JoinPaths(dir, "database.db");

  std::vector<LidarScanRecord> scans;
  {
    Database database(path);
    DatabaseTransaction transaction(&database);
    Camera camera;
    camera.camera_id = kCameraId;
    camera.model_id = CameraModelId::kPinhole;
    camera.width = 1242;  // KITTI image_02 size; colmap checks it.
    camera.height = 375;
    camera.params = {721.5377, 721.5377, 609.5593, 172.854};
    camera.has_prior_focal_length = true;
    ASSERT_EQ(database.WriteCamera(camera), kCameraId);
    for (const auto& [id, name] : kImages) {
      DatabaseImage image;
      image.image_id = id;
      image.name = name;
      image.camera_id = kCameraId;
      image.prior_q = Eigen::Quaterniond::Identity();
      image.prior_t = Eigen::Vector3d(0, 0, 0.8 * (id - 1000));
      ASSERT_EQ(database.WriteImage(image), id);
      LidarScanRecord scan;
      scan.image_id = id;
      scan.path = "lidar/" + name + ".ply";
      scan.num_points = 100000 + id;
      scan.cam_from_lidar = Rigid3d(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5),
                                    Eigen::Vector3d(0.06, -0.08, -0.27));
      database.WriteLidarScan(scan);
      scans.push_back(scan);
    }
    transaction.Commit();
  }

  const std::string extract_error = RunColmap(
      "feature_extractor --database_path '" + path + "' --image_path '" +
          image_dir +
          "' --SiftExtraction.use_gpu 0 --SiftExtraction.num_threads 2 "
          "--SiftExtraction.max_image_size 640 "
          "--SiftExtraction.max_num_features 1024",
      JoinPaths(dir, "feature_extractor.log"));
  ASSERT_TRUE(extract_error.empty()) << extract_error;
  const std::string match_error =
      RunColmap("exhaustive_matcher --database_path '" + path +
                    "' --SiftMatching.use_gpu 0 --SiftMatching.num_threads 2",
                JoinPaths(dir, "exhaustive_matcher.log"));
  ASSERT_TRUE(match_error.empty()) << match_error;

  Database database(path);
  EXPECT_EQ(database.UserVersion(), kColmapUserVersion);
  EXPECT_EQ(database.ExtSchemaVersion(), kExtSchemaVersion);
  // No new camera, ids and priors unchanged.
  const std::vector<Camera> cameras = database.ReadAllCameras();
  ASSERT_EQ(cameras.size(), 1u);
  EXPECT_EQ(cameras[0].camera_id, kCameraId);
  EXPECT_EQ(cameras[0].model_id, CameraModelId::kPinhole);
  const std::vector<DatabaseImage> images = database.ReadAllImages();
  ASSERT_EQ(images.size(), kImages.size());
  for (size_t i = 0; i < kImages.size(); ++i) {
    EXPECT_EQ(images[i].image_id, kImages[i].first);
    EXPECT_EQ(images[i].name, kImages[i].second);
    EXPECT_EQ(images[i].camera_id, kCameraId);
    ASSERT_TRUE(images[i].prior_t.has_value());
    EXPECT_EQ(images[i].prior_t->z(), 0.8 * (kImages[i].first - 1000));
  }

  for (const auto& [id, name] : kImages) {
    const FeatureKeypointsBlob keypoints = database.ReadKeypoints(id);
    const FeatureDescriptorsBlob descriptors = database.ReadDescriptors(id);
    EXPECT_EQ(keypoints.cols(), 6) << name;
    EXPECT_GT(keypoints.rows(), 200) << name;
    // max_num_features limits locations; colmap then adds a keypoint per
    // extra orientation, so the count may exceed 1024 a little.
    EXPECT_LE(keypoints.rows(), 2 * 1024) << name;
    EXPECT_EQ(descriptors.rows(), keypoints.rows()) << name;
    EXPECT_EQ(descriptors.cols(), 128) << name;
    EXPECT_EQ(database.NumKeypointsForImage(id),
              static_cast<size_t>(keypoints.rows()));
    // Keypoints in full-resolution pixels despite max_image_size 640.
    EXPECT_GT(keypoints.col(0).maxCoeff(), 700.f) << name;
    EXPECT_LE(keypoints.col(0).maxCoeff(), 1242.f) << name;
    EXPECT_LE(keypoints.col(1).maxCoeff(), 375.f) << name;
    EXPECT_GE(keypoints.col(1).minCoeff(), 0.f) << name;
  }

  // Every pair was processed; pair ids decode to (smaller, larger) of our
  // ids, and match indices are within the keypoints.
  const size_t num_pairs = kImages.size() * (kImages.size() - 1) / 2;
  const auto all_matches = database.ReadAllMatches();
  EXPECT_EQ(all_matches.size(), num_pairs);
  for (const auto& [pair_id, matches] : all_matches) {
    const auto [id1, id2] = Database::PairIdToImagePair(pair_id);
    EXPECT_LT(id1, id2);
    EXPECT_TRUE(database.ExistsImage(id1) && database.ExistsImage(id2))
        << pair_id;
    if (matches.rows() > 0) {
      EXPECT_LT(matches.col(0).maxCoeff(), database.NumKeypointsForImage(id1));
      EXPECT_LT(matches.col(1).maxCoeff(), database.NumKeypointsForImage(id2));
    }
  }
  const auto geometries = database.ReadAllTwoViewGeometries();
  EXPECT_EQ(geometries.size(), num_pairs);
  // Consecutive KITTI frames overlap strongly: verified with many inliers
  // and a non-zero F (row-major fundamental matrices are rank 2).
  for (size_t i = 0; i + 1 < kImages.size(); ++i) {
    const image_t id1 = kImages[i].first;
    const image_t id2 = kImages[i + 1].first;
    const std::optional<TwoViewGeometry> geometry =
        database.ReadTwoViewGeometry(id1, id2);
    ASSERT_TRUE(geometry.has_value()) << id1 << "-" << id2;
    EXPECT_GE(geometry->inlier_matches.rows(), 50) << id1 << "-" << id2;
    EXPECT_NE(geometry->config, TwoViewGeometryConfig::kUndefined);
    EXPECT_NE(geometry->config, TwoViewGeometryConfig::kDegenerate);
    EXPECT_GT(geometry->F.norm() + geometry->H.norm(), 0.0);
    const FeatureMatchesBlob matches = database.ReadMatches(id1, id2);
    EXPECT_GE(matches.rows(), geometry->inlier_matches.rows());
  }
  EXPECT_EQ(database.NumMatchedImagePairs(), num_pairs);
  EXPECT_GE(database.NumVerifiedImagePairs(), kImages.size() - 1);

  // Our rows survived unchanged.
  const std::vector<LidarScanRecord> read_scans = database.ReadAllLidarScans();
  ASSERT_EQ(read_scans.size(), scans.size());
  for (size_t i = 0; i < scans.size(); ++i) {
    EXPECT_EQ(read_scans[i].image_id, scans[i].image_id);
    EXPECT_EQ(read_scans[i].path, scans[i].path);
    EXPECT_EQ(read_scans[i].num_points, scans[i].num_points);
    EXPECT_TRUE(read_scans[i].cam_from_lidar.ToMatrix().isApprox(
        scans[i].cam_from_lidar.ToMatrix(), 1e-15));
  }
}

}  // namespace
}  // namespace colmap_lidar
