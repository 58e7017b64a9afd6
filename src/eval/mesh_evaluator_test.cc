#include "src/eval/mesh_evaluator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

struct Mesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;

  void AddQuad(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
               const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
    const int base = vertices.size();
    vertices.insert(vertices.end(), {a, b, c, d});
    triangles.emplace_back(base, base + 1, base + 2);
    triangles.emplace_back(base, base + 2, base + 3);
  }
};

// The axis-aligned unit cube [0,1]^3 shifted by `offset`.
Mesh Cube(const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
  Mesh mesh;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    for (const double side : {0.0, 1.0}) {
      Eigen::Vector3d corners[4];
      const double uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (int k = 0; k < 4; ++k) {
        corners[k][axis] = side;
        corners[k][u] = uv[k][0];
        corners[k][v] = uv[k][1];
        corners[k] += offset;
      }
      mesh.AddQuad(corners[0], corners[1], corners[2], corners[3]);
    }
  }
  return mesh;
}

// Cell-centred grid points (spacing 1/n) on the square [x0,x0+1]x[y0,y0+1]
// at height z.
std::vector<Eigen::Vector3d> SquareGrid(double x0, double y0, double z,
                                        int n = 200) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      points.emplace_back(x0 + (i + 0.5) / n, y0 + (j + 0.5) / n, z);
    }
  }
  return points;
}

// Cell-centred grid points on the six faces of the unit cube.
std::vector<Eigen::Vector3d> CubeGrid(int n = 200) {
  std::vector<Eigen::Vector3d> points;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double side : {0.0, 1.0}) {
      for (const Eigen::Vector3d& p : SquareGrid(0, 0, 0, n)) {
        Eigen::Vector3d point;
        point[axis] = side;
        point[(axis + 1) % 3] = p.x();
        point[(axis + 2) % 3] = p.y();
        points.push_back(point);
      }
    }
  }
  return points;
}

Mesh UnitSquare(double x0 = 0.0, double y0 = 0.0) {
  Mesh mesh;
  mesh.AddQuad({x0, y0, 0}, {x0 + 1, y0, 0}, {x0 + 1, y0 + 1, 0},
               {x0, y0 + 1, 0});
  return mesh;
}

TEST(MeshEvaluator, CubeAgainstItsSamplingIsPerfect) {
  const Mesh cube = Cube();
  MeshEvaluationOptions options;
  options.thresholds_m = {0.005, 0.01};
  const MeshEvaluation evaluation =
      EvaluateMesh(cube.vertices, cube.triangles, CubeGrid(), {}, options);
  EXPECT_TRUE(evaluation.estimate_is_mesh);
  EXPECT_NEAR(evaluation.estimate_area_m2, 6.0, 1e-12);
  EXPECT_EQ(evaluation.estimate_points.size(), 6000u);
  EXPECT_EQ(evaluation.num_estimate_points_in_crop, 6000u);
  // Grid spacing 5 mm: samples are at most 3.6 mm from a grid point.
  EXPECT_DOUBLE_EQ(evaluation.precisions[1], 1.0);
  EXPECT_DOUBLE_EQ(evaluation.recalls[1], 1.0);
  EXPECT_DOUBLE_EQ(evaluation.fscores[1], 1.0);
  EXPECT_LT(evaluation.accuracy_m.max, 0.0036);
  // Reference points lie on the mesh: exact zero distance.
  EXPECT_LT(evaluation.completeness_m.max, 1e-12);
}

// A unit square at z = 0 against a reference plane at z = 0.03: every
// distance is 0.03 (plus < 3.6 mm in-plane for the grid), so precision and
// recall are 0 at 0.02 and 1 at 0.05.
TEST(MeshEvaluator, PlaneShiftedByThreeCentimetres) {
  const Mesh square = UnitSquare();
  MeshEvaluationOptions options;
  options.thresholds_m = {0.02, 0.05};
  for (const bool recall_to_mesh : {true, false}) {
    options.recall_to_mesh = recall_to_mesh;
    // Dense sampling so that sample-based recall sees no holes > 4 cm.
    options.sample_density_per_m2 = 20000;
    const MeshEvaluation evaluation = EvaluateMesh(
        square.vertices, square.triangles, SquareGrid(0, 0, 0.03), {}, options);
    EXPECT_DOUBLE_EQ(evaluation.precisions[0], 0.0);
    EXPECT_DOUBLE_EQ(evaluation.recalls[0], 0.0);
    EXPECT_DOUBLE_EQ(evaluation.fscores[0], 0.0);
    EXPECT_DOUBLE_EQ(evaluation.precisions[1], 1.0);
    EXPECT_DOUBLE_EQ(evaluation.recalls[1], 1.0);
    EXPECT_NEAR(evaluation.accuracy_m.median, 0.03, 0.001);
    if (recall_to_mesh) {
      EXPECT_NEAR(evaluation.completeness_m.max, 0.03, 1e-12);
      EXPECT_NEAR(evaluation.completeness_m.mean, 0.03, 1e-12);
    }
  }
}

