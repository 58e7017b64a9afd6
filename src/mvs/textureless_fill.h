// Depth for the unmeasured part of a textureless surface whose other part
// is measured (issue 17: coverage where neither the images nor the LIDAR
// measure). Plain plaster above a LIDAR's vertical field has no LIDAR sample
// and a window whose grey variance is below the NCC cost's floor, so
// PatchMatch cannot verify any depth there and the filters drop it: on the
// quad HDL-64E 14 % of the surface pixels. The same plaster below the field
// is measured (the LIDAR's prior holds it), and nothing in the image
// separates the two parts. As textureless-aware MVS does per superpixel
// (Romanoni and Matteucci 2019, "TAPA-MVS"; Xu and Tao 2020, "Planar Prior
// Assisted PatchMatch"), the unmeasured part takes the plane of the
// measured one.
//
// Regions: 4-connected components of textureless pixels (measured or not).
// A texture edge bounds them: the NCC window straddling an edge has
// variance, so a roof line separates a wall from the sky, a kerb the road
// from the pavement. A region is filled only when
// - it holds at least `min_support_pixels` measured pixels, which are not
//   on one line (their smaller principal standard deviation at least
//   `min_support_spread_px`: a line of pixels fixes no tilt across it);
// - one plane explains them: RANSAC on the affine model of inverse z-depth
//   (on a plane, 1 / z = a col + b row + c exactly), refitted by least
//   squares, keeps at least `min_inlier_ratio` of them within
//   `max_relative_depth_error` whose own normals lie within
//   `max_normal_angle_deg` of the plane's (the measured normals come from
//   the LIDAR's fitted planes or from PatchMatch, independently of the
//   depths: a curved surface fits one plane's depths within the tolerance
//   over a small region, not its normals);
// then its empty pixels take the plane, up to `max_depth_factor` times the
// region's farthest inlier (a plane seen nearly edge-on runs to infinity
// at its horizon). A region with no measured pixel (the sky) stays empty.
// The caller keeps the filled pixels out of fusion: interpolated, not
// measured.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "src/mvs/plane_map.h"

namespace colmap_lidar {

struct TexturelessFillOptions {
  // Measured pixels a region needs, >= 3.
  int min_support_pixels = 100;
  // Their smaller principal standard deviation in the image, pixels, >= 0.
  double min_support_spread_px = 3.0;
  // Share of them the plane must explain, (0, 1].
  double min_inlier_ratio = 0.9;
  // Inlier tolerance, relative depth, > 0 (the geometric filter's).
  double max_relative_depth_error = 0.01;
  // An inlier's normal against the plane's, degrees, (0, 90].
  double max_normal_angle_deg = 10.0;
  // Filled depths at most this times the farthest inlier's, >= 1.
  double max_depth_factor = 2.0;
  // RANSAC iterations per region, >= 1.
  int num_ransac_iterations = 64;

  bool Check() const;
};

// `K`: the map's pinhole intrinsics. `textureless`: row-major of the map's
// size, 1 where the pixel's NCC window is too plain to verify a depth.
// Filled pixels get cost `filled_cost`; `filled` (optional) is set to the
// map's size, 1 at them. Returns their number. Deterministic.
size_t FillTexturelessRegions(const Eigen::Matrix3f& K,
                              const std::vector<uint8_t>& textureless,
                              const TexturelessFillOptions& options,
                              float filled_cost, PlaneMap* map,
                              std::vector<uint8_t>* filled = nullptr);

}  // namespace colmap_lidar
