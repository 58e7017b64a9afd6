#include "src/sfm/ba_input.h"

#include <gtest/gtest.h>

#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/database/line_tracks_table.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

class BaInputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    database_.Open(JoinPaths(testing::CreateTestDir(), "database.db"));
    camera_ = Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
    camera_.camera_id = database_.WriteCamera(camera_);
    model_.cameras[camera_.camera_id] = camera_;
    int k = 0;
    for (const char* name : {"a.png", "b.png", "c.png"}) {
      DatabaseImage db_image;
      db_image.name = name;
      db_image.camera_id = camera_.camera_id;
      // Camera k at x = k looking along +z; rotation about z by 10 k deg.
      db_image.prior_q = Eigen::Quaterniond(
          Eigen::AngleAxisd(0.1745 * k, Eigen::Vector3d::UnitZ()));
      db_image.prior_t = Eigen::Vector3d(k, 0.5 * k, 0.0);
      db_image.image_id = database_.WriteImage(db_image);
      image_ids_.push_back(db_image.image_id);
      // Two segments per image with distinct values.
      std::vector<LineSegmentRecord> segments(2);
      for (int s = 0; s < 2; ++s) {
        segments[s].start2D = Eigen::Vector2d(10 * k + s, 20);
        segments[s].end2D = Eigen::Vector2d(30, 40 * k + s);
        segments[s].start3D_in_cam = Eigen::Vector3d(k, s, 5);
        segments[s].end3D_in_cam = Eigen::Vector3d(k, s + 1, 6);
      }
      WriteLineSegments(&database_, db_image.image_id, segments);
      ++k;
    }
    // The model lacks image c.
    for (int i = 0; i < 2; ++i) {
      Image image;
      image.image_id = image_ids_[i];
      image.name = i == 0 ? "a.png" : "b.png";
      image.camera_id = camera_.camera_id;
      model_.images.push_back(image);
    }
  }

  LineTrackRecord Track(line3D_t id,
                        std::vector<LineTrackElement> elements) const {
    LineTrackRecord track;
    track.line3D_id = id;
    track.plucker << 1, 0, 0, 0, 2, 3;
    track.start_in_world = Eigen::Vector3d(0, 1, 2);
    track.end_in_world = Eigen::Vector3d(4, 1, 2);
    track.elements = std::move(elements);
    return track;
  }

  Database database_;
  Camera camera_;
  Reconstruction model_;
  std::vector<image_t> image_ids_;
};

TEST_F(BaInputTest, JoinsTracksWithSegments) {
  WriteLineTracks(&database_,
                  {Track(4, {{image_ids_[0], 1}, {image_ids_[1], 0}}),
                   // Only one observation in the model: dropped.
                   Track(7, {{image_ids_[1], 1}, {image_ids_[2], 0}})});
  LineTrackLoadSummary summary;
  const std::vector<LineTrack> tracks =
      LoadLineTracks(database_, model_, 2, &summary);
  EXPECT_EQ(summary.num_tracks_in_database, 2);
  EXPECT_EQ(summary.num_tracks, 1);
  EXPECT_EQ(summary.num_observations, 2);
  EXPECT_EQ(summary.num_observations_without_image, 1);
  ASSERT_EQ(tracks.size(), 1u);
  const LineTrack& track = tracks[0];
  EXPECT_EQ(track.line3D_id, 4u);
  EXPECT_EQ(track.plucker_in_world(4), 2.0);
  EXPECT_EQ(track.end_in_world.x(), 4.0);
  ASSERT_EQ(track.observations.size(), 2u);
  const LineObservation& first = track.observations[0];
  EXPECT_EQ(first.image_id, image_ids_[0]);
  EXPECT_EQ(first.line2D_idx, 1u);
  EXPECT_TRUE(first.has_lidar);
  EXPECT_EQ(first.start2D, Eigen::Vector2d(1, 20));
  EXPECT_EQ(first.end2D, Eigen::Vector2d(30, 1));
  EXPECT_EQ(first.start_in_cam, Eigen::Vector3d(0, 1, 5));
  EXPECT_EQ(first.end_in_cam, Eigen::Vector3d(0, 2, 6));
  const LineObservation& second = track.observations[1];
  EXPECT_EQ(second.image_id, image_ids_[1]);
  EXPECT_EQ(second.start2D, Eigen::Vector2d(10, 20));
  EXPECT_EQ(second.end_in_cam, Eigen::Vector3d(1, 1, 6));

  // With a minimum of one observation the second track stays.
  EXPECT_EQ(LoadLineTracks(database_, model_, 1).size(), 2u);
}

TEST_F(BaInputTest, MissingSegmentThrows) {
  WriteLineTracks(&database_,
                  {Track(1, {{image_ids_[0], 5}, {image_ids_[1], 0}})});
  EXPECT_THROW(LoadLineTracks(database_, model_), Error);
}

TEST_F(BaInputTest, PriorsAreCamFromWorld) {
  const auto priors = ReadPosePriors(database_, model_);
  ASSERT_EQ(priors.size(), 2u);  // c is not in the model.
  const Rigid3d& prior = priors.at(image_ids_[1]);
  EXPECT_TRUE(prior.Inverse().translation.isApprox(Eigen::Vector3d(1, 0.5, 0),
                                                   1e-12));
  EXPECT_NEAR(prior.rotation.angularDistance(Eigen::Quaterniond(
                  Eigen::AngleAxisd(0.1745, Eigen::Vector3d::UnitZ()))),
              0.0, 1e-12);
}

}  // namespace
}  // namespace colmap_lidar
