#include "src/mvs/dense_cameras.h"

#include <map>
#include <opencv2/imgcodecs.hpp>
#include <utility>
#include <vector>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

int ScaleDenseCamerasToImages(const std::string& dense_path) {
  const std::string sparse_path = JoinPaths(dense_path, "sparse");
  const std::string image_path = JoinPaths(dense_path, "images");
  Reconstruction reconstruction = ReadReconstruction(sparse_path);

  // camera_id -> (width, height) of its images, and the image that set it.
  std::map<camera_t, std::pair<cv::Size, std::string>> sizes;
  for (const Image& image : reconstruction.images) {
    const std::string path = JoinPaths(image_path, image.name);
    // Every image is read: a camera shared by images of different sizes
    // cannot be fixed by scaling and is reported instead.
    const cv::Mat pixels = cv::imread(path, cv::IMREAD_UNCHANGED);
    THROW_CHECK(!pixels.empty(), "cannot read the undistorted image " << path);
    const auto [it, inserted] =
        sizes.emplace(image.camera_id, std::make_pair(pixels.size(), path));
    THROW_CHECK(inserted || it->second.first == pixels.size(),
                "undistorted images " << it->second.second << " and " << path
                                      << " share camera " << image.camera_id
                                      << " but differ in size");
  }

  int num_scaled = 0;
  for (auto& [camera_id, camera] : reconstruction.cameras) {
    const auto it = sizes.find(camera_id);
    if (it == sizes.end()) {
      continue;
    }
    const cv::Size size = it->second.first;
    if (static_cast<uint64_t>(size.width) == camera.width &&
        static_cast<uint64_t>(size.height) == camera.height) {
      continue;
    }
    const double scale_x = static_cast<double>(size.width) / camera.width;
    const double scale_y = static_cast<double>(size.height) / camera.height;
    std::vector<double>& params = camera.params;
    if (camera.model_id == CameraModelId::kPinhole) {
      params = {params[0] * scale_x, params[1] * scale_y, params[2] * scale_x,
                params[3] * scale_y};
    } else if (camera.model_id == CameraModelId::kSimplePinhole) {
      params = {params[0] * 0.5 * (scale_x + scale_y), params[1] * scale_x,
                params[2] * scale_y};
    } else {
      THROW_ERROR("camera " << camera_id << " of " << sparse_path << " is "
                            << camera.ModelName()
                            << "; an undistorted workspace has PINHOLE or "
                               "SIMPLE_PINHOLE cameras");
    }
    LOG(INFO) << "Dense camera " << camera_id << " scaled from " << camera.width
              << "x" << camera.height << " to its images' " << size.width << "x"
              << size.height;
    camera.width = size.width;
    camera.height = size.height;
    ++num_scaled;
  }
  if (num_scaled > 0) {
    WriteReconstruction(sparse_path, reconstruction,
                        DetectModelFormat(sparse_path));
  }
  return num_scaled;
}

}  // namespace colmap_lidar
