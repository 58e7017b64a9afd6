#include "src/mesh/meshing_input.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/mvs/workspace.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"
#include "src/mesh/synthetic_box_scene.h"

namespace colmap_lidar {
namespace {

// Expects `function` to throw an Error whose message contains `text`.
template <typename Function>
void ExpectErrorNaming(Function&& function, const std::string& text) {
  try {
    function();
    ADD_FAILURE() << "no exception; expected one naming " << text;
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(text), std::string::npos)
        << error.what();
  }
}

class MeshingInputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_options_.box_spacing_m = 0.05;
    scene_options_.ground_spacing_m = 0.2;
    scene_ = std::make_unique<SyntheticBoxScene>(scene_options_);
    points_ = scene_->SampleVisualPoints();
    lidar_ = scene_->SimulateLidar(3, 2.0, 0.05, 0.0);
    workspace_ = testing::CreateTestDir();
    scene_->WriteWorkspace(workspace_, points_, &lidar_);
  }

  SyntheticBoxSceneOptions scene_options_;
  std::unique_ptr<SyntheticBoxScene> scene_;
  SyntheticPoints points_;
  SyntheticBoxScene::LidarVoxels lidar_;
  std::string workspace_;
};

TEST_F(MeshingInputTest, ReadsVisualLidarAndLines) {
  // Lines in a separate model folder (our lines3D.txt next to the model).
  Reconstruction lines_model = scene_->Model();
  line3D_t line3D_id = 1;
  for (const Line3D& line : scene_->BoxEdgeLines()) {
    lines_model.lines3D[line3D_id++] = line;
  }
  const std::string lines_dir = JoinPaths(workspace_, "lines");
  WriteReconstruction(lines_dir, lines_model, ModelFormat::kBinary);

  MeshingInputOptions options;
  options.line_sample_step_m = 0.1;
  options.validate_lines = false;  // Every line sampled (validated below).
  const MeshingInput input = ReadMeshingInput(options, workspace_, lines_dir);
  EXPECT_EQ(input.NumPoints(MeshingPointSource::kVisual),
            points_.positions.size());
  EXPECT_EQ(input.NumPoints(MeshingPointSource::kLidar),
            lidar_.positions.size());
  // 1.2 m edges -> 13 samples, 0.8 m -> 9 samples.
  size_t expected_line_samples = 0;
  for (const auto& [id, line] : lines_model.lines3D) {
    expected_line_samples +=
        1 + std::ceil((line.end_in_world - line.start_in_world).norm() / 0.1 - 1e-9);
  }
  EXPECT_EQ(input.NumPoints(MeshingPointSource::kLine), expected_line_samples);

  // Validated against the points (the default): the box's edges are
  // creases of its faces and the ground's, kept where the points show them
  // (the sparse ground, 0.2 m, leaves at most one out), and their samples
  // stay within a sixth of the point spacing (6 cm) of the true edges.
  options.validate_lines = true;
  options.line_samples_only_in_gaps = false;
  const MeshingInput validated =
      ReadMeshingInput(options, workspace_, lines_dir);
  const size_t num_validated = validated.NumPoints(MeshingPointSource::kLine);
  EXPECT_GE(num_validated, expected_line_samples - 13);
  EXPECT_LE(num_validated, expected_line_samples);
  for (size_t i = 0; i < validated.NumPoints(); ++i) {
    if (validated.sources[i] != MeshingPointSource::kLine) continue;
    double distance = std::numeric_limits<double>::infinity();
    for (const auto& [id, line] : lines_model.lines3D) {
      const Eigen::Vector3d direction =
          (line.end_in_world - line.start_in_world).normalized();
      const Eigen::Vector3d offset =
          validated.positions[i] - line.start_in_world;
      distance = std::min(
          distance, (offset - offset.dot(direction) * direction).norm());
    }
    EXPECT_LT(distance, 0.01) << "line sample " << i;
  }
  // By default only the samples with no visual or LIDAR point within the
  // validation's plane band are kept: fewer, each in a gap of the points.
  options.line_samples_only_in_gaps = true;
  const MeshingInput gaps = ReadMeshingInput(options, workspace_, lines_dir);
  ASSERT_FALSE(gaps.creases.empty());
  const double band = gaps.creases[0].plane_band_m;
  EXPECT_GT(band, 0);
  const size_t num_in_gaps = gaps.NumPoints(MeshingPointSource::kLine);
  EXPECT_GT(num_in_gaps, 0u);
  EXPECT_LT(num_in_gaps, num_validated);
  // The same creases to snap to.
  EXPECT_EQ(gaps.creases.size(), validated.creases.size());
  for (size_t i = 0; i < gaps.NumPoints(); ++i) {
    if (gaps.sources[i] != MeshingPointSource::kLine) continue;
    for (size_t j = 0; j < gaps.NumPoints(); ++j) {
      if (gaps.sources[j] == MeshingPointSource::kLine) continue;
      ASSERT_GE((gaps.positions[j] - gaps.positions[i]).norm(), band)
          << "line sample " << i << " near surface point " << j;
    }
  }
  // The default step is the points' spacing s that the validation measures
  // (6.3 cm on the box): every validated line sampled at its end points and
  // at most s apart, as few samples as that allows.
  options.line_samples_only_in_gaps = false;
  options.line_sample_step_m = 0;
  const MeshingInput spaced = ReadMeshingInput(options, workspace_, lines_dir);
  const double spacing = spaced.crease_spacing_m;
  ASSERT_GT(spacing, 0.02);
  ASSERT_LT(spacing, 0.1);
  EXPECT_EQ(spaced.creases.size(), validated.creases.size());
  size_t expected_spaced = 0;
  for (const MeshCrease& crease : spaced.creases) {
    expected_spaced +=
        1 + std::ceil((crease.end - crease.start).norm() / spacing - 1e-9);
  }
  EXPECT_EQ(spaced.NumPoints(MeshingPointSource::kLine), expected_spaced);
  EXPECT_GT(expected_spaced, num_validated);
  // Without the validation the spacing is measured all the same, and every
  // line sampled where estimated.
  options.validate_lines = false;
  const MeshingInput unvalidated =
      ReadMeshingInput(options, workspace_, lines_dir);
  size_t expected_unvalidated = 0;
  for (const auto& [id, line] : lines_model.lines3D) {
    expected_unvalidated +=
        1 +
        std::ceil((line.end_in_world - line.start_in_world).norm() / spacing -
                  1e-9);
  }
  EXPECT_EQ(unvalidated.NumPoints(MeshingPointSource::kLine),
            expected_unvalidated);
  // 12 cameras + 3 LIDAR origins.
  ASSERT_EQ(input.sensors.size(), 15u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_FALSE(input.sensors[12 + i].is_camera);
  }
  // LIDAR sensors are created in order of first use; each is an origin.
  for (int i = 0; i < 3; ++i) {
    int num_matches = 0;
    for (int frame = 0; frame < 3; ++frame) {
      num_matches += input.sensors[12 + i].position_in_world.isApprox(
                         scene_->LidarOrigin(frame))
                         ? 1
                         : 0;
    }
    EXPECT_EQ(num_matches, 1);
  }
  // Camera sensors project their own points inside the image.
  for (size_t i = 0; i < points_.positions.size(); i += 101) {
    for (const uint32_t sensor : input.visibility[i]) {
      const Eigen::Vector2d pixel =
          (input.sensors[sensor].proj_matrix * input.positions[i].homogeneous())
              .hnormalized();
      EXPECT_GE(pixel.x(), 0);
      EXPECT_LT(pixel.x(), scene_options_.image_width);
    }
  }
  // LIDAR weights: log mapping, spread over the frames.
  const size_t first_lidar = points_.positions.size();
  EXPECT_NEAR(input.ray_weights[first_lidar],
              (1 + std::log(lidar_.counts[0])) / lidar_.frames[0].size(), 1e-5);

  options.use_lidar = false;
  EXPECT_EQ(ReadMeshingInput(options, workspace_).NumPoints(MeshingPointSource::kLidar), 0u);
  options.use_lidar = true;
  options.use_visual = false;
  EXPECT_EQ(ReadMeshingInput(options, workspace_).NumPoints(MeshingPointSource::kVisual), 0u);
}

