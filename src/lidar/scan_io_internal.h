// Helpers shared by the files that implement scan_io.h (scan_io.cc and the
// per-format scan_io_<format>.cc); not part of the module's interface. The
// per-format readers return the file's points as they are; ReadLidarScan
// then checks them and drops the no-return points.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {
namespace scan_io_internal {

// A ring value as uint16; throws naming the point `index` and `path` when
// it is not an integer in [0, 65535].
uint16_t ToRing(double value, size_t index, const std::string& path);

// Reads header lines of a text-header format until `last_keyword`.
// `header_bytes`, when given, receives the size of the header in bytes.
std::vector<std::vector<std::string>> ReadHeaderLines(
    const std::string& path, const std::string& last_keyword,
    size_t* header_bytes = nullptr);

// PLY (scan_io_ply.cc).
LidarScan ReadPlyScan(const std::string& path);
// The vertex count of the PLY header.
size_t CountPlyScanPoints(const std::string& path);

// PCD (scan_io_pcd.cc).
// Validates the header (PCL crashes on some malformed ones); returns the
// POINTS count.
size_t CheckPcdHeader(const std::string& path);
LidarScan ReadPcdScan(const std::string& path);

// KITTI Velodyne .bin (scan_io_kitti.cc).
// The number of records, from the file size.
size_t KittiBinNumPoints(const std::string& path);
LidarScan ReadKittiBinScan(const std::string& path);

}  // namespace scan_io_internal
}  // namespace colmap_lidar
