#include "src/sfm/lidar_edge_check.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

void CheckLidarEdges(const std::vector<RelativePoseEdge>& edges,
                     const std::unordered_map<image_t, Rigid3d>& input_poses,
                     Reconstruction* model, LidarMapperSummary* summary) {
  constexpr double kChi2Dof6Quantile999 = 22.458;
  Reconstruction input = *model;
  for (Image& image : input.images) {
    const auto it = input_poses.find(image.image_id);
    if (it != input_poses.end()) {
      image.cam_from_world = it->second;
    }
  }
  double sum_input = 0.0;
  double sum_final = 0.0;
  int count = 0;
  std::unordered_map<image_t, double> worst_of_frame;
  for (const RelativePoseEdge& edge : edges) {
    const double error_input = ComputeRelativePoseEdgeError(input, edge);
    const double error_final = ComputeRelativePoseEdgeError(*model, edge);
    if (error_input < 0.0 || error_final < 0.0) {
      continue;
    }
    sum_input += error_input;
    sum_final += error_final;
    ++count;
    for (const image_t image_id : {edge.image_id1, edge.image_id2}) {
      double& worst = worst_of_frame[image_id];
      worst = std::max(worst, error_final);
    }
  }
  if (count == 0) {
    return;
  }
  summary->lidar_edge_error_input = sum_input / count;
  summary->lidar_edge_error_final = sum_final / count;
  std::vector<std::pair<double, image_t>> violated;
  for (const auto& [image_id, worst] : worst_of_frame) {
    if (worst * worst > kChi2Dof6Quantile999) {
      violated.emplace_back(worst, image_id);
    }
  }
  std::sort(violated.rbegin(), violated.rend());
  summary->num_lidar_edge_violated_frames = static_cast<int>(violated.size());
  if (!violated.empty()) {
    std::ostringstream worst;
    for (size_t k = 0; k < std::min<size_t>(5, violated.size()); ++k) {
      worst << " " << model->FindImage(violated[k].second)->name << " ("
            << violated[k].first << ")";
    }
    LOG(WARNING) << "lidar_mapper: " << violated.size()
                 << " frames violate a LIDAR edge beyond the chi-square(6) "
                    "99.9 % quantile after the iterations; worst (whitened "
                    "error):"
                 << worst.str();
  }
  // Expected whitened norm of a correct edge: sqrt(6).
  if (summary->lidar_edge_error_final > 2.0 * summary->lidar_edge_error_input &&
      summary->lidar_edge_error_final - summary->lidar_edge_error_input >
          std::sqrt(6.0)) {
    for (Image& image : model->images) {
      const auto it = input_poses.find(image.image_id);
      if (it != input_poses.end()) {
        image.cam_from_world = it->second;
      }
    }
    summary->kept_lidar_graph_poses = true;
    LOG(WARNING) << "lidar_mapper: the iterations raised the mean whitened "
                    "LIDAR edge error from "
                 << summary->lidar_edge_error_input << " to "
                 << summary->lidar_edge_error_final
                 << ": the LIDAR graph poses are kept (points and lines "
                    "are rebuilt at them)";
  } else {
    LOG(INFO) << "lidar_mapper: mean whitened LIDAR edge error "
              << summary->lidar_edge_error_input << " (graph) -> "
              << summary->lidar_edge_error_final << " (final) over " << count
              << " edges";
  }
}

}  // namespace colmap_lidar
