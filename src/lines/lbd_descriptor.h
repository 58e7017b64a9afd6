// LBD (Line Band Descriptor, Zhang & Koch 2013) of 2D segments with OpenCV
// contrib's line_descriptor module. The association stage (section III-C,
// t_LBD of Algorithm 1) compares these 256-bit descriptors by Hamming
// distance.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "src/lines/line_types.h"

namespace colmap_lidar {

// One descriptor per segment, in the order of `segments`; computed on the
// full-resolution image (one octave). `image` is 8-bit grey or BGR.
// Segments outside the image are clipped by OpenCV; a segment OpenCV cannot
// describe gets an all-zero descriptor (with one LOG(WARNING) per call).
std::vector<LbdDescriptor> ComputeLbdDescriptors(
    const cv::Mat& image, const std::vector<LineSegment2D>& segments);

// Number of differing bits, 0..256.
int LbdHammingDistance(const LbdDescriptor& a, const LbdDescriptor& b);

}  // namespace colmap_lidar
