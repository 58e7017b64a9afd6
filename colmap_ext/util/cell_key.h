// One 64-bit hash key for an integer 3D grid cell (voxels, neighbour grids):
// 21 bits per axis, two's complement masked, so cells within +-2^20 of the
// origin never collide (and a collision beyond only merges buckets).
#pragma once

#include <cstdint>

namespace colmap_lidar {

inline int64_t PackCellKey(int64_t x, int64_t y, int64_t z) {
  return ((x & 0x1FFFFF) << 42) | ((y & 0x1FFFFF) << 21) | (z & 0x1FFFFF);
}

}  // namespace colmap_lidar
