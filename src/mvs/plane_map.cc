#include "src/mvs/plane_map.h"

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

DepthMap ToDepthMap(const PlaneMap& map) {
  DepthMap depth_map(map.width, map.height);
  for (int row = 0; row < map.height; ++row) {
    for (int col = 0; col < map.width; ++col) {
      const float depth = map.depth[map.Index(row, col)];
      depth_map.Set(row, col, depth > 0 ? depth : 0.0f);
    }
  }
  return depth_map;
}

NormalMap ToNormalMap(const PlaneMap& map) {
  NormalMap normal_map(map.width, map.height);
  for (int row = 0; row < map.height; ++row) {
    for (int col = 0; col < map.width; ++col) {
      const size_t i = map.Index(row, col);
      if (map.depth[i] > 0) {
        normal_map.Set(row, col, map.normal[i]);
      }
    }
  }
  return normal_map;
}

PlaneMap FromDenseMaps(const DepthMap& depth_map, const NormalMap& normal_map) {
  THROW_CHECK(depth_map.GetWidth() == normal_map.GetWidth() &&
                  depth_map.GetHeight() == normal_map.GetHeight(),
              "depth map " << depth_map.GetWidth() << "x"
                           << depth_map.GetHeight() << " and normal map "
                           << normal_map.GetWidth() << "x"
                           << normal_map.GetHeight() << " differ in size");
  PlaneMap map(static_cast<int>(depth_map.GetWidth()),
               static_cast<int>(depth_map.GetHeight()));
  for (int row = 0; row < map.height; ++row) {
    for (int col = 0; col < map.width; ++col) {
      const size_t i = map.Index(row, col);
      const float depth = depth_map.Get(row, col);
      map.depth[i] = depth > 0 ? depth : 0.0f;
      map.normal[i] = normal_map.Get(row, col);
    }
  }
  return map;
}

}  // namespace colmap_lidar
