#include "src/mesh/view_region.h"

#include <algorithm>
#include <vector>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

bool ViewRegionOptions::Check() const {
  if (!(depth_quantile > 0 && depth_quantile <= 1)) {
    LOG(ERROR) << "DelaunayMeshing.view_depth_quantile must be in (0, 1]";
    return false;
  }
  if (!(depth_factor >= 0)) {
    LOG(ERROR) << "DelaunayMeshing.view_depth_factor must be >= 0";
    return false;
  }
  return true;
}

double ViewRegionMaxDepth(const ViewRegionOptions& options,
                          const MeshingInput& input) {
  THROW_CHECK(options.Check(), "Invalid view region options");
  if (options.depth_factor == 0) return 0;
  std::vector<double> depths;
  for (size_t i = 0; i < input.NumPoints(); ++i) {
    if (input.sources[i] != MeshingPointSource::kVisual) continue;
    const Eigen::Vector4d point = input.positions[i].homogeneous();
    for (const uint32_t sensor_idx : input.visibility[i]) {
      const MeshingSensor& sensor = input.sensors[sensor_idx];
      if (!sensor.is_camera) continue;
      // The third row of K [R | t] is the camera-frame depth.
      const double depth = sensor.proj_matrix.row(2).dot(point);
      if (depth > 0) depths.push_back(depth);
    }
  }
  if (depths.empty()) return 0;
  const size_t rank = std::min(
      depths.size() - 1,
      static_cast<size_t>(options.depth_quantile * (depths.size() - 1) + 0.5));
  std::nth_element(depths.begin(), depths.begin() + rank, depths.end());
  return options.depth_factor * depths[rank];
}

bool IsInViewRegion(const MeshingInput& input, double max_depth,
                    const Eigen::Vector3d& point) {
  const Eigen::Vector4d homogeneous = point.homogeneous();
  for (const MeshingSensor& sensor : input.sensors) {
    if (!sensor.is_camera || sensor.image_width <= 0 ||
        sensor.image_height <= 0) {
      continue;
    }
    const Eigen::Vector3d projection = sensor.proj_matrix * homogeneous;
    const double depth = projection.z();
    if (!(depth > 0 && depth <= max_depth)) continue;
    const double u = projection.x() / depth;
    const double v = projection.y() / depth;
    if (u >= 0 && u < sensor.image_width && v >= 0 &&
        v < sensor.image_height) {
      return true;
    }
  }
  return false;
}

size_t CropToViewRegion(double max_depth, MeshingInput* input) {
  if (!(max_depth > 0)) return 0;
  const bool has_image_size =
      std::any_of(input->sensors.begin(), input->sensors.end(),
                  [](const MeshingSensor& sensor) {
                    return sensor.is_camera && sensor.image_width > 0 &&
                           sensor.image_height > 0;
                  });
  if (!has_image_size) return 0;
  size_t num_kept = 0;
  for (size_t i = 0; i < input->NumPoints(); ++i) {
    if (!IsInViewRegion(*input, max_depth, input->positions[i])) continue;
    if (num_kept != i) {
      input->positions[num_kept] = input->positions[i];
      input->sources[num_kept] = input->sources[i];
      input->ray_weights[num_kept] = input->ray_weights[i];
      input->visibility[num_kept] = std::move(input->visibility[i]);
    }
    ++num_kept;
  }
  const size_t num_removed = input->NumPoints() - num_kept;
  input->positions.resize(num_kept);
  input->sources.resize(num_kept);
  input->ray_weights.resize(num_kept);
  input->visibility.resize(num_kept);
  return num_removed;
}

}  // namespace colmap_lidar