// The unit cube shifted by 0.05 m along x against the unit cube's grid.
// Precision at t < 0.05: the face x = 0.05 is within t of the reference's
// side faces where min(y, 1-y, z, 1-z) < t, share 1 - (1-2t)^2; the face
// x = 1.05 is 0.05 away; the four side faces are on the reference for
// x <= 1 and x - 1 away beyond, share 0.95 + t. By symmetry recall is the
// same. At t = 0.1 everything is within.
TEST(MeshEvaluator, CubeShiftedAlongX) {
  const Mesh cube = Cube(Eigen::Vector3d(0.05, 0, 0));
  MeshEvaluationOptions options;
  options.thresholds_m = {0.02, 0.1};
  options.sample_density_per_m2 = 5000;
  const MeshEvaluation evaluation =
      EvaluateMesh(cube.vertices, cube.triangles, CubeGrid(), {}, options);
  const double t = 0.02;
  const double expected =
      ((1.0 - (1 - 2 * t) * (1 - 2 * t)) + 0.0 + 4 * (0.95 + t)) / 6.0;
  EXPECT_NEAR(evaluation.precisions[0], expected, 0.01);
  EXPECT_NEAR(evaluation.recalls[0], expected, 0.01);
  EXPECT_DOUBLE_EQ(evaluation.precisions[1], 1.0);
  EXPECT_DOUBLE_EQ(evaluation.recalls[1], 1.0);
}

// Reference: patches A ([0,1]^2) and B ([5,6]x[0,1]) at z = 0. Estimate: a
// mesh of A and of a far patch C ([20,21]x[0,1]).
TEST(MeshEvaluator, ObservedCloudAndCropBox) {
  Mesh estimate = UnitSquare(0, 0);
  const Mesh far_patch = UnitSquare(20, 0);
  for (const Eigen::Vector3i& triangle : far_patch.triangles) {
    estimate.triangles.push_back(triangle +
                                 Eigen::Vector3i::Constant(4));
  }
  estimate.vertices.insert(estimate.vertices.end(),
                           far_patch.vertices.begin(),
                           far_patch.vertices.end());
  std::vector<Eigen::Vector3d> reference = SquareGrid(0, 0, 0, 100);
  const std::vector<Eigen::Vector3d> patch_b = SquareGrid(5, 0, 0, 100);
  reference.insert(reference.end(), patch_b.begin(), patch_b.end());
  MeshEvaluationOptions options;
  options.thresholds_m = {0.02};

  // All reference kept: half of it (B) is missed. C is outside the crop
  // box [-0.5, 6.5] x [-0.5, 1.5] x [-0.5, 0.5], so precision stays 1.
  MeshEvaluation evaluation = EvaluateMesh(
      estimate.vertices, estimate.triangles, reference, {}, options);
  EXPECT_EQ(evaluation.num_reference_points_kept, 20000u);
  EXPECT_NEAR(evaluation.recalls[0], 0.5, 1e-12);
  // 2000 samples drawn area-weighted from two unit squares: about half in A.
  ASSERT_EQ(evaluation.estimate_points.size(), 2000u);
  const double share_in_a = evaluation.num_estimate_points_in_crop / 2000.0;
  EXPECT_NEAR(share_in_a, 0.5, 0.05);
  EXPECT_DOUBLE_EQ(evaluation.precisions[0], 1.0);
  EXPECT_NEAR(evaluation.crop_max.x(), 6.5 - 0.005, 1e-12);

  // Without the crop, C counts against precision.
  options.crop_margin_m = -1.0;
  evaluation = EvaluateMesh(estimate.vertices, estimate.triangles, reference,
                            {}, options);
  EXPECT_EQ(evaluation.num_estimate_points_in_crop, 2000u);
  EXPECT_NEAR(evaluation.precisions[0], share_in_a, 1e-12);

  // The sensors only saw A (a coarse cloud 10 cm above it): B is dropped.
  options.crop_margin_m = 0.5;
  std::vector<Eigen::Vector3d> observed = SquareGrid(0, 0, 0.1, 10);
  evaluation = EvaluateMesh(estimate.vertices, estimate.triangles, reference,
                            observed, options);
  EXPECT_EQ(evaluation.num_reference_points_kept, 10000u);
  EXPECT_DOUBLE_EQ(evaluation.recalls[0], 1.0);
  for (size_t i = 0; i < reference.size(); ++i) {
    EXPECT_EQ(evaluation.reference_kept[i], reference[i].x() < 2.0);
  }
  EXPECT_DOUBLE_EQ(evaluation.precisions[0], 1.0);
  EXPECT_NEAR(evaluation.crop_max.x(), 1.5 - 0.005, 1e-12);
}

