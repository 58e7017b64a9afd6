// Keeps a dense workspace's cameras in step with its undistorted images.
//
// Stock COLMAP 3.8's image_undistorter with --max_image_size writes the
// images scaled down but the cameras of <dense>/sparse at the full size
// (seen with output_type COLMAP): every reader of the workspace (our
// PatchMatch, stock stereo_fusion) then pairs a 320x181 image with an
// 848x480 camera.
#pragma once

#include <string>

namespace colmap_lidar {

// Scales each camera of <dense_path>/sparse to the size of its images in
// <dense_path>/images (read from the first image of the camera; every other
// image of it must have the same size): focal lengths and principal point
// by width and height ratios, as colmap's Camera::Rescale. Only the
// undistorted models (PINHOLE, SIMPLE_PINHOLE) are accepted. The model is
// rewritten (atomically per file, same format) only when a camera changed.
// Returns the number of cameras scaled. Throws colmap_lidar::Error naming
// the image or camera at fault (unreadable image, other model, images of
// one camera with different sizes).
int ScaleDenseCamerasToImages(const std::string& dense_path);

}  // namespace colmap_lidar
