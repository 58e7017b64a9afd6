#include "src/lines/lbd_descriptor.h"

#include <bitset>
#include <cmath>
#include <cstring>

#include <opencv2/imgproc.hpp>
#include <opencv2/line_descriptor.hpp>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

std::vector<LbdDescriptor> ComputeLbdDescriptors(
    const cv::Mat& image, const std::vector<LineSegment2D>& segments) {
  THROW_CHECK(!image.empty(), "ComputeLbdDescriptors: empty image");
  std::vector<LbdDescriptor> descriptors(segments.size(), LbdDescriptor{});
  if (segments.empty()) {
    return descriptors;
  }
  cv::Mat gray;
  if (image.channels() == 3) {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  } else {
    gray = image;
  }

  // KeyLines at octave 0 in OpenCV's pixel convention (first pixel centre
  // at 0); class_id carries our index because compute() may reorder or drop.
  std::vector<cv::line_descriptor::KeyLine> keylines;
  keylines.reserve(segments.size());
  const float image_size = static_cast<float>(std::max(gray.cols, gray.rows));
  for (size_t i = 0; i < segments.size(); ++i) {
    const float sx = static_cast<float>(segments[i].start.x() - 0.5);
    const float sy = static_cast<float>(segments[i].start.y() - 0.5);
    const float ex = static_cast<float>(segments[i].end.x() - 0.5);
    const float ey = static_cast<float>(segments[i].end.y() - 0.5);
    const float length = std::hypot(ex - sx, ey - sy);
    cv::line_descriptor::KeyLine keyline;
    keyline.startPointX = keyline.sPointInOctaveX = sx;
    keyline.startPointY = keyline.sPointInOctaveY = sy;
    keyline.endPointX = keyline.ePointInOctaveX = ex;
    keyline.endPointY = keyline.ePointInOctaveY = ey;
    keyline.lineLength = length;
    keyline.numOfPixels = static_cast<int>(std::ceil(length));
    keyline.angle = std::atan2(ey - sy, ex - sx);
    keyline.octave = 0;
    keyline.class_id = static_cast<int>(i);
    keyline.pt = cv::Point2f(0.5f * (sx + ex), 0.5f * (sy + ey));
    keyline.size = length;
    keyline.response = length / image_size;
    keylines.push_back(keyline);
  }

  cv::line_descriptor::BinaryDescriptor::Params params;
  params.numOfOctave_ = 1;
  const cv::Ptr<cv::line_descriptor::BinaryDescriptor> extractor =
      cv::line_descriptor::BinaryDescriptor::createBinaryDescriptor(params);
  cv::Mat mat;
  extractor->compute(gray, keylines, mat);
  THROW_CHECK(mat.rows == static_cast<int>(keylines.size()) &&
                  (mat.rows == 0 || (mat.cols == 32 && mat.type() == CV_8U)),
              "ComputeLbdDescriptors: unexpected descriptor matrix "
                  << mat.rows << "x" << mat.cols);
  for (int row = 0; row < mat.rows; ++row) {
    const int idx = keylines[row].class_id;
    THROW_CHECK(idx >= 0 && idx < static_cast<int>(segments.size()),
                "ComputeLbdDescriptors: bad keyline id " << idx);
    std::memcpy(descriptors[idx].data(), mat.ptr<uint8_t>(row), 32);
  }
  if (mat.rows < static_cast<int>(segments.size())) {
    LOG(WARNING) << "LBD: " << segments.size() - mat.rows << " of "
                 << segments.size()
                 << " segments have no descriptor (all-zero stored)";
  }
  return descriptors;
}

int LbdHammingDistance(const LbdDescriptor& a, const LbdDescriptor& b) {
  int distance = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    distance += static_cast<int>(
        std::bitset<8>(static_cast<unsigned>(a[i] ^ b[i])).count());
  }
  return distance;
}

}  // namespace colmap_lidar
