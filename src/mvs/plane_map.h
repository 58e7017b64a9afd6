// The per-pixel state of PatchMatch: a plane hypothesis (z-depth and unit
// normal in the reference camera frame, facing the camera) and its cost.
// Depth 0 means "no hypothesis" (invalid, as in COLMAP's maps).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "colmap_ext/mvs/dense_maps.h"

namespace colmap_lidar {

struct PlaneMap {
  int width = 0;
  int height = 0;
  std::vector<float> depth;
  std::vector<Eigen::Vector3f> normal;
  std::vector<float> cost;

  PlaneMap() = default;
  PlaneMap(int width, int height)
      : width(width),
        height(height),
        depth(static_cast<size_t>(width) * height, 0.0f),
        normal(static_cast<size_t>(width) * height, Eigen::Vector3f::Zero()),
        cost(static_cast<size_t>(width) * height, 0.0f) {}
  size_t Index(int row, int col) const {
    return static_cast<size_t>(row) * width + col;
  }
  size_t NumValid() const {
    size_t n = 0;
    for (float d : depth) n += d > 0;
    return n;
  }
};

// COLMAP maps from the plane map; invalid pixels (depth <= 0) get depth 0
// and normal (0, 0, 0).
DepthMap ToDepthMap(const PlaneMap& map);
NormalMap ToNormalMap(const PlaneMap& map);
// Back from COLMAP maps (cost 0). Throws when the sizes differ.
PlaneMap FromDenseMaps(const DepthMap& depth_map, const NormalMap& normal_map);

}  // namespace colmap_lidar
