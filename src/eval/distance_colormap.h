// Points coloured by a distance, with CloudCompare's "Blue > Green > Yellow
// > Red" ramp: blue (0, 0, 255) at distance 0, green (0, 255, 0) at 1/3 of
// the colour threshold, yellow (255, 255, 0) at 2/3, red (255, 0, 0) at the
// threshold and beyond, linear in between. Points excluded from a metric
// (outside the crop box, unobserved reference) are grey (128, 128, 128).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/util/types.h"

namespace colmap_lidar {

constexpr uint8_t kExcludedGrey = 128;

// Non-finite distances are red.
Vector3ub DistanceColor(double distance, double color_threshold);

// Writes a binary PLY: double x y z, uchar red green blue, and a double
// scalar field "distance" (CloudCompare loads it as a scalar field).
// `included` may be empty (all included); excluded points are grey. Throws
// naming the path on a write failure or mismatched sizes.
void WriteDistanceColoredPly(const std::string& path,
                             const std::vector<Eigen::Vector3d>& points,
                             const std::vector<double>& distances,
                             const std::vector<bool>& included,
                             double color_threshold);

}  // namespace colmap_lidar
