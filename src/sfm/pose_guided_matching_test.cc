#include "src/sfm/pose_guided_matching.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "src/sfm/sift_test_util.h"

namespace colmap_lidar {
namespace {

Camera TestCamera() {
  return Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
}

// A wall z = 6 m in front of camera 1, seen by camera 2 one metre to the
// right and 0.5 m forward (cam2_from_world translation = -centre).
struct TwoViews {
  GuidedMatchingImage image1;
  GuidedMatchingImage image2;
  std::vector<Eigen::Vector3d> points_in_world;
  // LIDAR points of the wall in each camera's frame, every 0.1 m.
  std::vector<Eigen::Vector3f> scan1;
  std::vector<Eigen::Vector3f> scan2;
};

TwoViews MakeTwoViews(int num_points, std::mt19937* rng) {
  TwoViews views;
  views.image1.camera = TestCamera();
  views.image2.camera = TestCamera();
  views.image2.cam_from_world.translation = Eigen::Vector3d(-1.0, 0.0, -0.5);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<Eigen::Matrix<uint8_t, 1, 128>> descriptors;
  for (int n = 0; n < num_points; ++n) {
    const Eigen::Vector3d point(u(*rng), 0.7 * u(*rng), 6.0);
    const Eigen::Vector2d p1 = views.image1.camera.ImgFromCam(point);
    const Eigen::Vector2d p2 = views.image2.camera.ImgFromCam(
        views.image2.cam_from_world * point);
    if (p1.minCoeff() < 0 || p1.x() > 640 || p1.y() > 480 ||
        p2.minCoeff() < 0 || p2.x() > 640 || p2.y() > 480) {
      continue;
    }
    views.points_in_world.push_back(point);
    descriptors.push_back(RandomSiftDescriptor(rng));
  }
  const int n = static_cast<int>(views.points_in_world.size());
  for (GuidedMatchingImage* image : {&views.image1, &views.image2}) {
    image->keypoints.resize(n, 2);
    image->descriptors.resize(n, 128);
  }
  // Image 2 lists its keypoints in reverse order, half a pixel off.
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d& point = views.points_in_world[k];
    views.image1.keypoints.row(k) =
        views.image1.camera.ImgFromCam(point).cast<float>().transpose();
    views.image1.descriptors.row(k) = descriptors[k];
    const int r = n - 1 - k;
    views.image2.keypoints.row(r) =
        (views.image2.camera.ImgFromCam(views.image2.cam_from_world * point) +
         Eigen::Vector2d(0.5, -0.3))
            .cast<float>()
            .transpose();
    views.image2.descriptors.row(r) = descriptors[k];
  }
  for (double x = -8.0; x <= 8.0; x += 0.1) {
    for (double y = -4.0; y <= 4.0; y += 0.1) {
      const Eigen::Vector3d wall(x, y, 6.0);
      views.scan1.push_back(wall.cast<float>());
      views.scan2.push_back((views.image2.cam_from_world * wall).cast<float>());
    }
  }
  return views;
}

TEST(PoseGuidedMatching, DepthIntervalsFromTheNearestScanPoints) {
  PoseGuidedMatchingOptions options;
  const Camera camera = TestCamera();
  FeatureKeypointsBlob keypoints(2, 2);
  keypoints << 320.5f, 240.5f,  // on the wall
      20.0f, 20.0f;             // no scan point within 3 deg
  std::vector<Eigen::Vector3f> scan;
  for (double x = 0.0; x <= 1.0; x += 0.05) {
    for (double y = 0.0; y <= 1.0; y += 0.05) {
      scan.emplace_back(x, y, 5.0f);
    }
  }
  const std::vector<KeypointDepth> depths =
      KeypointDepthIntervals(camera, keypoints, scan, options);
  ASSERT_EQ(depths.size(), 2u);
  EXPECT_NEAR(depths[0].min_depth, 5.0 * (1.0 - options.depth_margin), 1e-4);
  EXPECT_NEAR(depths[0].max_depth, 5.0 * (1.0 + options.depth_margin), 1e-4);
  EXPECT_EQ(depths[1].max_depth, 0.0f);
  // Points behind the camera or outside the image give no depth.
  const std::vector<Eigen::Vector3f> behind = {{0.0f, 0.0f, -5.0f},
                                               {50.0f, 0.0f, 1.0f}};
  for (const KeypointDepth& depth :
       KeypointDepthIntervals(camera, keypoints, behind, options)) {
    EXPECT_EQ(depth.max_depth, 0.0f);
  }
}

TEST(PoseGuidedMatching, MatchesWhereTheLidarPutsThem) {
  std::mt19937 rng(3);
  TwoViews views = MakeTwoViews(300, &rng);
  const int n = static_cast<int>(views.points_in_world.size());
  ASSERT_GT(n, 100);
  PoseGuidedMatchingOptions options;
  views.image1.depths = KeypointDepthIntervals(
      views.image1.camera, views.image1.keypoints, views.scan1, options);
  views.image2.depths = KeypointDepthIntervals(
      views.image2.camera, views.image2.keypoints, views.scan2, options);
  const FeatureMatchesBlob matches =
      GuidedMatchesOneWay(views.image1, views.image2, options);
  EXPECT_GT(matches.rows(), 0.95 * n);
  for (int m = 0; m < matches.rows(); ++m) {
    EXPECT_EQ(matches(m, 1), n - 1 - matches(m, 0));
  }
  EXPECT_DOUBLE_EQ(EpipolarAgreement(views.image1, views.image2, matches,
                                     options),
                   1.0);
  // Without a depth nothing is guided from that side.
  GuidedMatchingImage no_depth = views.image1;
  for (KeypointDepth& depth : no_depth.depths) depth = KeypointDepth();
  EXPECT_EQ(GuidedMatchesOneWay(no_depth, views.image2, options).rows(), 0);
}

// A repeated texture: every target keypoint has a twin with the same
// descriptor 60 px away along the epipolar line (a point 3 m nearer than
// the wall). The whole-image ratio test of exact matching refuses them all;
// the LIDAR depth keeps the twin out of the candidates.
TEST(PoseGuidedMatching, RepeatedTextureOffTheDepthIsNoRival) {
  std::mt19937 rng(5);
  TwoViews views = MakeTwoViews(150, &rng);
  const int n = static_cast<int>(views.points_in_world.size());
  PoseGuidedMatchingOptions options;
  GuidedMatchingImage target = views.image2;
  target.keypoints.conservativeResize(2 * n, 2);
  target.descriptors.conservativeResize(2 * n, 128);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d nearer = 0.5 * views.points_in_world[k];
    const int r = n - 1 - k;
    target.keypoints.row(n + r) =
        target.camera.ImgFromCam(target.cam_from_world * nearer)
            .cast<float>()
            .transpose();
    target.descriptors.row(n + r) = target.descriptors.row(r);
  }
  target.depths.assign(2 * n, KeypointDepth());
  views.image1.depths = KeypointDepthIntervals(
      views.image1.camera, views.image1.keypoints, views.scan1, options);
  const FeatureMatchesBlob matches =
      GuidedMatchesOneWay(views.image1, target, options);
  EXPECT_GT(matches.rows(), 0.9 * n);
  for (int m = 0; m < matches.rows(); ++m) {
    EXPECT_EQ(matches(m, 1), n - 1 - matches(m, 0));
  }
}

