#include "src/mvs/map_filter.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <utility>

#include "colmap_ext/util/logging.h"
#include "src/mvs/parallel_rows.h"

namespace colmap_lidar {

size_t FilterByCost(float max_cost, PlaneMap* map) {
  size_t kept = 0;
  for (size_t i = 0; i < map->depth.size(); ++i) {
    if (!(map->depth[i] > 0) || !(map->cost[i] <= max_cost)) {
      map->depth[i] = 0.0f;
      map->normal[i].setZero();
    } else {
      ++kept;
    }
  }
  return kept;
}

size_t FilterByCostOrPrior(float max_cost, const std::vector<float>& prior_depth,
                           float prior_tolerance, PlaneMap* map) {
  THROW_CHECK(prior_depth.size() == map->depth.size(),
              "prior depth of " << prior_depth.size() << " pixels for a map of "
                                << map->depth.size());
  size_t kept = 0;
  for (size_t i = 0; i < map->depth.size(); ++i) {
    const float depth = map->depth[i];
    const float prior = prior_depth[i];
    const bool supported =
        prior > 0 && std::abs(depth - prior) <= prior_tolerance * prior;
    if (!(depth > 0) || !(map->cost[i] <= max_cost || supported)) {
      map->depth[i] = 0.0f;
      map->normal[i].setZero();
    } else {
      ++kept;
    }
  }
  return kept;
}

DepthSupportCounts& DepthSupportCounts::operator+=(
    const DepthSupportCounts& other) {
  images_only += other.images_only;
  images_and_lidar += other.images_and_lidar;
  lidar_and_views += other.lidar_and_views;
  lidar_only += other.lidar_only;
  return *this;
}

std::string DepthSupportCounts::Format() const {
  const double total = static_cast<double>(std::max<size_t>(Total(), 1));
  const auto percent = [&](size_t n) {
    std::ostringstream out;
    out << std::fixed << std::setprecision(1) << 100.0 * n / total << " %";
    return out.str();
  };
  std::ostringstream out;
  out << Total() << " pixels: " << percent(images_only) << " images only, "
      << percent(images_and_lidar) << " images and LIDAR, "
      << percent(lidar_and_views + lidar_only) << " need the LIDAR ("
      << percent(lidar_only) << " the LIDAR alone)";
  return out.str();
}

size_t KeepLidarWhereUnseen(const PatchCostComputer& cost,
                            const std::vector<float>& prior_depth,
                            const std::vector<Eigen::Vector3f>& prior_normal,
                            PlaneMap* map) {
  THROW_CHECK(prior_depth.size() == map->depth.size() &&
                  prior_normal.size() == map->depth.size(),
              "LIDAR prior of "
                  << prior_depth.size() << " depths and " << prior_normal.size()
                  << " normals for a map of " << map->depth.size());
  size_t num_reset = 0;
  for (int row = 0; row < map->height; ++row) {
    for (int col = 0; col < map->width; ++col) {
      const size_t i = map->Index(row, col);
      const float prior = prior_depth[i];
      if (!(prior > 0) || !(prior_normal[i].norm() > 0)) continue;
      bool seen = false;
      for (int s = 0; s < cost.NumSources() && !seen; ++s) {
        seen = cost.SourceSees(s, row, col, prior);
      }
      if (seen) continue;
      map->depth[i] = prior;
      map->normal[i] = prior_normal[i];
      map->cost[i] = kMaxCost;
      ++num_reset;
    }
  }
  return num_reset;
}

size_t FilterByConsistency(const PatchCostComputer& cost,
                           const LidarPatchMatchOptions& options,
                           const std::vector<float>& lidar_depth,
                           PlaneMap* map,
                           std::vector<uint8_t>* not_fused,
                           DepthSupportCounts* support) {
  THROW_CHECK(cost.HasSourceMaps(),
              "consistency filter of " << cost.Ref().name
                                       << " without source maps");
  const float max_lidar_relative =
      static_cast<float>(options.filter_lidar_max_relative_depth_error);
  const bool lidar_votes =
      options.filter_lidar_as_view && !lidar_depth.empty();
  THROW_CHECK(!lidar_votes || lidar_depth.size() == map->depth.size(),
              "LIDAR depth of " << lidar_depth.size() << " pixels for a map of "
                                << map->depth.size());
  const float max_reproj = static_cast<float>(options.filter_max_reproj_error);
  const float max_relative =
      static_cast<float>(options.filter_max_relative_depth_error);
  // Per pixel: 0 dropped, else 1 + the DepthSupportCounts field (in order).
  std::vector<uint8_t> label(map->depth.size(), 0);
  // Per kept pixel: 1 where fewer than the required source views agree
  // within max_reproj pixels (without the parallax tolerance or the LIDAR).
  std::vector<uint8_t> unfused(map->depth.size(), 0);
  ParallelForRows(map->height, options.num_threads, [&](int row) {
    for (int col = 0; col < map->width; ++col) {
      const size_t i = map->Index(row, col);
      const float depth = map->depth[i];
      if (!(depth > 0)) continue;
      int num_consistent = 0;
      int num_strict_views = 0;
      // Views able to confirm the pixel: the LIDAR where it measured one,
      // the sources whose image contains the point.
      int num_able = lidar_votes && lidar_depth[i] > 0 ? 1 : 0;
      const bool lidar_agrees =
          lidar_votes && lidar_depth[i] > 0 &&
          std::abs(depth - lidar_depth[i]) <= max_lidar_relative * lidar_depth[i];
      if (lidar_agrees) {
        ++num_consistent;
      }
      for (int s = 0; s < cost.NumSources(); ++s) {
        if (cost.SourceSees(s, row, col, depth)) ++num_able;
        const float depth_error = cost.SourceDepthError(s, row, col, depth);
        if (!(depth_error <= max_relative)) continue;
        const float reproj_error = cost.ReprojectionError(s, row, col, depth);
        if (reproj_error <= max_reproj) {
          ++num_strict_views;
          ++num_consistent;
        } else if (options.filter_reproj_parallax &&
                   reproj_error <=
                       max_reproj + cost.DepthErrorParallax(
                                        s, row, col, depth, max_relative)) {
          ++num_consistent;
        }
      }
      // visible_sources_only: min(filter_min_num_consistent, the views able
      // to confirm the pixel) must agree, at least one (a pixel that no view
      // can see is dropped).
      const int required =
          options.visible_sources_only
              ? std::min(options.filter_min_num_consistent,
                         std::max(1, num_able))
              : options.filter_min_num_consistent;
      if (num_consistent < required) {
        map->depth[i] = 0.0f;
        map->normal[i].setZero();
        continue;
      }
      unfused[i] = num_strict_views < required ? 1 : 0;
      if (!lidar_agrees) {
        label[i] = 1;
      } else if (num_consistent > required) {
        label[i] = 2;
      } else {
        label[i] = num_consistent > 1 ? 3 : 4;
      }
    }
  });
  if (not_fused != nullptr) {
    *not_fused = std::move(unfused);
  }
  if (support != nullptr) {
    size_t* fields[4] = {&support->images_only, &support->images_and_lidar,
                         &support->lidar_and_views, &support->lidar_only};
    for (const uint8_t l : label) {
      if (l > 0) ++*fields[l - 1];
    }
  }
  return map->NumValid();
}

}  // namespace colmap_lidar
