// Filtering of PatchMatch results before they are written (COLMAP's
// filter step): photometric maps drop pixels whose cost exceeds
// filter_max_cost; geometric maps also need at least
// filter_min_num_consistent source views whose depth map agrees
// (forward-backward reprojection error <= filter_max_reproj_error pixels and
// relative depth error <= filter_max_relative_depth_error).
#pragma once

#include "src/mvs/ncc_cost.h"
#include "src/mvs/patch_match_options.h"
#include "src/mvs/plane_map.h"

namespace colmap_lidar {

// Returns the number of pixels kept. `max_cost` is compared with map->cost.
size_t FilterByCost(float max_cost, PlaneMap* map);

// Needs cost.HasSourceMaps(). Returns the number of pixels kept.
size_t FilterByConsistency(const PatchCostComputer& cost,
                           const LidarPatchMatchOptions& options,
                           PlaneMap* map);

}  // namespace colmap_lidar
