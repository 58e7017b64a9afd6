#include "src/mesh/line_observations.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"
#include "src/mesh/meshing_input.h"

namespace colmap_lidar {
namespace {

// A 1 m line along x, 5 m in front of two cameras looking down +z.
Line3D MakeLine() {
  Line3D line;
  line.start_in_world = Eigen::Vector3d(0, 0, 5);
  line.end_in_world = Eigen::Vector3d(1, 0, 5);
  return line;
}

// A camera turned 90 deg about the optical axis and moved, so that the
// per-view segment must be carried into the world to give its interval.
Image MakeImage(image_t image_id, const std::string& name) {
  Image image;
  image.image_id = image_id;
  image.name = name;
  image.camera_id = 1;
  image.cam_from_world = Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(0.3, -0.2, 0.1 * image_id));
  return image;
}

// The per-view segment of `image` from world points at t1 and t2 of the line,
// off the line by a few centimetres (the projection must drop them).
LineSegmentRecord MakeSegment(const Image& image, double t1, double t2) {
  const Line3D line = MakeLine();
  auto at = [&](double t, const Eigen::Vector3d& offset) {
    return image.cam_from_world *
           (line.start_in_world + t * (line.end_in_world - line.start_in_world) +
            offset);
  };
  LineSegmentRecord segment;
  segment.start3D_in_cam = at(t1, Eigen::Vector3d(0, 0.02, -0.03));
  segment.end3D_in_cam = at(t2, Eigen::Vector3d(0, -0.01, 0.02));
  return segment;
}

TEST(ObservedLineInterval, ProjectsTheViewSegmentInTheWorld) {
  const Image image = MakeImage(3, "a.png");
  // Endpoints in either order give t_begin <= t_end; beyond the track's
  // segment is not clamped.
  LineObservedInterval observation =
      ObservedLineInterval(MakeLine(), image, MakeSegment(image, 0.6, 0.2));
  EXPECT_EQ(observation.image_id, 3u);
  EXPECT_NEAR(observation.t_begin, 0.2, 1e-12);
  EXPECT_NEAR(observation.t_end, 0.6, 1e-12);
  observation =
      ObservedLineInterval(MakeLine(), image, MakeSegment(image, -0.1, 1.2));
  EXPECT_NEAR(observation.t_begin, -0.1, 1e-12);
  EXPECT_NEAR(observation.t_end, 1.2, 1e-12);

  Line3D degenerate = MakeLine();
  degenerate.end_in_world = degenerate.start_in_world;
  EXPECT_THROW(ObservedLineInterval(degenerate, image,
                                    MakeSegment(image, 0.2, 0.6)),
               Error);
}

class LineObservationsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    database_path_ = JoinPaths(testing::CreateTestDir(), "database.db");
    database_.Open(database_path_);
    const camera_t camera_id = database_.WriteCamera(
        Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240}));
    model_.cameras[1] =
        Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
    for (const char* name : {"a.png", "b.png", "c.png"}) {
      DatabaseImage db_image;
      db_image.name = name;
      db_image.camera_id = camera_id;
      const image_t image_id = database_.WriteImage(db_image);
      model_.images.push_back(MakeImage(image_id, name));
    }
    // a.png sees the first half of the line, b.png the second half; its
    // segment 0 belongs to another line. c.png's segment is not in the
    // model's track.
    const Image& a = model_.images[0];
    const Image& b = model_.images[1];
    WriteLineSegments(&database_, a.image_id, {MakeSegment(a, 0.0, 0.45)});
    WriteLineSegments(&database_, b.image_id,
                      {MakeSegment(b, 0.9, 0.9), MakeSegment(b, 1.0, 0.55)});
    Line3D line = MakeLine();
    line.track = {{a.image_id, 0}, {b.image_id, 1}};
    model_.lines3D[7] = line;
  }

  std::string database_path_;
  Database database_;
  Reconstruction model_;
};

TEST_F(LineObservationsTest, ReadsTheIntervalOfEachTrackElement) {
  const auto observations = ReadLineObservations(model_, database_);
  ASSERT_EQ(observations.size(), 1u);
  const std::vector<LineObservedInterval>& line = observations.at(7);
  ASSERT_EQ(line.size(), 2u);
  EXPECT_EQ(line[0].image_id, model_.images[0].image_id);
  EXPECT_NEAR(line[0].t_begin, 0.0, 1e-12);
  EXPECT_NEAR(line[0].t_end, 0.45, 1e-12);
  EXPECT_EQ(line[1].image_id, model_.images[1].image_id);
  EXPECT_NEAR(line[1].t_begin, 0.55, 1e-12);
  EXPECT_NEAR(line[1].t_end, 1.0, 1e-12);
}

