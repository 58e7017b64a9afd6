// The debug overlay of a view, like the paper's Fig. 5: the image in grey,
// LIDAR edge points the camera sees drawn in the colour of the 3D segment
// they support (grey when they joined none), and each 3D segment reprojected
// into the image as a line of its colour with its endpoints marked.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "colmap_ext/scene/camera.h"
#include "src/lines/line_extractor.h"

namespace colmap_lidar {

// Returns a BGR image of the image's size.
cv::Mat DrawLineOverlay(const cv::Mat& image, const ViewLines& lines,
                        const Camera& camera);

// Encodes as PNG and writes atomically; throws naming the path on failure.
void WriteLineOverlay(const std::string& path, const cv::Mat& overlay);

}  // namespace colmap_lidar
