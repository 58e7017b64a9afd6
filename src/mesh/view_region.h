// The region the images see, to which the mesher's input is cropped: inside
// the image of at least one camera and at most max_depth in front of it.
//
// Why: a LIDAR sees all around and far (KITTI: 360 degrees, 80 m) while the
// cameras see a cone ahead. Meshing everything the scans reach gave KITTI's
// 20 frames 6.2M cells whose sparse, grazing far-field rays conflict with
// each other: the max-flow then routes > 1e6 units of flow in millions of
// augmenting paths (> 34 min). The surface nobody photographed is not what
// the camera + LIDAR mesh is for; cropped to the cameras' view the same
// frames give ~1.1M cells and the cut takes under a minute (mesh stage 95 s).
// The price: surfaces only the LIDAR sees are not meshed (on the synthetic
// quad, recall at 0.1 m falls from 0.83 to 0.60), so it is off by default.
//
// max_depth is derived from the data: depth_factor times the depth_quantile
// of the visual points' depths in the cameras that saw them (KITTI: 95 % of
// the visual points within 13.7 m -> 27 m at factor 2).
#pragma once

#include <cstddef>

#include "src/mesh/meshing_input.h"

namespace colmap_lidar {

struct ViewRegionOptions {
  // Quantile of the visual points' depths in their cameras, in (0, 1].
  double depth_quantile = 0.95;
  // Maximum depth = depth_factor * that quantile; 0 disables the cropping.
  double depth_factor = 0.0;

  bool Check() const;
};

// The maximum depth of the view region; 0 (no cropping) when the input has
// no visual point or the factor is 0.
double ViewRegionMaxDepth(const ViewRegionOptions& options,
                          const MeshingInput& input);

// True when `point` lies in the image (pixel centres of [0, width) x [0,
// height)) of at least one camera with image size, at a depth in (0,
// max_depth].
bool IsInViewRegion(const MeshingInput& input, double max_depth,
                    const Eigen::Vector3d& point);

// Removes the points outside the view region (sensors are kept); returns the
// number removed. Does nothing when max_depth <= 0 or no camera has an image
// size.
size_t CropToViewRegion(double max_depth, MeshingInput* input);

}  // namespace colmap_lidar
