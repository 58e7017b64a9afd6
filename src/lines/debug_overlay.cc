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

// The colour of an LSD segment that was not lifted, by the first reason
// that stopped it: no LIDAR support at all (black), a texture line or
// the same surface on both sides (blue), a surface the LIDAR cannot
// classify (one face and no ray past the other side, or too few points:
// white), a fit that did not agree with the segment (orange), too little
// support along it (magenta).
const cv::Scalar kNoSupportColor(0, 0, 0);
const cv::Scalar kTextureColor(255, 120, 0);
const cv::Scalar kUnknownSurfaceColor(255, 255, 255);
const cv::Scalar kDisagreeColor(0, 140, 255);
const cv::Scalar kLowCoverageColor(200, 0, 200);

cv::Scalar SegmentRejectionColor(const SegmentOutcome& outcome) {
  const bool unknown_surface =
      outcome.edge_result == LiftResult::kTexture &&
      outcome.edge_surface == LineSurfaceType::kUnknown;
  const bool texture =
      (outcome.edge_result == LiftResult::kTexture && !unknown_surface) ||
      outcome.plane_result == PlaneLiftResult::kTexture;
  if (texture) return kTextureColor;
  if (unknown_surface) return kUnknownSurfaceColor;
  const bool disagree =
      outcome.edge_result == LiftResult::kReprojection ||
      outcome.edge_result == LiftResult::kBackProjection ||
      outcome.edge_result == LiftResult::kRansacFailed ||
      outcome.plane_result == PlaneLiftResult::kReprojection ||
      outcome.plane_result == PlaneLiftResult::kBackProjection ||
      outcome.plane_result == PlaneLiftResult::kOutOfRange;
  if (disagree) return kDisagreeColor;
  const bool low_coverage =
      outcome.edge_result == LiftResult::kLowCoverage ||
      outcome.plane_result == PlaneLiftResult::kLowCoverage;
  if (low_coverage) return kLowCoverageColor;
  return kNoSupportColor;
}

void DrawLegend(cv::Mat* overlay) {
  const std::pair<const char*, cv::Scalar> entries[] = {
      {"no LIDAR support", kNoSupportColor},
      {"texture / one surface", kTextureColor},
      {"LIDAR cannot tell", kUnknownSurfaceColor},
      {"fit disagrees", kDisagreeColor},
      {"low coverage", kLowCoverageColor}};
  int y = 14;
  for (const auto& [text, color] : entries) {
    cv::line(*overlay, cv::Point(6, y - 4), cv::Point(26, y - 4), color, 2);
    cv::putText(*overlay, text, cv::Point(32, y), cv::FONT_HERSHEY_PLAIN,
                0.9, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    y += 14;
  }
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

  for (const SegmentOutcome& outcome : lines.outcomes) {
    if (outcome.Lifted()) continue;
    cv::line(overlay, ToCv(outcome.segment.start), ToCv(outcome.segment.end),
             SegmentRejectionColor(outcome), 1, cv::LINE_AA);
  }
  if (!lines.outcomes.empty()) {
    DrawLegend(&overlay);
  }

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

Json LineOutcomesToJson(const std::string& image_name,
                        const ViewLines& lines) {
  Json json;
  json["image_name"] = image_name;
  json["num_lsd_segments"] = lines.num_lsd_segments;
  json["num_segments"] = lines.segments.size();
  json["range_noise_m"] = lines.range_noise_m;
  Json segments = Json::array();
  for (const SegmentOutcome& outcome : lines.outcomes) {
    Json segment;
    segment["start"] = VectorToJson(outcome.segment.start);
    segment["end"] = VectorToJson(outcome.segment.end);
    segment["edge_result"] = LiftResultName(outcome.edge_result);
    segment["plane_result"] = PlaneLiftResultName(outcome.plane_result);
    if (outcome.edge_surface.has_value()) {
      segment["edge_surface"] = LineSurfaceTypeName(*outcome.edge_surface);
    }
    if (outcome.Lifted()) {
      segment["lifted_start"] = VectorToJson(outcome.lifted2D.start);
      segment["lifted_end"] = VectorToJson(outcome.lifted2D.end);
      segment["start3D_in_cam"] = VectorToJson(outcome.start3D_in_cam);
      segment["end3D_in_cam"] = VectorToJson(outcome.end3D_in_cam);
    }
    segments.push_back(std::move(segment));
  }
  json["segments"] = std::move(segments);
  return json;
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