// A target keypoint with a LIDAR depth of its own takes part only where
// the two rays meet within it; scales must agree with the depths.
TEST(PoseGuidedMatching, TargetDepthAndScaleMustAgree) {
  std::mt19937 rng(11);
  TwoViews views = MakeTwoViews(200, &rng);
  const int n = static_cast<int>(views.points_in_world.size());
  PoseGuidedMatchingOptions options;
  views.image1.depths = KeypointDepthIntervals(
      views.image1.camera, views.image1.keypoints, views.scan1, options);
  views.image2.depths = KeypointDepthIntervals(
      views.image2.camera, views.image2.keypoints, views.scan2, options);
  // Scales: 2 px at 6 m in image 1, f / z in image 2.
  for (GuidedMatchingImage* image : {&views.image1, &views.image2}) {
    image->keypoints.conservativeResize(n, 4);
  }
  for (int k = 0; k < n; ++k) {
    const double z2 =
        (views.image2.cam_from_world * views.points_in_world[k]).z();
    views.image1.keypoints(k, 2) = 2.0f;
    views.image1.keypoints(k, 3) = 0.0f;
    views.image2.keypoints(n - 1 - k, 2) = static_cast<float>(2.0 * 6.0 / z2);
    views.image2.keypoints(n - 1 - k, 3) = 0.0f;
  }
  EXPECT_GT(GuidedMatchesOneWay(views.image1, views.image2, options).rows(),
            0.95 * n);
  // Twice the predicted scale: refused; the test off: matched again.
  GuidedMatchingImage scaled = views.image2;
  scaled.keypoints.col(2) *= 2.0f;
  EXPECT_EQ(GuidedMatchesOneWay(views.image1, scaled, options).rows(), 0);
  options.max_scale_ratio = 0.0;
  EXPECT_GT(GuidedMatchesOneWay(views.image1, scaled, options).rows(),
            0.95 * n);
  // A target that sees a surface 2 m away where the match would be 5.5 m.
  GuidedMatchingImage nearer = views.image2;
  for (KeypointDepth& depth : nearer.depths) {
    depth.min_depth = 1.9f;
    depth.max_depth = 2.1f;
  }
  EXPECT_EQ(GuidedMatchesOneWay(views.image1, nearer, options).rows(), 0);
}

