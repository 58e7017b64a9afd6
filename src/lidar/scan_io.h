// Reading and writing LIDAR scans (LidarScan, in the LIDAR frame) as PLY,
// PCD and KITTI Velodyne .bin. The format is chosen by the file extension,
// case-insensitively.
//
// Reader contract (all formats):
//  - Coordinates x y z are required; intensity and ring are optional
//    channels (see ReadLidarScan for the accepted names).
//  - Points exactly at the origin (0, 0, 0) are dropped: many drivers write
//    them for a laser without return (organized Velodyne/Ouster clouds), and
//    as geometry they would be a spurious cluster at the sensor centre. The
//    count goes to one LOG(INFO) line. Their intensity and ring are dropped
//    with them, so the channels stay aligned.
//  - Throws colmap_lidar::Error naming the file on a missing file, a parse
//    failure, a non-finite coordinate (naming the point index in the file)
//    or a scan with no point left.
#pragma once

#include <string>

#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {

// Reads .ply, .pcd or .bin (KITTI).
//  - PLY (ASCII or binary): vertex properties x y z of any scalar type;
//    intensity from `intensity`, `reflectance` or `scalar_intensity` (first
//    present), ring from `ring`; other properties are ignored.
//  - PCD (ascii, binary, binary_compressed, through PCL): fields x y z,
//    intensity (or reflectance) and ring by name, any scalar type.
//  - KITTI .bin: records of float32 x y z reflectance, little-endian; the
//    file size must be a multiple of 16 bytes.
LidarScan ReadLidarScan(const std::string& path);

// The number of point records in the file, from the header (PLY, PCD) or
// the file size (.bin), without reading the points. It counts the no-return
// points that ReadLidarScan drops. Throws like ReadLidarScan.
size_t CountLidarScanPoints(const std::string& path);

// Writes x y z as float32, intensity as float32 and ring as uint16 when the
// scan has them. Binary little-endian by default, else ASCII. Atomic.
void WriteLidarScanPly(const std::string& path, const LidarScan& scan,
                       bool binary = true);

enum class PcdFormat { kAscii, kBinary, kBinaryCompressed };

// Writes through PCL with fields x y z intensity (float32) and ring
// (uint16) when present; an unorganized cloud (height 1). Atomic (written
// beside `path`, then renamed).
void WriteLidarScanPcd(const std::string& path, const LidarScan& scan,
                       PcdFormat format = PcdFormat::kBinary);

}  // namespace colmap_lidar
