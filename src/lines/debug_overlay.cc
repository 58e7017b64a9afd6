#include "src/lines/debug_overlay.h"

#include <unordered_map>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// A saturated colour per segment index (golden-angle hue steps).
cv::Scalar SegmentColor(const size_t idx) {
  const int hue = static_cast<int>((idx * 137.508)) % 180;
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(hue, 255, 255));
  cv::Mat bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  const cv::Vec3b color = bgr.at<cv::Vec3b>(0, 0);
  return cv::Scalar(color[0], color[1], color[2]);
}

cv::Point ToCv(const Eigen::Vector2d& pixel) {
  // COLMAP pixel convention to OpenCV drawing coordinates.
  return cv::Point(static_cast<int>(std::lround(pixel.x() - 0.5)),
                   static_cast<int>(std::lround(pixel.y() - 0.5)));
}

}  // namespace

cv::Mat DrawLineOverlay(const cv::Mat& image, const ViewLines& lines,
                        const Camera& camera) {
  THROW_CHECK(!image.empty(), "DrawLineOverlay: empty image");
  cv::Mat gray;
  if (image.channels() == 3) {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  } else {
    gray = image;
  }
  cv::Mat overlay;
  // Dimmed so that the colours stand out.
  cv::cvtColor(gray / 2 + 40, overlay, cv::COLOR_GRAY2BGR);

  std::unordered_map<int, size_t> segment_of_point;
  for (size_t s = 0; s < lines.segments.size(); ++s) {
    for (const int idx : lines.segments[s].inlier_point_idxs) {
      segment_of_point.emplace(idx, s);
    }
  }
  for (size_t i = 0; i < lines.visible_edge_point_idxs.size(); ++i) {
    const auto it = segment_of_point.find(lines.visible_edge_point_idxs[i]);
    if (it == segment_of_point.end()) {
      cv::circle(overlay, ToCv(lines.visible_edge_pixels[i]), 1,
                 cv::Scalar(170, 170, 170), cv::FILLED);
    }
  }
  for (size_t i = 0; i < lines.visible_edge_point_idxs.size(); ++i) {
    const auto it = segment_of_point.find(lines.visible_edge_point_idxs[i]);
    if (it != segment_of_point.end()) {
      cv::circle(overlay, ToCv(lines.visible_edge_pixels[i]), 3,
                 SegmentColor(it->second), cv::FILLED);
    }
  }
  for (size_t s = 0; s < lines.segments.size(); ++s) {
    const ViewLineSegment& segment = lines.segments[s];
    const cv::Point start = ToCv(camera.ImgFromCam(segment.start3D_in_cam));
    const cv::Point end = ToCv(camera.ImgFromCam(segment.end3D_in_cam));
    const cv::Scalar color = SegmentColor(s);
    cv::line(overlay, start, end, color, 2, cv::LINE_AA);
    cv::circle(overlay, start, 4, color, 1, cv::LINE_AA);
    cv::circle(overlay, end, 4, color, 1, cv::LINE_AA);
  }
  return overlay;
}

void WriteLineOverlay(const std::string& path, const cv::Mat& overlay) {
  std::vector<uint8_t> buffer;
  THROW_CHECK(cv::imencode(".png", overlay, buffer),
              "Cannot encode the overlay for " << path);
  WriteFileAtomically(path, [&buffer](std::ostream& stream) {
    stream.write(reinterpret_cast<const char*>(buffer.data()),
                 static_cast<std::streamsize>(buffer.size()));
  });
}

}  // namespace colmap_lidar