TEST(MeshEvaluator, PointCloudEstimateAndColouredPly) {
  const std::vector<Eigen::Vector3d> reference = {{0, 0, 0}, {1, 0, 0}};
  // On a reference point, 0.05 away, 1 m away.
  const std::vector<Eigen::Vector3d> estimate = {
      {0, 0, 0}, {1, 0.05, 0}, {0, 0, 1}};
  MeshEvaluationOptions options;
  options.crop_margin_m = 2.0;
  EXPECT_DOUBLE_EQ(options.ColorThreshold(), 0.1);
  const MeshEvaluation evaluation =
      EvaluateMesh(estimate, {}, reference, {}, options);
  EXPECT_FALSE(evaluation.estimate_is_mesh);
  EXPECT_EQ(evaluation.estimate_points.size(), 3u);
  // Thresholds 0.02, 0.05, 0.1, 0.2, 0.5.
  EXPECT_NEAR(evaluation.precisions[0], 1 / 3.0, 1e-12);
  EXPECT_NEAR(evaluation.precisions[1], 1 / 3.0, 1e-12);  // 0.05 is not < 0.05
  EXPECT_NEAR(evaluation.precisions[2], 2 / 3.0, 1e-12);
  EXPECT_NEAR(evaluation.recalls[0], 0.5, 1e-12);
  EXPECT_NEAR(evaluation.recalls[2], 1.0, 1e-12);
  EXPECT_NEAR(evaluation.fscores[2], 2 * (2 / 3.0) / (2 / 3.0 + 1), 1e-12);

  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "colored.ply");
  WritePrecisionColoredPly(path, evaluation);
  const PlyData data = ReadPly(path);
  ASSERT_EQ(data.NumVertices(), 3u);
  const PlyColumn* red = data.FindColumn("red");
  const PlyColumn* green = data.FindColumn("green");
  const PlyColumn* blue = data.FindColumn("blue");
  const PlyColumn* distance = data.FindColumn("distance");
  ASSERT_TRUE(red && green && blue && distance);
  // Distance 0: blue.
  EXPECT_EQ(red->values[0], 0);
  EXPECT_EQ(green->values[0], 0);
  EXPECT_EQ(blue->values[0], 255);
  // Distance 0.05 of 0.1: halfway from green (1/3) to yellow (2/3).
  EXPECT_EQ(red->values[1], 128);
  EXPECT_EQ(green->values[1], 255);
  EXPECT_EQ(blue->values[1], 0);
  // Distance 1 > 0.1: red.
  EXPECT_EQ(red->values[2], 255);
  EXPECT_EQ(green->values[2], 0);
  EXPECT_EQ(blue->values[2], 0);
  EXPECT_NEAR(distance->values[2], 1.0, 1e-12);

  const std::string recall_path = JoinPaths(dir, "recall.ply");
  WriteRecallColoredPly(recall_path, evaluation);
  EXPECT_EQ(ReadPly(recall_path).NumVertices(), 2u);

  const std::string json_path = JoinPaths(dir, "mesh.json");
  WriteMeshEvaluationJson(json_path, evaluation);
  const Json json = ReadJsonFile(json_path);
  EXPECT_EQ(json.at("evaluator"), "mesh");
  EXPECT_EQ(json.at("thresholds_m"), Json({0.02, 0.05, 0.1, 0.2, 0.5}));
  EXPECT_EQ(json.at("recall"), Json({0.5, 0.5, 1.0, 1.0, 1.0}));
  EXPECT_EQ(json.at("precision"), Json(evaluation.precisions));
  EXPECT_EQ(json.at("fscore"), Json(evaluation.fscores));
  EXPECT_EQ(json.at("estimate_is_mesh"), evaluation.estimate_is_mesh);
  EXPECT_EQ(json.at("num_estimate_points"), evaluation.estimate_points.size());
  EXPECT_EQ(json.at("accuracy_m").at("count"), evaluation.accuracy_m.count);
  EXPECT_EQ(json.at("accuracy_m").at("max").get<double>(),
            evaluation.accuracy_m.max);
  EXPECT_EQ(json.at("completeness_m").at("median").get<double>(),
            evaluation.completeness_m.median);
  ASSERT_EQ(json.at("crop_min").size(), 3u);
  EXPECT_EQ(json.at("color_threshold_m").get<double>(),
            evaluation.color_threshold_m);
  const std::string table = FormatMeshEvaluation(evaluation);
  EXPECT_NE(table.find("precision"), std::string::npos) << table;
}

