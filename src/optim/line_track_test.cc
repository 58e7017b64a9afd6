#include "src/optim/line_track.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"
#include "src/optim/line_geometry.h"

namespace colmap_lidar {
namespace {

// Two pinhole cameras looking down +z at a line 6-8 m away.
struct TwoViewScene {
  Reconstruction reconstruction;
  Eigen::Vector3d line_start{-1.0, 0.5, 6.0};
  Eigen::Vector3d line_end{1.0, -0.3, 8.0};

  TwoViewScene() {
    reconstruction.cameras[1] =
        Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
    reconstruction.cameras[1].camera_id = 1;
    for (image_t image_id : {1u, 2u}) {
      Image image;
      image.image_id = image_id;
      image.camera_id = 1;
      image.name = "image" + std::to_string(image_id) + ".png";
      image.cam_from_world.rotation =
          Eigen::AngleAxisd(image_id == 1 ? 0.0 : 0.15, Eigen::Vector3d::UnitY());
      image.cam_from_world.translation =
          image_id == 1 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(-1.2, 0.1, 0.2);
      reconstruction.images.push_back(image);
    }
  }

  // Observation of the part [t0, t1] of the segment in image image_id.
  LineObservation Observe(image_t image_id, double t0, double t1,
                          bool with_lidar) const {
    const Image& image = *reconstruction.FindImage(image_id);
    const Camera& camera = reconstruction.cameras.at(1);
    const Eigen::Vector3d a = line_start + t0 * (line_end - line_start);
    const Eigen::Vector3d b = line_start + t1 * (line_end - line_start);
    LineObservation observation;
    observation.image_id = image_id;
    observation.start2D = camera.ImgFromCam(image.cam_from_world * a);
    observation.end2D = camera.ImgFromCam(image.cam_from_world * b);
    observation.has_lidar = with_lidar;
    if (with_lidar) {
      observation.start_in_cam = image.cam_from_world * a;
      observation.end_in_cam = image.cam_from_world * b;
    }
    return observation;
  }
};

double LineDifference(const Vector6d& a, const Vector6d& b) {
  const Vector6d na = NormalizePlucker(a);
  const Vector6d nb = NormalizePlucker(b);
  return std::min((na - nb).norm(), (na + nb).norm());
}

TEST(LineTrack, InitializeFromLidar) {
  const TwoViewScene scene;
  LineTrack track;
  track.observations = {scene.Observe(1, 0.0, 0.6, true),
                        scene.Observe(2, 0.3, 1.0, true)};
  EXPECT_FALSE(IsLineInitialized(track));
  ASSERT_TRUE(InitializeLineFromLidar(scene.reconstruction, &track));
  EXPECT_TRUE(IsLineInitialized(track));
  EXPECT_NEAR(track.plucker_in_world.head<3>().norm(), 1.0, 1e-12);
  EXPECT_LT(LineDifference(track.plucker_in_world,
                           PluckerFromPoints(scene.line_start, scene.line_end)),
            1e-9);
  // A single view with LIDAR is enough.
  LineTrack single;
  single.observations = {scene.Observe(2, 0.2, 0.5, true)};
  ASSERT_TRUE(InitializeLineFromLidar(scene.reconstruction, &single));
  EXPECT_LT(LineDifference(single.plucker_in_world,
                           PluckerFromPoints(scene.line_start, scene.line_end)),
            1e-9);
}

TEST(LineTrack, InitializeFromLidarFailures) {
  const TwoViewScene scene;
  LineTrack track;
  track.observations = {scene.Observe(1, 0.0, 0.6, false)};
  EXPECT_FALSE(InitializeLineFromLidar(scene.reconstruction, &track));
  EXPECT_FALSE(IsLineInitialized(track));
  // Degenerate: both endpoints equal.
  track.observations = {scene.Observe(1, 0.4, 0.4, true)};
  EXPECT_FALSE(InitializeLineFromLidar(scene.reconstruction, &track));
  // Unknown image.
  track.observations = {scene.Observe(1, 0.0, 0.6, true)};
  track.observations[0].image_id = 99;
  EXPECT_FALSE(InitializeLineFromLidar(scene.reconstruction, &track));
}

TEST(LineTrack, InitializeFromViews) {
  const TwoViewScene scene;
  LineTrack track;
  track.observations = {scene.Observe(1, 0.0, 0.6, false),
                        scene.Observe(2, 0.3, 1.0, false)};
  ASSERT_TRUE(InitializeLineFromViews(scene.reconstruction, &track));
  EXPECT_LT(LineDifference(track.plucker_in_world,
                           PluckerFromPoints(scene.line_start, scene.line_end)),
            1e-8);
  LineTrack single;
  single.observations = {scene.Observe(1, 0.0, 0.6, false)};
  EXPECT_FALSE(InitializeLineFromViews(scene.reconstruction, &single));
}

TEST(LineTrack, SegmentIsTheExtentOverViews) {
  const TwoViewScene scene;
  LineTrack track;
  track.plucker_in_world = PluckerFromPoints(scene.line_start, scene.line_end);
  track.observations = {scene.Observe(1, 0.1, 0.6, false),
                        scene.Observe(2, 0.3, 0.9, true)};
  ASSERT_TRUE(ComputeLineSegment(scene.reconstruction, &track));
  const Eigen::Vector3d expected_start =
      scene.line_start + 0.1 * (scene.line_end - scene.line_start);
  const Eigen::Vector3d expected_end =
      scene.line_start + 0.9 * (scene.line_end - scene.line_start);
  // The direction of the Pluecker vector orders the endpoints.
  EXPECT_LT((track.start_in_world - expected_start).norm(), 1e-6);
  EXPECT_LT((track.end_in_world - expected_end).norm(), 1e-6);

  LineTrack uninitialized;
  uninitialized.observations = track.observations;
  EXPECT_FALSE(ComputeLineSegment(scene.reconstruction, &uninitialized));
}

TEST(LineTrack, ConversionToLine3D) {
  const TwoViewScene scene;
  LineTrack track;
  track.line3D_id = 7;
  track.start_in_world = Eigen::Vector3d(1, 2, 3);
  track.end_in_world = Eigen::Vector3d(4, 5, 6);
  track.error = 0.7;
  track.observations = {scene.Observe(1, 0.1, 0.6, false),
                        scene.Observe(2, 0.3, 0.9, true)};
  track.observations[1].line2D_idx = 12;
  const Line3D line3D = LineTrackToLine3D(track);
  EXPECT_EQ(line3D.start_in_world, track.start_in_world);
  EXPECT_EQ(line3D.end_in_world, track.end_in_world);
  EXPECT_EQ(line3D.error, 0.7);
  ASSERT_EQ(line3D.track.size(), 2u);
  EXPECT_EQ(line3D.track[1].image_id, 2u);
  EXPECT_EQ(line3D.track[1].line2D_idx, 12u);

  Reconstruction reconstruction = scene.reconstruction;
  SetReconstructionLines({track}, &reconstruction);
  ASSERT_EQ(reconstruction.lines3D.count(7), 1u);
  EXPECT_NO_THROW(reconstruction.CheckConsistency());
  EXPECT_THROW(SetReconstructionLines({track, track}, &reconstruction), Error);
}

}  // namespace
}  // namespace colmap_lidar