// What rank 0 sends the other ranks of an MPI job.
TEST_F(LineObservationsTest, SerializationRoundTrips) {
  auto observations = ReadLineObservations(model_, database_);
  observations[9] = {};  // A line without an observation travels too.
  const std::string bytes = SerializeLineObservations(observations);
  const auto copy = DeserializeLineObservations(bytes);
  ASSERT_EQ(copy.size(), 2u);
  ASSERT_EQ(copy.at(7).size(), 2u);
  EXPECT_TRUE(copy.at(9).empty());
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(copy.at(7)[i].image_id, observations.at(7)[i].image_id);
    EXPECT_EQ(copy.at(7)[i].t_begin, observations.at(7)[i].t_begin);
    EXPECT_EQ(copy.at(7)[i].t_end, observations.at(7)[i].t_end);
  }
  EXPECT_THROW(DeserializeLineObservations(bytes.substr(0, bytes.size() - 1)),
               Error);
  EXPECT_THROW(DeserializeLineObservations(bytes + "x"), Error);
  EXPECT_THROW(DeserializeLineObservations(""), Error);
  // A count beyond the bytes is refused before anything is allocated.
  std::string huge = bytes;
  const uint64_t count = ~uint64_t{0} / 4;
  std::memcpy(&huge[2 * sizeof(uint64_t)], &count, sizeof(count));
  EXPECT_THROW(DeserializeLineObservations(huge), Error);
}

TEST_F(LineObservationsTest, SegmentIndexBeyondTheDatabaseNamesIt) {
  model_.lines3D[7].track.push_back({model_.images[2].image_id, 0});
  try {
    ReadLineObservations(model_, database_);
    FAIL() << "expected an error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(database_path_),
              std::string::npos)
        << error.what();
  }
}

TEST_F(LineObservationsTest, SamplesAreSeenOnlyByTheImagesThatObservedThem) {
  MeshingInputOptions options;
  options.line_sample_step_m = 0.1;  // 11 samples, t = 0, 0.1, ..., 1.
  options.validate_lines = false;  // No surface points to validate against.
  const auto observations = ReadLineObservations(model_, database_);
  MeshingInput input;
  AddCameraSensors(model_, &input);
  ASSERT_EQ(AddLineSamples(options, model_, model_, &observations, &input),
            11u);
  ASSERT_EQ(input.NumPoints(), 11u);
  // Sensor i is image i; one step of tolerance beyond each interval:
  // a.png [0, 0.45] sees t <= 0.55, b.png [0.55, 1] sees t >= 0.45.
  const std::vector<uint32_t> only_a = {0};
  const std::vector<uint32_t> only_b = {1};
  const std::vector<uint32_t> both = {0, 1};
  for (int k = 0; k <= 10; ++k) {
    const std::vector<uint32_t>& expected =
        k <= 4 ? only_a : (k >= 6 ? only_b : both);
    EXPECT_EQ(input.visibility[k], expected) << "sample " << k;
    // Each ray weighs as a visual point's of as many images (sigma 3).
    const double n = static_cast<double>(expected.size());
    EXPECT_NEAR(input.ray_weights[k], 1.0 - std::exp(-n * n / 18.0), 1e-6)
        << "sample " << k;
  }

  // Without observations every image of the track sees every sample.
  MeshingInput all;
  AddCameraSensors(model_, &all);
  ASSERT_EQ(AddLineSamples(options, model_, model_, nullptr, &all), 11u);
  for (int k = 0; k <= 10; ++k) EXPECT_EQ(all.visibility[k], both);

  // Samples that no image observed are left out.
  auto partial = observations;
  partial.at(7).pop_back();  // b.png's half is no longer observed.
  MeshingInput input_partial;
  AddCameraSensors(model_, &input_partial);
  EXPECT_EQ(AddLineSamples(options, model_, model_, &partial, &input_partial),
            6u);
}

}  // namespace
}  // namespace colmap_lidar