std::string ErrorOf(const std::function<void()>& body) {
  try {
    body();
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

// A sparse survey of a plane (0.5 m spacing, as a far, grazing ground) judges
// an estimate lying exactly on the plane as mostly wrong at 0.1 m; the true
// surface judges it right and still rejects an estimate 0.2 m off.
TEST(MeshEvaluator, SparseReferenceAndTrueSurface) {
  Mesh plane;
  plane.AddQuad({0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0});
  std::vector<Eigen::Vector3d> sparse;
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {
      sparse.emplace_back(0.25 + 0.5 * i, 0.25 + 0.5 * j, 0);
    }
  }
  MeshEvaluationOptions options;
  options.thresholds_m = {0.1};
  const MeshEvaluation to_points =
      EvaluateMesh(plane.vertices, plane.triangles, sparse, {}, options);
  EXPECT_FALSE(to_points.precision_to_surface);
  // Within 0.1 m of a grid point: pi 0.1^2 / 0.25 = 12.6 % of the area.
  EXPECT_NEAR(to_points.precisions[0], M_PI * 0.01 / 0.25, 0.02);
  ReferenceSurface surface;
  surface.vertices = plane.vertices;
  surface.triangles = plane.triangles;
  const MeshEvaluation to_surface = EvaluateMesh(
      plane.vertices, plane.triangles, sparse, {}, options, &surface);
  EXPECT_TRUE(to_surface.precision_to_surface);
  EXPECT_DOUBLE_EQ(to_surface.precisions[0], 1.0);
  EXPECT_LT(to_surface.accuracy_m.max, 1e-9);
  // Recall still counts the reference points.
  EXPECT_DOUBLE_EQ(to_surface.recalls[0], to_points.recalls[0]);
  Mesh lifted;
  lifted.AddQuad({0, 0, 0.2}, {4, 0, 0.2}, {4, 4, 0.2}, {0, 4, 0.2});
  const MeshEvaluation off = EvaluateMesh(lifted.vertices, lifted.triangles,
                                          sparse, {}, options, &surface);
  EXPECT_DOUBLE_EQ(off.precisions[0], 0.0);
  EXPECT_NEAR(off.accuracy_m.median, 0.2, 1e-9);

  // The same through files; a missing surface is named.
  const std::string dir = testing::CreateTestDir();
  const std::string mesh_path = JoinPaths(dir, "mesh.ply");
  const std::string reference_path = JoinPaths(dir, "reference.ply");
  const std::string surface_path = JoinPaths(dir, "scene.ply");
  testing::WriteXyzPly(mesh_path,
                       {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}},
                       {{0, 1, 2, 3}});
  testing::WriteXyzPly(surface_path,
                       {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}},
                       {{0, 1, 2, 3}});
  testing::WriteXyzPly(reference_path, sparse);
  options.reference_surface_path = surface_path;
  const MeshEvaluation from_files =
      EvaluateMeshFiles(mesh_path, reference_path, options);
  EXPECT_TRUE(from_files.precision_to_surface);
  EXPECT_DOUBLE_EQ(from_files.precisions[0], 1.0);
  options.reference_surface_path = JoinPaths(dir, "no_scene.ply");
  EXPECT_NE(ErrorOf([&] {
              EvaluateMeshFiles(mesh_path, reference_path, options);
            }).find("no_scene.ply"),
            std::string::npos);
  options.reference_surface_path = reference_path;  // Points, no faces.
  EXPECT_NE(ErrorOf([&] {
              EvaluateMeshFiles(mesh_path, reference_path, options);
            }).find("has no triangles"),
            std::string::npos);
}