// With a cap of one ray, a LIDAR voxel keeps the ray from its nearest
// scanner position, with the voxel's whole weight.
TEST_F(MeshingInputTest, LidarRaysCappedToTheNearestScanners) {
  MeshingInputOptions options;
  options.use_visual = false;
  options.max_lidar_rays_per_point = 1;
  const MeshingInput input = ReadMeshingInput(options, workspace_);
  ASSERT_EQ(input.positions.size(), lidar_.positions.size());
  size_t num_multi_frame = 0;
  for (size_t i = 0; i < input.positions.size(); ++i) {
    ASSERT_EQ(input.visibility[i].size(), 1u) << i;
    const double kept = (input.sensors[input.visibility[i][0]]
                             .position_in_world - input.positions[i])
                            .norm();
    for (const uint32_t frame : lidar_.frames[i]) {
      EXPECT_LE(kept, (scene_->LidarOrigin(frame) - input.positions[i])
                          .norm() + 1e-9);
    }
    num_multi_frame += lidar_.frames[i].size() > 1 ? 1 : 0;
    EXPECT_NEAR(input.ray_weights[i], 1 + std::log(lidar_.counts[i]), 1e-5);
  }
  EXPECT_GT(num_multi_frame, 0u);
  options.max_lidar_rays_per_point = -1;
  EXPECT_FALSE(options.Check());
}

