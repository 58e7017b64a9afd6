// The check of lidar_mapper's final poses against the LIDAR pose graph's
// edges (init_method "lidar_graph", see LidarMapperSummary in
// src/sfm/lidar_mapper.h).
#pragma once

#include <unordered_map>
#include <vector>

#include "colmap_ext/scene/reconstruction.h"
#include "src/optim/line_bundle_adjustment.h"
#include "src/sfm/lidar_mapper.h"

namespace colmap_lidar {

// A correct edge's squared whitened error is below the chi-square(6)
// 99.9 % quantile; frames with an edge beyond it are logged. When the
// final poses of `model` violate the edges much more than `input_poses`
// (the graph's) did, the input poses are restored (the caller rebuilds the
// points and lines at them: RebuildStructureAtPoses). Fills the summary's
// lidar_edge_*, num_lidar_edge_violated_frames and kept_lidar_graph_poses.
void CheckLidarEdges(const std::vector<RelativePoseEdge>& edges,
                     const std::unordered_map<image_t, Rigid3d>& input_poses,
                     Reconstruction* model, LidarMapperSummary* summary);

}  // namespace colmap_lidar
