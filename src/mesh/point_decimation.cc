#include "src/mesh/point_decimation.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

uint64_t VoxelKey(const Eigen::Vector3d& position, const Eigen::Vector3d& origin,
                  double voxel_size) {
  const Eigen::Vector3d cell = ((position - origin) / voxel_size).array().floor();
  // 21 bits per axis; the grid is sized so that this does not wrap in
  // practice, and a wrap only merges distant voxels' bookkeeping.
  const uint64_t mask = (1ull << 21) - 1;
  return ((static_cast<uint64_t>(cell.x()) & mask) << 42) |
         ((static_cast<uint64_t>(cell.y()) & mask) << 21) |
         (static_cast<uint64_t>(cell.z()) & mask);
}

}  // namespace

double DecimateMeshingInput(size_t max_num_points, MeshingInput* input) {
  THROW_CHECK(max_num_points > 0, "Decimation to 0 points");
  if (input->NumPoints() <= max_num_points) return 0;
  Eigen::Vector3d min = input->positions.front();
  Eigen::Vector3d max = min;
  for (const Eigen::Vector3d& position : input->positions) {
    min = min.cwiseMin(position);
    max = max.cwiseMax(position);
  }
  const Eigen::Vector3d extent = (max - min).cwiseMax(1e-6);
  // Points on surfaces: occupied voxels ~ area / size^2; start from a size
  // that would fit a filled bounding-box face and grow.
  double voxel_size = std::sqrt(extent.x() * extent.y() +
                                extent.y() * extent.z() +
                                extent.x() * extent.z()) /
                      std::sqrt(static_cast<double>(max_num_points)) * 0.5;
  voxel_size = std::max(voxel_size, extent.maxCoeff() / 2e6);
  std::unordered_map<uint64_t, uint32_t> voxel_to_point;
  while (true) {
    voxel_to_point.clear();
    bool fits = true;
    for (uint32_t i = 0; i < input->NumPoints(); ++i) {
      voxel_to_point.emplace(VoxelKey(input->positions[i], min, voxel_size), i);
      if (voxel_to_point.size() > max_num_points) {
        fits = false;
        break;
      }
    }
    if (fits) break;
    voxel_size *= 1.25;
  }
  // Representative per voxel, then sensor unions.
  for (uint32_t i = 0; i < input->NumPoints(); ++i) {
    uint32_t& best = voxel_to_point[VoxelKey(input->positions[i], min,
                                              voxel_size)];
    const bool is_line = input->sources[i] == MeshingPointSource::kLine;
    const bool best_is_line = input->sources[best] == MeshingPointSource::kLine;
    if ((is_line && !best_is_line) ||
        (is_line == best_is_line &&
         input->ray_weights[i] > input->ray_weights[best])) {
      best = i;
    }
  }
  std::vector<int64_t> new_index(input->NumPoints(), -1);
  MeshingInput output;
  output.sensors = input->sensors;
  output.creases = input->creases;
  output.crease_spacing_m = input->crease_spacing_m;
  for (const auto& [key, point_idx] : voxel_to_point) {
    new_index[point_idx] = static_cast<int64_t>(output.NumPoints());
    output.positions.push_back(input->positions[point_idx]);
    output.sources.push_back(input->sources[point_idx]);
    output.ray_weights.push_back(input->ray_weights[point_idx]);
    output.visibility.emplace_back();
  }
  for (uint32_t i = 0; i < input->NumPoints(); ++i) {
    const uint32_t best =
        voxel_to_point.at(VoxelKey(input->positions[i], min, voxel_size));
    auto& sensors = output.visibility[new_index[best]];
    sensors.insert(sensors.end(), input->visibility[i].begin(),
                   input->visibility[i].end());
  }
  for (auto& sensors : output.visibility) {
    std::sort(sensors.begin(), sensors.end());
    sensors.erase(std::unique(sensors.begin(), sensors.end()), sensors.end());
  }
  LOG(INFO) << "Memory guard: decimated " << input->NumPoints() << " to "
            << output.NumPoints() << " points with a " << voxel_size
            << " m voxel grid";
  *input = std::move(output);
  return voxel_size;
}

}  // namespace colmap_lidar
