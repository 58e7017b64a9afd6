#include "src/eval/depth_evaluator.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/mvs/workspace.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/calibration.h"

namespace colmap_lidar {
namespace {

// A steep plane in the camera frame, z = 4 + 1.5 x: along the ray
// (u, v, 1) the z-depth is 4 / (1 - 1.5 u), which changes by 2.5 to 28 cm
// per pixel of the test cameras (less than the 5 % that still allows
// bilinear sampling), so a half-pixel slip in either camera mapping shows
// as errors > 2 cm.
double PlaneDepth(const Eigen::Vector3d& ray) {
  const Eigen::Vector2d uv = ray.hnormalized();
  return 4.0 / (1.0 - 1.5 * uv.x());
}

// The truth as the synthesizer writes it: pixel (col, row) holds the depth
// along the ray of image point (col, row) of `camera`.
DepthMap RenderTruth(const Camera& camera) {
  DepthMap truth(camera.width, camera.height);
  for (size_t row = 0; row < camera.height; ++row) {
    for (size_t col = 0; col < camera.width; ++col) {
      const Eigen::Vector2d uv = camera.CamFromImg(Eigen::Vector2d(col, row));
      truth.Set(row, col, static_cast<float>(PlaneDepth(uv.homogeneous())));
    }
  }
  return truth;
}

// Our map on a PINHOLE camera with another focal length and size.
DepthMap RenderEstimate(const Eigen::Matrix3d& K, size_t width, size_t height) {
  DepthMap estimate(width, height);
  for (size_t row = 0; row < height; ++row) {
    for (size_t col = 0; col < width; ++col) {
      estimate.Set(row, col,
                   static_cast<float>(PlaneDepth(MvsPixelRay(K, row, col))));
    }
  }
  return estimate;
}

Camera DistortedTruthCamera() {
  return Camera::FromModelName("SIMPLE_RADIAL", 80, 60,
                               {100.0, 40.0, 30.0, -0.05});
}

Camera UndistortedCamera() {
  return Camera::FromModelName("PINHOLE", 70, 50, {95.0, 95.0, 35.0, 25.0});
}

TEST(DepthEvaluator, ExactMapsThroughADistortedCameraAgree) {
  const Camera truth_camera = DistortedTruthCamera();
  const Camera camera = UndistortedCamera();
  const DepthMap truth = RenderTruth(truth_camera);
  const DepthMap estimate =
      RenderEstimate(camera.CalibrationMatrix(), camera.width, camera.height);
  const DepthEvaluationOptions options;
  const DepthErrors errors = CompareDepthMaps(
      estimate, camera.CalibrationMatrix(), truth, truth_camera, options);
  EXPECT_EQ(errors.num_pixels, 70u * 50u);
  // The undistorted field lies inside the distorted one.
  EXPECT_EQ(errors.num_truth_valid, errors.num_pixels);
  EXPECT_EQ(errors.num_covered, errors.num_pixels);
  const DepthStats stats = ComputeDepthStats(errors, options.thresholds_m);
  EXPECT_DOUBLE_EQ(stats.coverage, 1.0);
  EXPECT_DOUBLE_EQ(stats.within[0], 1.0);
  EXPECT_LT(stats.median_abs_error_m, 0.002);

  // The same with the half-pixel SfM offset wrongly applied to our rays:
  // the evaluator must see it.
  Eigen::Matrix3d K_shifted = camera.CalibrationMatrix();
  K_shifted(0, 2) += 0.5;
  const DepthMap shifted = RenderEstimate(K_shifted, camera.width,
                                          camera.height);
  const DepthStats shifted_stats = ComputeDepthStats(
      CompareDepthMaps(shifted, camera.CalibrationMatrix(), truth,
                       truth_camera, options),
      options.thresholds_m);
  EXPECT_LT(shifted_stats.within[0], 0.5);
}

TEST(DepthEvaluator, OffsetsHolesAndInventedDepth) {
  const Camera truth_camera = Camera::FromModelName(
      "PINHOLE", 80, 60, {100.0, 100.0, 40.0, 30.0});
  DepthMap truth = RenderTruth(truth_camera);
  // The top 10 truth rows see the sky.
  for (size_t row = 0; row < 10; ++row) {
    for (size_t col = 0; col < truth.GetWidth(); ++col) truth.Set(row, col, 0);
  }
  // Our map at half resolution: K scaled as stereo_fusion does.
  const Eigen::Matrix3d K = ScaleCalibrationToMap(
      truth_camera.CalibrationMatrix(), 80, 60, 40, 30);
  DepthMap estimate = RenderEstimate(K, 40, 30);
  size_t num_truth_valid = 0;
  size_t num_without_truth = 0;
  size_t num_covered = 0;
  size_t num_offset_3cm = 0;
  size_t num_offset_20cm = 0;
  for (size_t row = 0; row < 30; ++row) {
    for (size_t col = 0; col < 40; ++col) {
      // Our row r looks along truth row 2 r (+ 0.5 px from the scaling).
      const bool truth_valid = 2 * row >= 10;
      if (!truth_valid) {
        // Sky where we invent depth in half of the columns.
        if (col % 2 == 0) {
          estimate.Set(row, col, 0);
        } else {
          ++num_without_truth;
        }
        continue;
      }
      ++num_truth_valid;
      if (col < 5) {
        estimate.Set(row, col, 0);  // A hole.
        continue;
      }
      ++num_covered;
      if (col >= 30) {
        estimate.Set(row, col, estimate.Get(row, col) + 0.2f);
        ++num_offset_20cm;
      } else if (col >= 20) {
        estimate.Set(row, col, estimate.Get(row, col) - 0.03f);
        ++num_offset_3cm;
      }
    }
  }
  DepthEvaluationOptions options;
  options.thresholds_m = {0.02, 0.05, 0.1};
  const DepthErrors errors =
      CompareDepthMaps(estimate, K, truth, truth_camera, options);
  EXPECT_EQ(errors.num_truth_valid, num_truth_valid);
  EXPECT_EQ(errors.num_covered, num_covered);
  EXPECT_EQ(errors.num_without_truth, num_without_truth);
  const DepthStats stats = ComputeDepthStats(errors, options.thresholds_m);
  const double covered = static_cast<double>(num_covered);
  EXPECT_NEAR(stats.coverage, covered / num_truth_valid, 1e-12);
  EXPECT_NEAR(stats.within[0],
              (covered - num_offset_3cm - num_offset_20cm) / covered, 1e-12);
  EXPECT_NEAR(stats.within[1], (covered - num_offset_20cm) / covered, 1e-12);
  EXPECT_NEAR(stats.within[2], (covered - num_offset_20cm) / covered, 1e-12);
  EXPECT_NEAR(stats.mean_abs_error_m,
              (0.03 * num_offset_3cm + 0.2 * num_offset_20cm) / covered,
              2e-3);
}

// Surface distances: a depth offset along the ray is a smaller offset from
// a plane the ray meets obliquely, by |r . n| (r with z = 1). On the plane
// z = 4 + 1.5 x (normal (-1.5, 0, 1) / |.|), an estimate 10 cm too deep is
// 0.1 |1 - 1.5 u| / sqrt(3.25) off the surface at ray (u, v, 1); where the
// truth has a depth edge the distance is the depth error itself.
TEST(DepthEvaluator, SurfaceDistanceIsTheOffsetAlongTheNormal) {
  const Camera camera =
      Camera::FromModelName("PINHOLE", 60, 40, {100.0, 100.0, 30.0, 20.0});
  const DepthMap truth = RenderTruth(camera);
  const Eigen::Matrix3d K = camera.CalibrationMatrix();
  DepthMap estimate = RenderEstimate(K, camera.width, camera.height);
  for (size_t row = 0; row < camera.height; ++row) {
    for (size_t col = 0; col < camera.width; ++col) {
      estimate.Set(row, col, estimate.Get(row, col) + 0.1f);
    }
  }
  const DepthEvaluationOptions options;
  const DepthErrors errors =
      CompareDepthMaps(estimate, K, truth, camera, options);
  ASSERT_EQ(errors.surface_errors_m.size(), camera.width * camera.height);
  size_t num_within_5cm = 0;
  for (size_t row = 0; row < camera.height; ++row) {
    for (size_t col = 0; col < camera.width; ++col) {
      const Eigen::Vector3d ray = MvsPixelRay(K, row, col);
      const double expected =
          0.1 * std::abs(1.0 - 1.5 * ray.x()) / std::sqrt(3.25);
      const size_t i = row * camera.width + col;
      EXPECT_NEAR(errors.abs_errors_m[i], 0.1, 1e-5);
      EXPECT_NEAR(errors.surface_errors_m[i], expected, 1e-4)
          << "row " << row << " col " << col;
      num_within_5cm += expected < 0.05 ? 1 : 0;
    }
  }
  const DepthStats stats = ComputeDepthStats(errors, options.thresholds_m);
  EXPECT_DOUBLE_EQ(stats.within[1], 0.0);
  EXPECT_GT(num_within_5cm, 0u);
  EXPECT_NEAR(stats.surface_within[1],
              static_cast<double>(num_within_5cm) / errors.num_covered, 1e-12);

  // A depth edge (every other column 1 m nearer): no normal, the depth
  // error itself.
  DepthMap stripes = truth;
  DepthMap stripes_estimate = estimate;
  for (size_t row = 0; row < camera.height; ++row) {
    for (size_t col = 1; col < camera.width; col += 2) {
      stripes.Set(row, col, truth.Get(row, col) - 1.0f);
      stripes_estimate.Set(row, col, estimate.Get(row, col) - 1.0f);
    }
  }
  const DepthErrors edge_errors =
      CompareDepthMaps(stripes_estimate, K, stripes, camera, options);
  for (size_t i = 0; i < edge_errors.surface_errors_m.size(); ++i) {
    EXPECT_NEAR(edge_errors.surface_errors_m[i], 0.1, 1e-5);
  }
}

// A depth edge: the truth jumps from 2 m to 6 m between two columns; the
// evaluator takes the nearest truth pixel there instead of blending.
TEST(DepthEvaluator, DepthEdgesAreNotBlended) {
  const Camera truth_camera =
      Camera::FromModelName("PINHOLE", 20, 10, {20.0, 20.0, 10.0, 5.0});
  DepthMap truth(20, 10);
  for (size_t row = 0; row < 10; ++row) {
    for (size_t col = 0; col < 20; ++col) {
      truth.Set(row, col, col < 10 ? 2 : 6);
    }
  }
  // Our pixel (col, row) looks at truth column col + 0.4.
  Eigen::Matrix3d K = truth_camera.CalibrationMatrix();
  K(0, 2) -= 0.4;
  DepthMap estimate(20, 10);
  for (size_t row = 0; row < 10; ++row) {
    for (size_t col = 0; col < 20; ++col) {
      estimate.Set(row, col, col < 10 ? 2 : 6);
    }
  }
  DepthEvaluationOptions options;
  const DepthStats stats = ComputeDepthStats(
      CompareDepthMaps(estimate, K, truth, truth_camera, options),
      options.thresholds_m);
  EXPECT_DOUBLE_EQ(stats.within[0], 1.0);
  // Always bilinear would blend column 9 with column 10 (3.6 m) in the 9
  // rows that have a row below them (the last row takes the nearest).
  options.max_bilinear_spread = 1e9;
  const DepthStats blended = ComputeDepthStats(
      CompareDepthMaps(estimate, K, truth, truth_camera, options),
      options.thresholds_m);
  EXPECT_NEAR(blended.within[0], 1.0 - 9.0 / 200.0, 1e-12);
}

// Files: a dataset with calibration.yaml and ground_truth/depth_maps, a
// dense workspace with one image of a sub-folder-free name, and the JSON
// keys scripts/matrix_table.py reads.
TEST(DepthEvaluator, FilesAndJson) {
  const std::string root = testing::CreateTestDir();
  const std::string dataset = JoinPaths(root, "dataset");
  const std::string dense = JoinPaths(root, "dense");
  CreateDirIfNotExists(dataset);
  CreateDirIfNotExists(JoinPaths(dataset, "ground_truth"));
  CreateDirIfNotExists(JoinPaths(dataset, "ground_truth/depth_maps"));
  RigCalibration calibration;
  calibration.camera = DistortedTruthCamera();
  WriteCalibration(JoinPaths(dataset, "calibration.yaml"), calibration);
  RenderTruth(calibration.camera)
      .Write(JoinPaths(dataset, "ground_truth/depth_maps/000007.bin"));

  CreateDenseWorkspaceLayout(dense, {"000007.png", "000008.png"});
  Reconstruction model;
  Camera camera = UndistortedCamera();
  camera.camera_id = 1;
  model.cameras[1] = camera;
  for (const image_t id : {1, 2}) {
    Image image;
    image.image_id = id;
    image.camera_id = 1;
    image.name = id == 1 ? "000007.png" : "000008.png";
    model.images.push_back(image);
  }
  const DenseWorkspace workspace(dense);
  WriteReconstruction(workspace.SparseDir(), model, ModelFormat::kBinary);
  DepthMap estimate =
      RenderEstimate(camera.CalibrationMatrix(), camera.width, camera.height);
  estimate.Write(
      workspace.DepthMapPath("000007.png", DenseMapType::kGeometric));
  estimate.Set(0, 0, estimate.Get(0, 0) + 1.0f);
  estimate.Write(
      workspace.DepthMapPath("000007.png", DenseMapType::kPhotometric));

  DepthEvaluationOptions options;
  options.num_threads = 2;
  const DepthEvaluation evaluation =
      EvaluateDepthMaps(dense, dataset, options);
  ASSERT_EQ(evaluation.map_types.size(), 2u);
  EXPECT_EQ(evaluation.map_types[1], "geometric");
  EXPECT_EQ(evaluation.num_images_without_truth, 1u);
  ASSERT_EQ(evaluation.images.size(), 1u);
  EXPECT_DOUBLE_EQ(evaluation.overall[1].within[1], 1.0);
  EXPECT_NEAR(evaluation.overall[0].within[1], 1.0 - 1.0 / (70 * 50), 1e-12);
  EXPECT_EQ(DepthThresholdKey(0.05), "within_5cm");
  EXPECT_EQ(DepthThresholdKey(0.005), "within_0.5cm");

  const std::string json_path = JoinPaths(root, "depth_maps.json");
  WriteDepthEvaluationJson(json_path, evaluation);
  const Json json = ReadJsonFile(json_path);
  EXPECT_EQ(json.at("evaluator"), "depth_maps");
  EXPECT_EQ(json.at("num_images"), 1);
  EXPECT_EQ(json.at("num_images_without_truth"), 1);
  const Json& geometric = json.at("overall").at("geometric");
  EXPECT_EQ(geometric.at("coverage"), 1.0);
  EXPECT_EQ(geometric.at("within_5cm"), 1.0);
  EXPECT_EQ(geometric.at("surface_within_5cm"), 1.0);
  const Json& photometric = json.at("overall").at("photometric");
  EXPECT_TRUE(photometric.at("within_2cm").is_number_float());
  EXPECT_EQ(photometric.at("within_5cm").get<double>(),
            evaluation.overall[0].within[1]);
  EXPECT_EQ(geometric.at("num_pixels"), evaluation.overall[1].num_pixels);
  ASSERT_EQ(json.at("images").size(), 1u);
  EXPECT_EQ(json.at("images").at(0).at("name"), "000007.png");
  EXPECT_TRUE(json.at("images").at(0).contains("geometric"));

  // Missing truth folder and bad options are errors naming the problem.
  EXPECT_THROW(EvaluateDepthMaps(dense, root, options), Error);
  options.map_types = {"fused"};
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(EvaluateDepthMaps(dense, dataset, options), Error);
}

// Random per-map errors spanning four decades, the way depth errors do
// (most below a centimetre, a tail of metres).
DepthErrors RandomErrors(std::mt19937* rng, size_t count) {
  std::lognormal_distribution<float> error_m(std::log(0.007f), 1.5f);
  std::uniform_real_distribution<float> cosine(0.05f, 1.0f);
  DepthErrors errors;
  errors.num_pixels = count + 17;
  errors.num_truth_valid = count + 5;
  errors.num_covered = count;
  errors.num_without_truth = 3;
  for (size_t i = 0; i < count; ++i) {
    const float error = error_m(*rng);
    errors.abs_errors_m.push_back(error);
    errors.surface_errors_m.push_back(error * cosine(*rng));
  }
  return errors;
}

TEST(DepthErrorAccumulator, MatchesTheFiguresOfAllErrorsTogether) {
  const std::vector<double> thresholds_m = {0.02, 0.05, 0.1};
  std::mt19937 rng(7);
  std::vector<DepthErrors> maps;
  DepthErrors all;
  for (const size_t count : {20000u, 1u, 0u, 33333u, 4096u}) {
    maps.push_back(RandomErrors(&rng, count));
    const DepthErrors& map = maps.back();
    all.num_pixels += map.num_pixels;
    all.num_truth_valid += map.num_truth_valid;
    all.num_covered += map.num_covered;
    all.num_without_truth += map.num_without_truth;
    all.abs_errors_m.insert(all.abs_errors_m.end(), map.abs_errors_m.begin(),
                            map.abs_errors_m.end());
    all.surface_errors_m.insert(all.surface_errors_m.end(),
                                map.surface_errors_m.begin(),
                                map.surface_errors_m.end());
  }
  const DepthStats exact = ComputeDepthStats(all, thresholds_m);

  DepthErrorAccumulator forward(thresholds_m, maps.size());
  for (size_t i = 0; i < maps.size(); ++i) forward.Add(i, maps[i]);
  const DepthStats stats = forward.Stats();
  EXPECT_EQ(stats.num_pixels, exact.num_pixels);
  EXPECT_EQ(stats.num_truth_valid, exact.num_truth_valid);
  EXPECT_EQ(stats.num_covered, exact.num_covered);
  EXPECT_EQ(stats.num_without_truth, exact.num_without_truth);
  EXPECT_EQ(stats.coverage, exact.coverage);
  EXPECT_EQ(stats.within, exact.within);
  EXPECT_EQ(stats.surface_within, exact.surface_within);
  EXPECT_NEAR(stats.mean_abs_error_m, exact.mean_abs_error_m,
              1e-12 * exact.mean_abs_error_m);
  EXPECT_NE(stats.median_abs_error_m, 0.0);
  EXPECT_NEAR(stats.median_abs_error_m, exact.median_abs_error_m,
              2.5e-4 * exact.median_abs_error_m);

  // Any order of the maps (threads) gives the same figures, bit for bit.
  DepthErrorAccumulator backward(thresholds_m, maps.size());
  for (size_t i = maps.size(); i-- > 0;) backward.Add(i, maps[i]);
  const DepthStats reversed = backward.Stats();
  EXPECT_EQ(reversed.mean_abs_error_m, stats.mean_abs_error_m);
  EXPECT_EQ(reversed.median_abs_error_m, stats.median_abs_error_m);

  // Ranks read off the histogram are ordered and within their bin.
  std::vector<float> sorted = all.abs_errors_m;
  std::sort(sorted.begin(), sorted.end());
  double previous = 0.0;
  for (size_t rank = 0; rank < sorted.size(); rank += 997) {
    const double value = forward.ValueAtRank(rank);
    EXPECT_GE(value, previous);
    EXPECT_NEAR(value, sorted[rank], 2.5e-4 * sorted[rank]);
    previous = value;
  }
  EXPECT_THROW(forward.ValueAtRank(sorted.size()), Error);

  // Each slot once, and only the slots asked for.
  EXPECT_THROW(forward.Add(0, maps[0]), Error);
  EXPECT_THROW(forward.Add(maps.size(), maps[0]), Error);
}

TEST(DepthErrorAccumulator, NothingAddedAndTinyErrors) {
  DepthErrorAccumulator empty({0.05}, 2);
  const DepthStats none = empty.Stats();
  EXPECT_EQ(none.num_covered, 0u);
  EXPECT_EQ(none.coverage, 0.0);
  EXPECT_EQ(none.within, std::vector<double>({0.0}));

  // Exact zeros (a perfect map) and a value at the histogram's top.
  DepthErrors errors;
  errors.num_pixels = errors.num_truth_valid = errors.num_covered = 3;
  errors.abs_errors_m = {0.0f, 0.0f, 1e30f};
  errors.surface_errors_m = errors.abs_errors_m;
  DepthErrorAccumulator accumulator({0.05}, 1);
  accumulator.Add(0, errors);
  const DepthStats stats = accumulator.Stats();
  EXPECT_LT(stats.median_abs_error_m, 1e-40);
  EXPECT_NEAR(accumulator.ValueAtRank(2), 1e30, 1e27);
  EXPECT_NEAR(stats.within[0], 2.0 / 3.0, 1e-15);
}

}  // namespace
}  // namespace colmap_lidar
