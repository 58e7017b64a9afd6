// Our table ext_line_segments: the 3D line segments of each view found by
// the line detection module (paper section III-B; src/lines).
//
// Contract: only segments that were lifted to 3D are stored (a 2D segment
// without LIDAR support has no use downstream: the 3D/3D association of
// section III-C needs the 3D endpoints and the LBD descriptor of each
// segment). Per image, `idx` runs 0..n-1 in the order written; it is the
// line2D_idx of LineTrackElement (colmap_ext/scene/line3d.h).
//
// Columns (all NOT NULL):
//   image_id    INTEGER  references images(image_id) ON DELETE CASCADE
//   idx         INTEGER  PRIMARY KEY (image_id, idx)
//   segment2D   BLOB     4 float64: x1 y1 x2 y2, pixels, COLMAP convention
//                        (centre of the upper-left pixel at (0.5, 0.5))
//   segment3D   BLOB     6 float64: X1 Y1 Z1 X2 Y2 Z2, metres, camera frame;
//                        endpoint k is the back-projection of 2D endpoint k
//   num_inliers INTEGER  LIDAR edge points supporting the segment
//   descriptor  BLOB     32 uint8, the LBD descriptor (OpenCV layout)
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/schema.h"

namespace colmap_lidar {

struct LineSegmentRecord {
  Eigen::Vector2d start2D = Eigen::Vector2d::Zero();
  Eigen::Vector2d end2D = Eigen::Vector2d::Zero();
  Eigen::Vector3d start3D_in_cam = Eigen::Vector3d::Zero();
  Eigen::Vector3d end3D_in_cam = Eigen::Vector3d::Zero();
  uint32_t num_inliers = 0;
  std::array<uint8_t, 32> descriptor{};
};

// The schema entry (listed in ExtTableSchemas(), schema.cc).
const TableSchema& LineSegmentsTableSchema();

// Replaces all segments of the image with `segments` (idx = position), in
// one transaction. The image must exist (foreign key) else throws.
void WriteLineSegments(Database* database, image_t image_id,
                       const std::vector<LineSegmentRecord>& segments);
// In idx order; empty when the image has none.
std::vector<LineSegmentRecord> ReadLineSegments(const Database& database,
                                                image_t image_id);
void DeleteLineSegments(Database* database, image_t image_id);
size_t NumLineSegments(const Database& database);
size_t NumLineSegmentsForImage(const Database& database, image_t image_id);
// Images with at least one segment, increasing.
std::vector<image_t> ReadImageIdsWithLineSegments(const Database& database);

// Segments by (image_id, idx) as line tracks refer to them, each image's
// read once. The database must outlive the cache.
class LineSegmentCache {
 public:
  explicit LineSegmentCache(const Database& database) : database_(database) {}
  // Throws naming the database, the image and `line3D_id` (the referring
  // track, for the message) when the image has no segment `idx`: a model or
  // track table of another run than the segments.
  const LineSegmentRecord& Segment(image_t image_id, uint32_t idx,
                                   line3D_t line3D_id);

 private:
  const Database& database_;
  std::unordered_map<image_t, std::vector<LineSegmentRecord>> segments_;
};

}  // namespace colmap_lidar
