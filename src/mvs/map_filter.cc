#include "src/mvs/map_filter.h"

#include <algorithm>
#include <cmath>

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

size_t FilterByConsistency(const PatchCostComputer& cost,
                           const LidarPatchMatchOptions& options,
                           const std::vector<float>& lidar_depth,
                           PlaneMap* map,
                           std::vector<uint8_t>* kept_by_lidar) {
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
  if (kept_by_lidar != nullptr) {
    kept_by_lidar->assign(map->depth.size(), 0);
  }
  ParallelForRows(map->height, options.num_threads, [&](int row) {
    for (int col = 0; col < map->width; ++col) {
      const size_t i = map->Index(row, col);
      const float depth = map->depth[i];
      if (!(depth > 0)) continue;
      int num_consistent = 0;
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
        if (cost.ReprojectionError(s, row, col, depth) <= max_reproj &&
            cost.SourceDepthError(s, row, col, depth) <= max_relative) {
          ++num_consistent;
        }
      }
      // A pixel no view can see is not confirmed by fewer required views.
      const int required =
          options.visible_sources_only
              ? std::min(options.filter_min_num_consistent,
                         std::max(1, num_able))
              : options.filter_min_num_consistent;
      if (num_consistent < required) {
        map->depth[i] = 0.0f;
        map->normal[i].setZero();
      } else if (lidar_agrees && kept_by_lidar != nullptr &&
                 num_consistent == required) {
        (*kept_by_lidar)[i] = 1;
      }
    }
  });
  return map->NumValid();
}

}  // namespace colmap_lidar
