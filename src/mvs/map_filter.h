// Filtering of PatchMatch results before they are written (COLMAP's
// filter step): photometric maps drop pixels whose cost exceeds
// filter_max_cost; geometric maps also need at least
// filter_min_num_consistent source views whose depth map agrees
// (forward-backward reprojection error <= filter_max_reproj_error pixels and
// relative depth error <= filter_max_relative_depth_error; with
// filter_reproj_parallax the pixel tolerance grows by the parallax of that
// relative depth error), the LIDAR
// counting as one with filter_lidar_as_view; with visible_sources_only no
// more than the views that can see the pixel (the sources whose image holds
// its point, and the LIDAR where it has a depth there).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "src/mvs/ncc_cost.h"
#include "src/mvs/patch_match_options.h"
#include "src/mvs/plane_map.h"

namespace colmap_lidar {

// Returns the number of pixels kept. `max_cost` is compared with map->cost.
size_t FilterByCost(float max_cost, PlaneMap* map);

// As FilterByCost, but a pixel whose depth agrees with its prior depth
// (> 0) within `prior_tolerance` (relative) is kept whatever its cost: the
// LIDAR supports it where the photometric cost cannot (textureless
// surfaces, where NCC is undefined and costs kMaxCost). `prior_depth` is
// row-major of the map's size.
size_t FilterByCostOrPrior(float max_cost, const std::vector<float>& prior_depth,
                           float prior_tolerance, PlaneMap* map);

// What confirmed the pixels a consistency filter kept (issue 17: how much of
// the depth comes from the images, from the LIDAR, from both).
struct DepthSupportCounts {
  // Enough source views agree; the LIDAR has no depth there or disagrees.
  size_t images_only = 0;
  // Enough source views agree, and so does the LIDAR.
  size_t images_and_lidar = 0;
  // Kept only thanks to the LIDAR's vote (masked out of fusion): with
  // agreeing source views, fewer than required, or with none (no source view
  // sees the point: the LIDAR alone, with visible_sources_only).
  size_t lidar_and_views = 0;
  size_t lidar_only = 0;

  size_t Total() const {
    return images_only + images_and_lidar + lidar_and_views + lidar_only;
  }
  DepthSupportCounts& operator+=(const DepthSupportCounts& other);
  // "N pixels: a % images only, b % images and LIDAR, c % need the LIDAR
  // (d % the LIDAR alone)".
  std::string Format() const;
};

// Where no source view can see the surface of the LIDAR prior (its point
// lies behind every source or outside its image: the surroundings of the
// first frame of a walk, which the later frames have passed), the images
// cannot measure the pixel and the LIDAR is its only measurement; but the
// search moves such a pixel to any depth some source sees, since an
// unverifiable hypothesis costs the maximum and a match anywhere costs
// less. Resets those pixels (prior_depth > 0, a prior normal) to the prior's
// plane with cost kMaxCost, so that FilterByCostOrPrior keeps them and
// FilterByConsistency confirms them by the LIDAR alone (kept out of fusion:
// no source agrees). `prior_depth` and `prior_normal` are row-major of the
// map's size. Returns the number of pixels reset.
size_t KeepLidarWhereUnseen(const PatchCostComputer& cost,
                            const std::vector<float>& prior_depth,
                            const std::vector<Eigen::Vector3f>& prior_normal,
                            PlaneMap* map);

// Needs cost.HasSourceMaps(). `lidar_depth` (row-major of the map's size,
// 0: none; may be empty) is the interpolated LIDAR depth: with
// options.filter_lidar_as_view, agreeing with it within
// filter_lidar_max_relative_depth_error counts as one consistent view.
// `not_fused` (optional) is set to the map's size, 1 where a kept pixel has
// fewer than the required source views agreeing within
// filter_max_reproj_error pixels, i.e. was kept only thanks to the LIDAR's
// vote or to the parallax tolerance (filter_reproj_parallax), 0 elsewhere:
// the fusion mask, which keeps the fused cloud that of the strict two-view
// filter. `support` (optional) counts the kept pixels by what confirmed
// them. Returns the number of pixels kept.
size_t FilterByConsistency(const PatchCostComputer& cost,
                           const LidarPatchMatchOptions& options,
                           const std::vector<float>& lidar_depth,
                           PlaneMap* map,
                           std::vector<uint8_t>* not_fused = nullptr,
                           DepthSupportCounts* support = nullptr);

}  // namespace colmap_lidar
