// 2D line segments of an image with the Line Segment Detector (LSD, Grompone
// von Gioi et al. 2012) as OpenCV implements it (paper section III-B, first
// step of the line detection module).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "src/lines/line_types.h"

namespace colmap_lidar {

struct LsdOptions {
  // Segments shorter than this are dropped, pixels.
  double min_length_px = 20.0;
  // LSD's Gaussian down-scaling of the image before detection, (0, 1];
  // OpenCV's default is 0.8. Smaller is faster and finds fewer, longer
  // segments.
  double scale = 0.8;
  // Refine the segments (OpenCV LSD_REFINE_STD: splits arcs into segments).
  bool refine = false;
  // At most this many segments are kept (the longest); 0 = no limit.
  int max_num_segments = 0;

  bool Check() const;
};

// `image` is 8-bit grey or BGR (converted to grey). Segments are returned
// longest first, in COLMAP pixel coordinates (OpenCV's detector puts the
// centre of the first pixel at 0, so 0.5 is added). An empty image throws.
std::vector<LineSegment2D> DetectLineSegments(const cv::Mat& image,
                                              const LsdOptions& options);

}  // namespace colmap_lidar
