#include "src/mvs/own_scan.h"

#include <algorithm>
#include <cmath>

#include "src/mvs/interpolation.h"

namespace colmap_lidar {

std::vector<uint8_t> OwnScanVoxels(const FusedVisibility& visibility,
                                   uint32_t image_idx) {
  std::vector<uint8_t> own(visibility.size(), 0);
  for (size_t v = 0; v < visibility.size(); ++v) {
    const std::vector<uint32_t>& frames = visibility[v];
    own[v] = std::find(frames.begin(), frames.end(), image_idx) != frames.end();
  }
  return own;
}

std::vector<DepthSample> OwnScanSamples(
    const MvsView& view, const FusedLidarCloud& cloud, uint32_t image_idx,
    const std::vector<Eigen::Vector3f>& features_in_world,
    const LidarPatchMatchOptions& options) {
  const std::vector<uint8_t> own = OwnScanVoxels(cloud.visibility, image_idx);
  const bool with_normals = cloud.normals.size() == cloud.points.size();
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;
  for (size_t v = 0; v < own.size() && v < cloud.points.size(); ++v) {
    if (!own[v]) continue;
    points.push_back(cloud.points[v]);
    if (with_normals) normals.push_back(cloud.normals[v]);
  }
  return MergeFeatureSamples(
      view, features_in_world,
      ProjectLidarSamples(view, points, normals, options), options);
}

size_t PreferOwnScan(const MvsView& view,
                     const std::vector<DepthSample>& own_samples,
                     const LidarPatchMatchOptions& options, PlaneMap* map,
                     std::vector<uint8_t>* across_depth_edge) {
  if (own_samples.empty() || options.lidar_own_scan_min_incidence_deg >= 90) {
    return 0;
  }
  std::vector<uint8_t> own_across;
  const PlaneMap own_map =
      InterpolateSamples(view, own_samples, options, &own_across);
  const float max_cos_incidence = static_cast<float>(
      std::cos(options.lidar_own_scan_min_incidence_deg * M_PI / 180.0));
  size_t num_replaced = 0;
  for (int row = 0; row < map->height; ++row) {
    for (int col = 0; col < map->width; ++col) {
      const size_t i = map->Index(row, col);
      if (!(map->depth[i] > 0) || !(own_map.depth[i] > 0) || own_across[i]) {
        continue;
      }
      // The own interpolation's normal faces the camera (unit).
      const Eigen::Vector3f ray =
          view.Ray(static_cast<float>(row), static_cast<float>(col))
              .normalized();
      if (std::abs(own_map.normal[i].dot(ray)) > max_cos_incidence) continue;
      map->depth[i] = own_map.depth[i];
      map->normal[i] = own_map.normal[i];
      (*across_depth_edge)[i] = 0;
      ++num_replaced;
    }
  }
  return num_replaced;
}

}  // namespace colmap_lidar
