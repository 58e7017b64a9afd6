#include "src/sfm/lidar_edge_check.h"

#include <cmath>
#include <string>
#include <unordered_map>
#include <vector>

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

// Two cameras 1 m apart (LIDAR = camera frame) and the edge their poses
// imply: the graph's poses, with a zero edge error.
struct TwoFrames {
  Reconstruction model;
  std::unordered_map<image_t, Rigid3d> input_poses;
  std::vector<RelativePoseEdge> edges;

  TwoFrames() {
    for (const image_t image_id : {1, 2}) {
      Image image;
      image.image_id = image_id;
      image.name = "frame" + std::to_string(image_id);
      image.cam_from_world =
          Rigid3d(Eigen::Quaterniond::Identity(),
                  Eigen::Vector3d(-static_cast<double>(image_id), 0.0, 0.0));
      input_poses[image_id] = image.cam_from_world;
      model.images.push_back(image);
    }
    RelativePoseEdge edge;
    edge.image_id1 = 1;
    edge.image_id2 = 2;
    edge.lidar1_from_lidar2 =
        input_poses.at(1) * input_poses.at(2).Inverse();
    edges.push_back(edge);
  }

  void MoveImage2(double dx_m) {
    model.FindImage(2)->cam_from_world.translation.x() -= dx_m;
  }
};

TEST(CheckLidarEdges, KeepsFinalPosesThatRespectTheEdges) {
  TwoFrames frames;
  frames.MoveImage2(0.01);
  LidarMapperSummary summary;
  CheckLidarEdges(frames.edges, frames.input_poses, &frames.model, &summary);
  EXPECT_NEAR(summary.lidar_edge_error_input, 0.0, 1e-9);
  EXPECT_GT(summary.lidar_edge_error_final, 0.0);
  EXPECT_EQ(summary.num_lidar_edge_violated_frames, 0);
  EXPECT_FALSE(summary.kept_lidar_graph_poses);
  EXPECT_NEAR(frames.model.FindImage(2)->cam_from_world.translation.x(),
              -2.01, 1e-12);
}

TEST(CheckLidarEdges, RestoresTheGraphPosesWhenTheEdgesAreViolated) {
  TwoFrames frames;
  frames.MoveImage2(10.0);
  LidarMapperSummary summary;
  CheckLidarEdges(frames.edges, frames.input_poses, &frames.model, &summary);
  EXPECT_GT(summary.lidar_edge_error_final, std::sqrt(22.458));
  EXPECT_EQ(summary.num_lidar_edge_violated_frames, 2);
  EXPECT_TRUE(summary.kept_lidar_graph_poses);
  EXPECT_NEAR(frames.model.FindImage(2)->cam_from_world.translation.x(), -2.0,
              1e-12);
}

TEST(CheckLidarEdges, NoEdgeWithBothImagesLeavesTheSummary) {
  TwoFrames frames;
  frames.edges[0].image_id2 = 3;
  LidarMapperSummary summary;
  CheckLidarEdges(frames.edges, frames.input_poses, &frames.model, &summary);
  EXPECT_LT(summary.lidar_edge_error_input, 0.0);
  EXPECT_FALSE(summary.kept_lidar_graph_poses);
}

}  // namespace
}  // namespace colmap_lidar
