#include "src/eval/edge_region.h"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"
#include "src/eval/mesh_evaluator.h"

namespace colmap_lidar {
namespace {

// A wall (x = 0, z in [0, 2]) standing on the ground (z = 0, x in [0, 4]),
// both 4 m along y; the crease is the y axis.
const Segment3D kCrease{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 4, 0)};

std::vector<Eigen::Vector3d> SurveyPoints() {
  std::vector<Eigen::Vector3d> points;
  for (double y = 0.0; y <= 4.0 + 1e-9; y += 0.02) {
    for (double x = 0.0; x <= 4.0 + 1e-9; x += 0.02) {
      points.emplace_back(x, y, 0.0);
    }
    for (double z = 0.02; z <= 2.0 + 1e-9; z += 0.02) {
      points.emplace_back(0.0, y, z);
    }
  }
  return points;
}

// Quads (as two triangles) of a strip from a(y) to b(y) along y in [0, 4].
void AddStrip(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
              std::vector<Eigen::Vector3d>* vertices,
              std::vector<std::vector<uint32_t>>* faces) {
  const uint32_t first = static_cast<uint32_t>(vertices->size());
  vertices->push_back(a);
  vertices->push_back(b);
  vertices->push_back(b + Eigen::Vector3d(0, 4, 0));
  vertices->push_back(a + Eigen::Vector3d(0, 4, 0));
  faces->push_back({first, first + 1, first + 2});
  faces->push_back({first, first + 2, first + 3});
}

// The true wall and ground; with `bevel_m` > 0 the corner is cut by a
// 45-degree bevel from (bevel, y, 0) to (0, y, bevel), as a mesh that
// rounds a crease.
void WriteCornerMesh(const std::string& path, double bevel_m) {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::vector<uint32_t>> faces;
  AddStrip(Eigen::Vector3d(bevel_m, 0, 0), Eigen::Vector3d(4, 0, 0),
           &vertices, &faces);
  AddStrip(Eigen::Vector3d(0, 0, bevel_m), Eigen::Vector3d(0, 0, 2),
           &vertices, &faces);
  if (bevel_m > 0.0) {
    AddStrip(Eigen::Vector3d(bevel_m, 0, 0), Eigen::Vector3d(0, 0, bevel_m),
             &vertices, &faces);
  }
  testing::WriteXyzPly(path, vertices, faces);
}

TEST(EdgeRegion, DistancesToSegmentsAreExact) {
  const std::vector<Eigen::Vector3d> points = {
      Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(0, 5, 0),
      Eigen::Vector3d(0, 2, 0), Eigen::Vector3d(3, 2, 0)};
  const Segment3D other{Eigen::Vector3d(3, 0, 0), Eigen::Vector3d(3, 1, 0)};
  const std::vector<double> distances =
      DistancesToSegments(points, {kCrease, other});
  ASSERT_EQ(distances.size(), 4u);
  EXPECT_NEAR(distances[0], std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(distances[1], 1.0, 1e-6);  // Past the end: to the endpoint.
  EXPECT_NEAR(distances[2], 0.0, 1e-6);
  EXPECT_NEAR(distances[3], 1.0, 1e-6);  // To (3,1,0), the end of `other`.
  EXPECT_THROW(DistancesToSegments(points, {}), Error);
}

class EdgeRegionFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::CreateTestDir();
    reference_path_ = JoinPaths(dir_, "survey.ply");
    testing::WriteXyzPly(reference_path_, SurveyPoints());
    edges_path_ = JoinPaths(dir_, "crease_edges.txt");
    WriteSegmentsText(edges_path_, {kCrease});
    options_.thresholds_m = {0.02, 0.05, 0.11};
    options_.sample_density_per_m2 = 4000.0;
    options_.edge_region_path = edges_path_;
    options_.edge_region_radius_m = 0.2;
  }

  std::string dir_;
  std::string reference_path_;
  std::string edges_path_;
  MeshEvaluationOptions options_;
};