// A corrupt keypoint (not finite) gets no depth and no match; the others
// are matched as before.
TEST(PoseGuidedMatching, NonFiniteKeypointsAreLeftOut) {
  std::mt19937 rng(13);
  TwoViews views = MakeTwoViews(100, &rng);
  const int n = static_cast<int>(views.points_in_world.size());
  PoseGuidedMatchingOptions options;
  views.image1.keypoints(0, 0) = std::numeric_limits<float>::quiet_NaN();
  views.image2.keypoints(0, 1) = std::numeric_limits<float>::infinity();
  views.image1.depths = KeypointDepthIntervals(
      views.image1.camera, views.image1.keypoints, views.scan1, options);
  views.image2.depths = KeypointDepthIntervals(
      views.image2.camera, views.image2.keypoints, views.scan2, options);
  EXPECT_EQ(views.image1.depths[0].max_depth, 0.0f);
  const FeatureMatchesBlob matches =
      GuidedMatchesOneWay(views.image1, views.image2, options);
  EXPECT_GT(matches.rows(), 0.9 * n);
  for (int m = 0; m < matches.rows(); ++m) {
    EXPECT_NE(matches(m, 0), 0u);
    EXPECT_NE(matches(m, 1), 0u);
    EXPECT_EQ(matches(m, 1), n - 1 - matches(m, 0));
  }
}

// Poses that do not explain the matches (camera 2 tilted by 5.7 deg, its
// epipolar lines 50 px off): the agreement is low.
TEST(PoseGuidedMatching, AgreementTellsWrongPoses) {
  std::mt19937 rng(7);
  TwoViews views = MakeTwoViews(200, &rng);
  const int n = static_cast<int>(views.points_in_world.size());
  PoseGuidedMatchingOptions options;
  FeatureMatchesBlob truth(n, 2);
  for (int k = 0; k < n; ++k) {
    truth(k, 0) = k;
    truth(k, 1) = n - 1 - k;
  }
  EXPECT_DOUBLE_EQ(EpipolarAgreement(views.image1, views.image2, truth, options),
                   1.0);
  GuidedMatchingImage turned = views.image2;
  turned.cam_from_world.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));
  EXPECT_LT(EpipolarAgreement(views.image1, turned, truth, options), 0.2);
}

// Each image with its 2 nearest images: on a walk along x, its neighbours
// (the ends: the next two).
TEST(PoseGuidedMatching, NearestImagePairs) {
  Reconstruction model;
  std::vector<std::pair<image_t, image_t>> pairs;
  for (image_t id = 1; id <= 5; ++id) {
    Image image;
    image.image_id = id;
    image.cam_from_world.translation = Eigen::Vector3d(-2.0 * id, 0.0, 0.0);
    model.images.push_back(image);
    for (image_t other = id + 1; other <= 5; ++other) {
      pairs.emplace_back(id, other);
    }
  }
  const std::vector<std::pair<image_t, image_t>> expected = {
      {1, 2}, {1, 3}, {2, 3}, {3, 4}, {3, 5}, {4, 5}};
  EXPECT_EQ(NearestImagePairs(model, pairs, 2), expected);
  EXPECT_EQ(NearestImagePairs(model, pairs, 0), pairs);
  EXPECT_EQ(NearestImagePairs(model, pairs, 10), pairs);
}

TEST(PoseGuidedMatching, OptionsCheck) {
  PoseGuidedMatchingOptions options;
  EXPECT_TRUE(options.Check());
  options.max_ratio = 1.5;
  EXPECT_FALSE(options.Check());
  options = PoseGuidedMatchingOptions();
  options.max_depth_neighbor_angle_deg = 0.0;
  EXPECT_FALSE(options.Check());
  options = PoseGuidedMatchingOptions();
  options.pose_sigma_m = std::nan("");
  EXPECT_FALSE(options.Check());
  options = PoseGuidedMatchingOptions();
  options.max_scale_ratio = 0.5;
  EXPECT_FALSE(options.Check());
  options = PoseGuidedMatchingOptions();
  options.num_nearest_images = -1;
  EXPECT_FALSE(options.Check());
}

}  // namespace
}  // namespace colmap_lidar
