// A uniform grid over a point set for radius searches: with cells of the
// search radius, the neighbours of a point lie in the 27 cells around its
// own. Used by the LIDAR denoising and the line validation of the mesher.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {

class RadiusGrid {
 public:
  // Keeps indices into `positions`, not the points. cell_size > 0, metres.
  RadiusGrid(const std::vector<Eigen::Vector3d>& positions, double cell_size)
      : cell_size_(cell_size) {
    order_.resize(positions.size());
    std::iota(order_.begin(), order_.end(), 0);
    std::vector<uint64_t> keys(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
      keys[i] = Key(Cell(positions[i]));
    }
    std::sort(order_.begin(), order_.end(), [&](uint32_t a, uint32_t b) {
      return keys[a] < keys[b];
    });
    for (size_t begin = 0; begin < order_.size();) {
      size_t end = begin + 1;
      while (end < order_.size() && keys[order_[end]] == keys[order_[begin]]) {
        ++end;
      }
      ranges_.emplace(keys[order_[begin]], std::make_pair(begin, end));
      cells_.emplace_back(Cell(positions[order_[begin]]),
                          std::make_pair(begin, end));
      begin = end;
    }
  }

  double cell_size() const { return cell_size_; }

  // Calls visit(index) for every point in the 27 cells around `position`
  // (a superset of the points within cell_size of it).
  template <typename Visit>
  void ForEachNear(const Eigen::Vector3d& position, Visit&& visit) const {
    const Eigen::Vector3i center = Cell(position);
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it =
              ranges_.find(Key(center + Eigen::Vector3i(dx, dy, dz)));
          if (it == ranges_.end()) continue;
          for (size_t k = it->second.first; k < it->second.second; ++k) {
            visit(order_[k]);
          }
        }
      }
    }
  }

  // Calls visit(index) for every point in the cells that meet the
  // axis-aligned box [box_min, box_max] (a superset of the points in it).
  template <typename Visit>
  void ForEachInBox(const Eigen::Vector3d& box_min,
                    const Eigen::Vector3d& box_max, Visit&& visit) const {
    const Eigen::Vector3i lo = Cell(box_min);
    const Eigen::Vector3i hi = Cell(box_max);
    // A box of more cells than there are points: visit the points instead
    // (bounds the work for a small cell size).
    const Eigen::Array3d num_cells =
        (hi - lo).cast<double>().array() + 1.0;
    if (num_cells.prod() > static_cast<double>(order_.size())) {
      for (const auto& [cell, range] : cells_) {
        if ((cell.array() < lo.array()).any() ||
            (cell.array() > hi.array()).any()) {
          continue;
        }
        for (size_t k = range.first; k < range.second; ++k) visit(order_[k]);
      }
      return;
    }
    for (int x = lo.x(); x <= hi.x(); ++x) {
      for (int y = lo.y(); y <= hi.y(); ++y) {
        for (int z = lo.z(); z <= hi.z(); ++z) {
          const auto it = ranges_.find(Key(Eigen::Vector3i(x, y, z)));
          if (it == ranges_.end()) continue;
          for (size_t k = it->second.first; k < it->second.second; ++k) {
            visit(order_[k]);
          }
        }
      }
    }
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3d& position) const {
    return (position / cell_size_).array().floor().cast<int>();
  }
  static uint64_t Key(const Eigen::Vector3i& cell) {
    // 21 bits per axis (two's complement wrap): distinct for any scene
    // smaller than 2^21 cells per axis.
    const uint64_t mask = (1ull << 21) - 1;
    return ((static_cast<uint64_t>(cell.x()) & mask) << 42) |
           ((static_cast<uint64_t>(cell.y()) & mask) << 21) |
           (static_cast<uint64_t>(cell.z()) & mask);
  }

  double cell_size_;
  std::vector<uint32_t> order_;
  std::unordered_map<uint64_t, std::pair<size_t, size_t>> ranges_;
  // The occupied cells and their ranges of order_, in key order.
  std::vector<std::pair<Eigen::Vector3i, std::pair<size_t, size_t>>> cells_;
};

}  // namespace colmap_lidar