TEST_F(EdgeRegionFiles, SharpCornerIsPerfectAndABevelShowsOnlyNearTheCrease) {
  const std::string sharp_path = JoinPaths(dir_, "sharp.ply");
  WriteCornerMesh(sharp_path, 0.0);
  const MeshEvaluation sharp =
      EvaluateMeshFiles(sharp_path, reference_path_, options_);
  ASSERT_TRUE(sharp.has_edge_region);
  const EdgeRegionEvaluation& sharp_region = sharp.edge_region;
  EXPECT_EQ(sharp_region.num_edges, 1u);
  // The region is 0.2 m of ground and 0.2 m of wall along 4 m: 1.6 m2 of
  // the 24 m2 surface.
  const double region_share =
      static_cast<double>(sharp_region.num_estimate_points) /
      sharp.num_estimate_points_in_crop;
  EXPECT_NEAR(region_share, 1.6 / 24.0, 0.01);
  EXPECT_GT(sharp_region.num_reference_points, 1000u);
  for (size_t k = 0; k < sharp_region.thresholds_m.size(); ++k) {
    EXPECT_NEAR(sharp_region.precisions[k], 1.0, 1e-9);
    EXPECT_NEAR(sharp_region.recalls[k], 1.0, 1e-9);
  }

  // A 0.15 m bevel: its middle is 0.075 m from the true wall and ground,
  // and the corner's survey points are up to 0.106 m from the bevel.
  const std::string bevel_path = JoinPaths(dir_, "bevel.ply");
  WriteCornerMesh(bevel_path, 0.15);
  const MeshEvaluation bevel =
      EvaluateMeshFiles(bevel_path, reference_path_, options_);
  ASSERT_TRUE(bevel.has_edge_region);
  const EdgeRegionEvaluation& bevel_region = bevel.edge_region;
  // At 2 cm the bevel is mostly wrong near the crease and a small share of
  // the whole scene.
  EXPECT_LT(bevel_region.precisions[0], 0.75);
  EXPECT_GT(bevel.precisions[0], 0.95);
  EXPECT_LT(bevel_region.recalls[0], 0.85);
  EXPECT_GT(bevel.recalls[0], 0.94);
  EXPECT_LT(bevel_region.fscores[0], sharp_region.fscores[0] - 0.2);
  // Everything is within 0.11 m, both ways.
  EXPECT_NEAR(bevel_region.precisions[2], 1.0, 1e-9);
  EXPECT_NEAR(bevel_region.recalls[2], 1.0, 1e-9);

  // The JSON report carries the region; the text report names it.
  const std::string json_path = JoinPaths(dir_, "bevel.json");
  WriteMeshEvaluationJson(json_path, bevel);
  const Json json = ReadJsonFile(json_path);
  ASSERT_TRUE(json.contains("edge_region"));
  EXPECT_EQ(json.at("edge_region").at("num_edges").get<size_t>(), 1u);
  EXPECT_EQ(json.at("edge_region").at("fscore").size(), 3u);
  EXPECT_NE(FormatMeshEvaluation(bevel).find("edge region"),
            std::string::npos);
}

TEST_F(EdgeRegionFiles, NoEdgeFileNoRegion) {
  const std::string sharp_path = JoinPaths(dir_, "sharp.ply");
  WriteCornerMesh(sharp_path, 0.0);
  options_.edge_region_path = "";
  const MeshEvaluation evaluation =
      EvaluateMeshFiles(sharp_path, reference_path_, options_);
  EXPECT_FALSE(evaluation.has_edge_region);
  const std::string json_path = JoinPaths(dir_, "sharp.json");
  WriteMeshEvaluationJson(json_path, evaluation);
  EXPECT_FALSE(ReadJsonFile(json_path).contains("edge_region"));
}

TEST_F(EdgeRegionFiles, RefusesBadInput) {
  const std::string sharp_path = JoinPaths(dir_, "sharp.ply");
  WriteCornerMesh(sharp_path, 0.0);
  options_.edge_region_radius_m = 0.0;
  EXPECT_FALSE(options_.Check());
  EXPECT_THROW(EvaluateMeshFiles(sharp_path, reference_path_, options_),
               Error);
  options_.edge_region_radius_m = 0.2;

  options_.edge_region_path = JoinPaths(dir_, "missing_edges.txt");
  try {
    EvaluateMeshFiles(sharp_path, reference_path_, options_);
    ADD_FAILURE() << "a missing edge file was accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("missing_edges.txt"),
              std::string::npos)
        << error.what();
  }

  const std::string empty_path = JoinPaths(dir_, "no_edges.txt");
  WriteSegmentsText(empty_path, {});
  options_.edge_region_path = empty_path;
  EXPECT_THROW(EvaluateMeshFiles(sharp_path, reference_path_, options_),
               Error);
}

}  // namespace
}  // namespace colmap_lidar
