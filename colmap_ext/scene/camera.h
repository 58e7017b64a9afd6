// A camera of a COLMAP model or database: a model id from camera_models.h,
// the image size and the parameters in COLMAP's order for that model.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/camera_models.h"
#include "colmap_ext/util/types.h"

namespace colmap_lidar {

struct Camera {
  camera_t camera_id = kInvalidCameraId;
  CameraModelId model_id = CameraModelId::kInvalid;
  uint64_t width = 0;
  uint64_t height = 0;
  std::vector<double> params;
  // COLMAP's prior_focal_length: the focal length is trusted.
  bool has_prior_focal_length = false;

  // Builds a camera; throws colmap_lidar::Error on an unknown model name or a
  // wrong number of parameters (naming the model and the counts).
  static Camera FromModelName(const std::string& model_name, uint64_t width,
                              uint64_t height,
                              const std::vector<double>& params);

  std::string ModelName() const;
  // True when the model id is known, the parameter count matches, all
  // parameters are finite and width, height > 0.
  bool IsValid() const;
  // Throws colmap_lidar::Error with the reason when !IsValid().
  void Check() const;

  double MeanFocalLength() const;
  // fx, fy, cx, cy as a 3x3 matrix (ignoring distortion).
  Eigen::Matrix3d CalibrationMatrix() const;

  // Point in the camera frame -> pixel (COLMAP's SfM convention: the centre
  // of the upper-left pixel is (0.5, 0.5)). Undefined for z <= 0.
  Eigen::Vector2d ImgFromCam(const Eigen::Vector3d& point_in_cam) const;
  // Pixel -> normalised image coordinates (x/z, y/z) after undistortion.
  Eigen::Vector2d CamFromImg(const Eigen::Vector2d& pixel) const;
};

}  // namespace colmap_lidar
