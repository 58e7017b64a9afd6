// The line_extractor stage over a COLMAP workspace: for every image with a
// LIDAR scan (ext_lidar_scans), runs ExtractViewLines and stores the result
// in ext_line_segments (replacing that image's rows), in parallel over
// images, with one progress line per image and a summary. Under mpirun /
// srun (colmap_ext/util/process_group.h) the images are split over the
// ranks; rank 0 alone opens the database, sends the others their jobs and
// writes their segments with its own, all in one transaction, and its
// summary counts every rank's images (the others' count their own).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "colmap_ext/database/line_segments_table.h"
#include "src/lines/line_extractor.h"

namespace colmap_lidar {

struct WorkspaceLineExtractionSummary {
  int num_images = 0;
  // Images skipped because they have no LIDAR scan.
  int num_images_without_scan = 0;
  int64_t num_lsd_segments = 0;
  int64_t num_lifted_segments = 0;
  int64_t num_segments = 0;
  int min_segments_per_image = 0;
  int max_segments_per_image = 0;
  double mean_ms_per_image = 0.0;

  // A few human-readable lines: segments per image, share of 2D segments
  // lifted to 3D.
  std::string Format() const;
};

// The stored form of a view's segment (descriptor and inlier count kept).
LineSegmentRecord ToLineSegmentRecord(const ViewLineSegment& segment);

// database_path: an existing database.db; scan paths in ext_lidar_scans are
// relative to its folder (or absolute). image_path: the image folder.
// image_names: images to process (empty: all images that have a scan); a
// name that is not in the database, or has no scan, throws. debug_path: when
// not empty, a folder (created) that receives per image <stem>.png (the
// overlay) and <stem>.json (every LSD segment and why it was or was not
// lifted; debug_overlay.h), slashes in names becoming '_'. Throws naming the file on I/O errors; the
// images finished before the error keep their rows.
WorkspaceLineExtractionSummary ExtractWorkspaceLines(
    const std::string& database_path, const std::string& image_path,
    const std::vector<std::string>& image_names,
    const LineExtractionOptions& options, const std::string& debug_path = "");

}  // namespace colmap_lidar
