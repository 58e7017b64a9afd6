#include "src/lines/lsd_detector.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

bool LsdOptions::Check() const {
  if (!(min_length_px >= 0.0)) {
    LOG(ERROR) << "LineExtraction.lsd_min_length_px must be >= 0, got "
               << min_length_px;
    return false;
  }
  if (!(scale > 0.0 && scale <= 1.0)) {
    LOG(ERROR) << "LineExtraction.lsd_scale must be in (0, 1], got " << scale;
    return false;
  }
  if (max_num_segments < 0) {
    LOG(ERROR) << "LineExtraction.lsd_max_num_segments must be >= 0, got "
               << max_num_segments;
    return false;
  }
  return true;
}

std::vector<LineSegment2D> DetectLineSegments(const cv::Mat& image,
                                              const LsdOptions& options) {
  THROW_CHECK(!image.empty(), "DetectLineSegments: empty image");
  cv::Mat gray;
  if (image.channels() == 3) {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  } else {
    THROW_CHECK(image.channels() == 1 && image.depth() == CV_8U,
                "DetectLineSegments: expected an 8-bit grey or BGR image");
    gray = image;
  }
  const cv::Ptr<cv::LineSegmentDetector> detector =
      cv::createLineSegmentDetector(
          options.refine ? cv::LSD_REFINE_STD : cv::LSD_REFINE_NONE,
          options.scale);
  std::vector<cv::Vec4f> lines;
  detector->detect(gray, lines);

  std::vector<LineSegment2D> segments;
  segments.reserve(lines.size());
  for (const cv::Vec4f& line : lines) {
    LineSegment2D segment;
    segment.start = Eigen::Vector2d(line[0] + 0.5, line[1] + 0.5);
    segment.end = Eigen::Vector2d(line[2] + 0.5, line[3] + 0.5);
    if (segment.Length() >= options.min_length_px && segment.Length() > 0) {
      segments.push_back(segment);
    }
  }
  std::stable_sort(segments.begin(), segments.end(),
                   [](const LineSegment2D& a, const LineSegment2D& b) {
                     return a.Length() > b.Length();
                   });
  if (options.max_num_segments > 0 &&
      static_cast<int>(segments.size()) > options.max_num_segments) {
    segments.resize(options.max_num_segments);
  }
  return segments;
}

}  // namespace colmap_lidar