TEST(MeshEvaluator, FilesAndErrors) {
  const std::string dir = testing::CreateTestDir();
  const std::string mesh_path = JoinPaths(dir, "mesh.ply");
  const std::string reference_path = JoinPaths(dir, "reference.ply");
  const std::string empty_path = JoinPaths(dir, "empty.ply");
  const std::string nan_path = JoinPaths(dir, "nan.ply");
  testing::WriteXyzPly(mesh_path,
                       {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                       {{0, 1, 2, 3}});
  testing::WriteXyzPly(reference_path, SquareGrid(0, 0, 0.03, 50));
  testing::WriteXyzPly(empty_path, {});
  testing::WriteXyzPly(nan_path, {{0, 0, 0}, {NAN, 0, 0}});

  MeshEvaluationOptions options;
  options.thresholds_m = {0.02, 0.05};
  const MeshEvaluation evaluation =
      EvaluateMeshFiles(mesh_path, reference_path, options);
  EXPECT_TRUE(evaluation.estimate_is_mesh);
  EXPECT_EQ(evaluation.num_estimate_triangles, 2u);  // Quad split in two.
  EXPECT_DOUBLE_EQ(evaluation.recalls[1], 1.0);
  EXPECT_DOUBLE_EQ(evaluation.recalls[0], 0.0);

  EXPECT_NE(ErrorOf([&] {
              EvaluateMeshFiles(JoinPaths(dir, "missing.ply"), reference_path,
                                options);
            }).find("missing.ply"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              EvaluateMeshFiles(mesh_path, empty_path, options);
            }).find("empty.ply has no vertices"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              EvaluateMeshFiles(empty_path, reference_path, options);
            }).find("empty.ply"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              EvaluateMeshFiles(mesh_path, nan_path, options);
            }).find("non-finite"),
            std::string::npos);
  options.observed_cloud_path = JoinPaths(dir, "no_observed.ply");
  EXPECT_NE(ErrorOf([&] {
              EvaluateMeshFiles(mesh_path, reference_path, options);
            }).find("no_observed.ply"),
            std::string::npos);
  options = MeshEvaluationOptions();
  options.thresholds_m = {0.05, 0.02};
  EXPECT_FALSE(options.Check());
  options.thresholds_m = {-0.01};
  EXPECT_FALSE(options.Check());
  options = MeshEvaluationOptions();
  options.sample_density_per_m2 = 0;
  EXPECT_FALSE(options.Check());
}

