#include "src/eval/mesh_icp.h"

#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"
#include "src/eval/mesh_evaluator.h"
#include "src/eval/mesh_sampling.h"

namespace colmap_lidar {
namespace {

// A room corner: 6 x 6 m floor and two 3 m walls, each rectangle split into
// two triangles. Three orthogonal planes fix all six degrees of freedom.
void CornerMesh(std::vector<Eigen::Vector3d>* vertices,
                std::vector<Eigen::Vector3i>* triangles) {
  const auto add_rectangle = [&](const Eigen::Vector3d& origin,
                                 const Eigen::Vector3d& u,
                                 const Eigen::Vector3d& v) {
    const int base = static_cast<int>(vertices->size());
    vertices->push_back(origin);
    vertices->push_back(origin + u);
    vertices->push_back(origin + u + v);
    vertices->push_back(origin + v);
    triangles->emplace_back(base, base + 1, base + 2);
    triangles->emplace_back(base, base + 2, base + 3);
  };
  add_rectangle({0, 0, 0}, {6, 0, 0}, {0, 6, 0});
  add_rectangle({0, 0, 0}, {0, 6, 0}, {0, 0, 3});
  add_rectangle({0, 0, 0}, {6, 0, 0}, {0, 0, 3});
}

// The true mesh displaced by 1.5 deg and (8, -5, 6) cm.
Eigen::Affine3d Displacement() {
  Eigen::Affine3d displacement(Eigen::AngleAxisd(
      1.5 * M_PI / 180.0, Eigen::Vector3d(1, 2, -1).normalized()));
  displacement.translation() = Eigen::Vector3d(0.08, -0.05, 0.06);
  return displacement;
}

TEST(MeshIcp, RecoversADisplacementOfTheMesh) {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  CornerMesh(&vertices, &triangles);
  const std::vector<Eigen::Vector3d> reference =
      SampleTriangleMesh(vertices, triangles, 500.0, /*seed=*/3);
  for (Eigen::Vector3d& vertex : vertices) {
    vertex = Displacement() * vertex;
  }
  MeshEvaluationOptions evaluation_options;
  // Reference points 4.5 cm apart: F at 5 cm is ~1 for a perfect mesh.
  evaluation_options.thresholds_m = {0.05};
  evaluation_options.sample_density_per_m2 = 200.0;
  const MeshEvaluation before =
      EvaluateMesh(vertices, triangles, reference, {}, evaluation_options);

  for (const std::string method : {"point_to_plane", "point_to_point"}) {
    MeshIcpOptions options;
    options.method = method;
    options.max_num_samples = 5000;
    // Final distance 3 x 5 cm; stages 0.6, 0.3, 0.15 m.
    const MeshIcpResult result = RefineMeshAlignmentIcp(
        vertices, triangles, reference, /*evaluation_threshold_m=*/0.05,
        /*crop_margin_m=*/0.5, options);
    ASSERT_EQ(result.stage_distances_m.size(), 3u);
    EXPECT_NEAR(result.stage_distances_m.front(), 0.6, 1e-12);
    EXPECT_NEAR(result.stage_distances_m.back(), 0.15, 1e-12);
    EXPECT_GT(result.num_source_points, 4000u) << method;
    EXPECT_NEAR(result.rotation_deg, 1.5, 0.1) << method;
    // The correction undoes the displacement.
    const Eigen::Affine3d residual = result.refined_from_aligned *
                                     Displacement();
    EXPECT_LT(Eigen::AngleAxisd(residual.linear()).angle() * 180.0 / M_PI,
              0.05)
        << method;
    EXPECT_LT(residual.translation().norm(), 0.005) << method;
    EXPECT_GT(result.inlier_ratio, 0.99) << method;
    EXPECT_LT(result.inlier_rmse_m, result.inlier_rmse_before_m) << method;

    // And the figures at 5 cm recover.
    std::vector<Eigen::Vector3d> refined = vertices;
    for (Eigen::Vector3d& vertex : refined) {
      vertex = result.refined_from_aligned * vertex;
    }
    const MeshEvaluation after =
        EvaluateMesh(refined, triangles, reference, {}, evaluation_options);
    EXPECT_LT(before.fscores[0], 0.7) << method;
    EXPECT_GT(after.fscores[0], 0.97) << method;
  }
}

TEST(MeshIcp, FilesOptionsAndErrors) {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  CornerMesh(&vertices, &triangles);
  const std::vector<Eigen::Vector3d> reference =
      SampleTriangleMesh(vertices, triangles, 300.0, /*seed=*/3);
  const std::string dir = testing::CreateTestDir();
  const std::string mesh_path = JoinPaths(dir, "mesh.ply");
  const std::string reference_path = JoinPaths(dir, "reference.ply");
  std::ofstream(mesh_path)
      << ("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                "property float y\nproperty float z\nend_header\n");
  std::vector<PlyPoint> points;
  for (const Eigen::Vector3d& point : reference) {
    PlyPoint p;
    p.xyz = point.cast<float>();
    points.push_back(p);
  }
  WriteColmapPlyPoints(reference_path, points);

  MeshIcpOptions options;
  EXPECT_THROW(RefineMeshAlignmentIcpFiles(mesh_path, reference_path,
                                           Eigen::Affine3d::Identity(), 0.05,
                                           0.5, options),
               Error);
  EXPECT_THROW(RefineMeshAlignmentIcpFiles(JoinPaths(dir, "missing.ply"),
                                           reference_path,
                                           Eigen::Affine3d::Identity(), 0.05,
                                           0.5, options),
               Error);
  // The reference as a point-cloud estimate, displaced, read from files.
  const MeshIcpResult result = RefineMeshAlignmentIcpFiles(
      reference_path, reference_path, Displacement(), 0.05, 0.5, options);
  const Eigen::Affine3d residual = result.refined_from_aligned * Displacement();
  EXPECT_LT(residual.translation().norm(), 0.01);
  // An estimate far outside the reference's box.
  std::vector<Eigen::Vector3d> far = vertices;
  for (Eigen::Vector3d& vertex : far) {
    vertex.x() += 100.0;
  }
  EXPECT_THROW(
      RefineMeshAlignmentIcp(far, triangles, reference, 0.05, 0.5, options),
      Error);
  options.method = "magic";
  EXPECT_FALSE(options.Check());
  options = MeshIcpOptions();
  options.num_stages = 0;
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(RefineMeshAlignmentIcp(vertices, triangles, reference, 0.05,
                                      0.5, options),
               Error);
}

}  // namespace
}  // namespace colmap_lidar
