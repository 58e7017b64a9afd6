// Laser ring indices for scans whose file has no ring channel (KITTI .bin).
// The ring of a point is the laser that measured it; ring 0 is the lowest
// beam, rings increase with elevation. Two estimators:
//
//  - From the elevation angle seen from the sensor origin, for a known
//    vertical field of view. Simple and order-independent, but only as good
//    as the assumption of equally spaced beams from one centre: the
//    HDL-64E's upper block is 1/3 deg apart and its lasers sit centimetres
//    off the axis, so near points blur across neighbouring rings.
//  - From the point order, for files written ring after ring with each ring
//    one full turn in azimuth (KITTI's .bin layout). This recovers the true
//    lasers and needs no field of view. It returns an empty vector when the
//    order does not look like that.
//
// A histogram of elevation angles with one peak per laser was considered for
// an unknown field of view and rejected: on KITTI the peaks above -8 deg
// overlap (1/3 deg spacing plus the laser offsets), so peak picking gives
// neither the right count nor stable boundaries.
#pragma once

#include <cstdint>
#include <vector>

#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {

// Elevation of a point above the sensor's horizontal plane, degrees.
double ElevationDeg(const Eigen::Vector3f& point_in_lidar);

// Ring = round((elevation - min) / (max - min) * (num_rings - 1)), clamped
// to [0, num_rings - 1], i.e. the beams are assumed equally spaced with the
// lowest at min_elevation_deg and the highest at max_elevation_deg
// (HDL-64E: 64 rings, -24.9 .. +2 deg). Throws on num_rings outside
// [1, 65535] or min >= max.
std::vector<uint16_t> EstimateRingsFromElevation(const LidarScan& scan,
                                                 int num_rings,
                                                 double min_elevation_deg,
                                                 double max_elevation_deg);

// Splits the point sequence into full azimuth turns (the direction of
// rotation is detected; backward steps up to 45 deg count as jitter, larger
// ones as a forward gap) and numbers the turns by their median elevation,
// lowest first. Returns an empty vector (with a LOG(WARNING)) when the
// number of turns differs from num_rings, e.g. for clouds in firing order.
std::vector<uint16_t> EstimateRingsFromScanOrder(const LidarScan& scan,
                                                 int num_rings);

}  // namespace colmap_lidar