TEST_F(MeshingInputTest, ErrorsNameTheFile) {
  const MeshingInputOptions options;
  // A .vis file with one entry too many.
  FusedVisibility visibility = points_.visibility;
  visibility.push_back({0});
  WriteFusedVis(JoinPaths(workspace_, "fused.ply.vis"), visibility);
  ExpectErrorNaming([&] { ReadMeshingInput(options, workspace_); },
                    "fused.ply.vis");
  // A .vis index beyond the model's images.
  visibility = points_.visibility;
  visibility[0] = {99};
  WriteFusedVis(JoinPaths(workspace_, "fused.ply.vis"), visibility);
  ExpectErrorNaming([&] { ReadMeshingInput(options, workspace_); },
                    "fused.ply.vis");
  WriteFusedVis(JoinPaths(workspace_, "fused.ply.vis"), points_.visibility);
  // Missing fused.ply.
  std::filesystem::rename(JoinPaths(workspace_, "fused.ply"),
                          JoinPaths(workspace_, "fused.bak"));
  ExpectErrorNaming([&] { ReadMeshingInput(options, workspace_); },
                    "fused.ply");
  std::filesystem::rename(JoinPaths(workspace_, "fused.bak"),
                          JoinPaths(workspace_, "fused.ply"));
  // LIDAR vis count mismatch.
  FusedVisibility frames = lidar_.frames;
  frames.pop_back();
  WriteFusedVis(LidarFusedVisPath(workspace_), frames);
  ExpectErrorNaming([&] { ReadMeshingInput(options, workspace_); },
                    "lidar_fused.ply.vis");
  WriteFusedVis(LidarFusedVisPath(workspace_), lidar_.frames);
  // A frame without origin.
  WriteLidarOrigins(LidarOriginsPath(workspace_),
                    {{scene_->Model().images[0].name, scene_->LidarOrigin(0)}});
  ExpectErrorNaming([&] { ReadMeshingInput(options, workspace_); },
                    "lidar_origins.txt");
  // Missing origins file.
  std::filesystem::remove(LidarOriginsPath(workspace_));
  ExpectErrorNaming([&] { ReadMeshingInput(options, workspace_); },
                    "lidar_origins.txt");
  // A lines folder without lines.
  MeshingInputOptions visual_only;
  visual_only.use_lidar = false;
  ExpectErrorNaming(
      [&] {
        ReadMeshingInput(visual_only, workspace_,
                         JoinPaths(workspace_, "sparse"));
      },
      "sparse");
  ExpectErrorNaming(
      [&] { ReadMeshingInput(options, JoinPaths(workspace_, "nothing")); },
      "nothing");
}