// The paper's recall: only the reference the cameras could see. A camera
// 3 m above the unit square looks down on it; a second square 1 m below
// the first lies in its shadow and no method could reconstruct it.
TEST(MeshEvaluator, VisibleModelDropsTheHiddenReference) {
  const std::string dir = testing::CreateTestDir();
  const std::string mesh_path = JoinPaths(dir, "mesh.ply");
  const std::string reference_path = JoinPaths(dir, "reference.ply");
  testing::WriteXyzPly(mesh_path, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                       {{0, 1, 2, 3}});
  std::vector<Eigen::Vector3d> reference = SquareGrid(0, 0, 0, 50);
  const std::vector<Eigen::Vector3d> hidden = SquareGrid(0, 0, -1, 50);
  reference.insert(reference.end(), hidden.begin(), hidden.end());
  testing::WriteXyzPly(reference_path, reference);

  Reconstruction model;
  Camera camera =
      Camera::FromModelName("PINHOLE", 640, 480, {320.0, 320.0, 320.0, 240.0});
  camera.camera_id = 1;
  model.cameras[1] = camera;
  Image image;
  image.image_id = 1;
  image.camera_id = 1;
  image.name = "000000.png";
  // Camera z along world -z, centre (0.5, 0.5, 3).
  image.cam_from_world.rotation = Eigen::Quaterniond(0, 1, 0, 0);
  image.cam_from_world.translation = Eigen::Vector3d(-0.5, 0.5, 3.0);
  model.images.push_back(image);
  const std::string model_path = JoinPaths(dir, "true_poses");
  WriteReconstruction(model_path, model, ModelFormat::kBinary);

  MeshEvaluationOptions options;
  options.thresholds_m = {0.02, 0.05};
  const MeshEvaluation all =
      EvaluateMeshFiles(mesh_path, reference_path, options);
  EXPECT_EQ(all.num_reference_points_kept, 5000u);
  EXPECT_NEAR(all.recalls[1], 0.5, 1e-12);

  options.visible_model_path = model_path;
  const MeshEvaluation visible =
      EvaluateMeshFiles(mesh_path, reference_path, options);
  EXPECT_EQ(visible.num_reference_points_kept, 2500u);
  EXPECT_DOUBLE_EQ(visible.recalls[1], 1.0);
  for (size_t i = 0; i < reference.size(); ++i) {
    EXPECT_EQ(visible.reference_kept[i], i < 2500) << i;
  }

  options.visible_model_path = JoinPaths(dir, "no_model");
  EXPECT_NE(ErrorOf([&] {
              EvaluateMeshFiles(mesh_path, reference_path, options);
            }).find("no_model"),
            std::string::npos);
}

}  // namespace
// An estimate in a frame rotated and shifted from the reference's (the
// gauge of a reconstruction) scores only once carried back; the observed
// cloud, in the estimate's frame too, goes along.
TEST(MeshEvaluator, AlignmentCarriesEstimateAndObservedCloud) {
  const std::string dir = testing::CreateTestDir();
  Eigen::Affine3d estimate_from_reference = Eigen::Affine3d::Identity();
  estimate_from_reference.linear() =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 0.1, 1.0).normalized())
          .toRotationMatrix();
  estimate_from_reference.translation() = Eigen::Vector3d(0.4, -0.2, 0.1);
  std::vector<Eigen::Vector3d> corners = {
      {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (Eigen::Vector3d& corner : corners) {
    corner = estimate_from_reference * corner;
  }
  const std::string mesh_path = JoinPaths(dir, "mesh.ply");
  const std::string reference_path = JoinPaths(dir, "reference.ply");
  const std::string observed_path = JoinPaths(dir, "observed.ply");
  testing::WriteXyzPly(mesh_path, corners, {{0, 1, 2, 3}});
  const std::vector<Eigen::Vector3d> reference = SquareGrid(0, 0, 0, 50);
  testing::WriteXyzPly(reference_path, reference);
  // The observed cloud covers the left half of the square, in the
  // estimate's frame.
  std::vector<Eigen::Vector3d> observed;
  for (const Eigen::Vector3d& point : reference) {
    if (point.x() < 0.5) observed.push_back(estimate_from_reference * point);
  }
  testing::WriteXyzPly(observed_path, observed);

  MeshEvaluationOptions options;
  options.thresholds_m = {0.02, 0.05};
  options.observed_cloud_path = observed_path;
  options.observed_radius_m = 0.015;
  const MeshEvaluation unaligned =
      EvaluateMeshFiles(mesh_path, reference_path, options);
  EXPECT_LT(unaligned.fscores[1], 0.5);
  const MeshEvaluation aligned = EvaluateMeshFiles(
      mesh_path, reference_path, options, estimate_from_reference.inverse());
  EXPECT_GT(aligned.precisions[0], 0.99);
  EXPECT_GT(aligned.recalls[0], 0.99);
  // Only the observed half of the reference counts for recall.
  EXPECT_NEAR(static_cast<double>(aligned.num_reference_points_kept) /
                  reference.size(),
              0.5, 0.03);

  // The same region given in the reference's frame (the scans fused with
  // the true poses, shared by reconstructions in other frames) stays where
  // it is; carried like the estimate, it would miss the square.
  std::vector<Eigen::Vector3d> observed_in_reference;
  for (const Eigen::Vector3d& point : reference) {
    if (point.x() < 0.5) observed_in_reference.push_back(point);
  }
  const std::string observed_reference_path =
      JoinPaths(dir, "observed_in_reference.ply");
  testing::WriteXyzPly(observed_reference_path, observed_in_reference);
  options.observed_cloud_path = observed_reference_path;
  options.observed_cloud_in_reference_frame = true;
  const MeshEvaluation shared = EvaluateMeshFiles(
      mesh_path, reference_path, options, estimate_from_reference.inverse());
  EXPECT_EQ(shared.num_reference_points_kept,
            aligned.num_reference_points_kept);
  EXPECT_NEAR(shared.recalls[0], aligned.recalls[0], 1e-12);
  options.observed_cloud_in_reference_frame = false;
  const MeshEvaluation carried = EvaluateMeshFiles(
      mesh_path, reference_path, options, estimate_from_reference.inverse());
  EXPECT_LT(
      static_cast<double>(carried.num_reference_points_kept) / reference.size(),
      0.4);
}

}  // namespace colmap_lidar
