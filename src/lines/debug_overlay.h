// The debug overlay of a view, like the paper's Fig. 5: the image in grey,
// LIDAR edge points the camera sees drawn in the colour of the 3D segment
// they support (grey when they joined none), and each 3D segment reprojected
// into the image as a line of its colour with its endpoints marked. The LSD
// segments that were not lifted are drawn thin, coloured by why
// (SegmentRejectionColor; a legend is drawn in the top-left corner).
// Beside the overlay, --debug_path holds the same as JSON per view
// (LineOutcomesToJson): every LSD segment, its outcome and, when lifted,
// its 3D endpoints, for scripts that compare them with a ground truth.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "colmap_ext/scene/camera.h"
#include "colmap_ext/util/json.h"
#include "src/lines/line_extractor.h"

namespace colmap_lidar {

// Returns a BGR image of the image's size.
cv::Mat DrawLineOverlay(const cv::Mat& image, const ViewLines& lines,
                        const Camera& camera);

// {"image_name", "num_lsd_segments", "num_segments", "range_noise_m",
//  "segments": [{"start", "end" (pixels, COLMAP convention), "edge_result",
//  "plane_result" (LiftResultName / PlaneLiftResultName), and when lifted
//  "lifted_start", "lifted_end" (pixels), "start3D_in_cam", "end3D_in_cam"
//  (metres)}]}: the segments before the fusion of duplicates.
Json LineOutcomesToJson(const std::string& image_name, const ViewLines& lines);

// Encodes as PNG and writes atomically; throws naming the path on failure.
void WriteLineOverlay(const std::string& path, const cv::Mat& overlay);

}  // namespace colmap_lidar