TEST_F(MeshingInputTest, CreasesWithAStepsSideFaceAreSnappedToNotSampled) {
  // Surface points drawn uniformly, one per 4 cm^2, away from the box: a 6
  // cm step along x (near floor z = 0.06 for y in (10, 10.6], riser y = 10,
  // far floor z = 0 for y in [9.4, 10)) and a wall on a floor (y = 20,
  // z >= 0 and z = 0 for y < 20).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  MeshingInput input;
  AddCameraSensors(scene_->Model(), &input);
  const auto add = [&](double x, double y, double z) {
    input.AddPoint(Eigen::Vector3d(x, y, z), MeshingPointSource::kVisual, 1,
                   {});
  };
  for (int i = 0; i < 3000; ++i) {
    add(-1 + 2 * uniform(rng), 10 + 0.6 * uniform(rng), 0.06);
    add(-1 + 2 * uniform(rng), 10 - 0.6 * uniform(rng), 0.0);
    add(-1 + 2 * uniform(rng), 20, 0.6 * uniform(rng));
    add(-1 + 2 * uniform(rng), 20 - 0.6 * uniform(rng), 0.0);
  }
  for (int i = 0; i < 300; ++i) {
    add(-1 + 2 * uniform(rng), 10, 0.06 * uniform(rng));
  }
  // The step's top edge and the wall's foot, seen by the scene's first
  // image.
  Reconstruction lines_model = scene_->Model();
  const image_t image_id = lines_model.images.front().image_id;
  Line3D step;
  step.start_in_world = Eigen::Vector3d(-0.8, 10.005, 0.063);
  step.end_in_world = Eigen::Vector3d(0.8, 10.005, 0.063);
  step.track = {{image_id, 0}};
  Line3D foot = step;
  foot.start_in_world = Eigen::Vector3d(-0.8, 20.0, 0.0);
  foot.end_in_world = Eigen::Vector3d(0.8, 20.0, 0.0);
  lines_model.lines3D[1] = step;
  lines_model.lines3D[2] = foot;
  MeshingInputOptions options;
  options.line_sample_step_m = 0.1;
  options.line_samples_only_in_gaps = false;  // Tested above.
  const size_t num_samples =
      AddLineSamples(options, scene_->Model(), lines_model, nullptr, &input);
  // Only the wall's foot is sampled: 17 samples over 1.6 m.
  EXPECT_EQ(num_samples, 17u);
  EXPECT_EQ(input.NumPoints(MeshingPointSource::kLine), 17u);
  for (size_t i = 0; i < input.NumPoints(); ++i) {
    if (input.sources[i] == MeshingPointSource::kLine) {
      EXPECT_NEAR(input.positions[i].y(), 20.0, 0.01);
    }
  }
  // Both are creases to snap to, the step's moved onto its top edge.
  ASSERT_EQ(input.creases.size(), 2u);
  const MeshCrease& step_crease = input.creases[0];
  EXPECT_LT(
      std::hypot(step_crease.start.y() - 10, step_crease.start.z() - 0.06),
      0.005);
  EXPECT_GT(input.crease_spacing_m, 0);
  for (const MeshCrease& crease : input.creases) {
    EXPECT_GT(crease.plane_band_m, 0);
  }
}

TEST(LidarOrigins, RoundTripNamesWithSpacesAndErrors) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "lidar_origins.txt");
  WriteLidarOrigins(path, {{"cam0/a b.png", Eigen::Vector3d(1, 2.5, -3)},
                           {"x.png", Eigen::Vector3d(0.1, 0, 1e-7)}});
  const auto origins = ReadLidarOrigins(path);
  ASSERT_EQ(origins.size(), 2u);
  EXPECT_EQ(origins[0].first, "cam0/a b.png");
  EXPECT_EQ(origins[0].second, Eigen::Vector3d(1, 2.5, -3));
  EXPECT_EQ(origins[1].second, Eigen::Vector3d(0.1, 0, 1e-7));
  WriteFileAtomically(path, [](std::ostream& s) { s << "x.png 1 2\n"; }, false);
  ExpectErrorNaming([&] { ReadLidarOrigins(path); }, "lidar_origins.txt:1");
  WriteFileAtomically(
      path, [](std::ostream& s) { s << "# c\nx.png 1 2 3\nx.png 1 2 3\n"; },
      false);
  ExpectErrorNaming([&] { ReadLidarOrigins(path); }, "lidar_origins.txt:3");
}

TEST(MeshingInputOptions, Check) {
  MeshingInputOptions options;
  EXPECT_TRUE(options.Check());
  options.lidar_count_mapping = "cubic";
  EXPECT_FALSE(options.Check());
  options = MeshingInputOptions();
  options.line_sample_step_m = 0;  // The points' spacing.
  EXPECT_TRUE(options.Check());
  options.line_sample_step_m = -0.01;
  EXPECT_FALSE(options.Check());
  options.line_sample_step_m = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(options.Check());
  EXPECT_EQ(LidarCountMappingFromString("LINEAR"), LidarCountMapping::kLinear);
}

}  // namespace
}  // namespace colmap_lidar
