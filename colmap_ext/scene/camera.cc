#include "colmap_ext/scene/camera.h"

#include <cmath>
#include <sstream>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Empty when the camera is valid, otherwise the first problem found.
std::string InvalidReason(const Camera& camera) {
  std::ostringstream reason;
  const int num_params = CameraModelNumParams(camera.model_id);
  if (num_params < 0) {
    reason << "unknown camera model id " << static_cast<int>(camera.model_id);
  } else if (static_cast<int>(camera.params.size()) != num_params) {
    reason << "camera model " << CameraModelIdToName(camera.model_id)
           << " expects " << num_params << " parameters ("
           << CameraModelParamsInfo(camera.model_id) << "), got "
           << camera.params.size();
  } else if (camera.width == 0 || camera.height == 0) {
    reason << "image size " << camera.width << "x" << camera.height
           << " is empty";
  } else {
    for (size_t i = 0; i < camera.params.size(); ++i) {
      if (!std::isfinite(camera.params[i])) {
        reason << "parameter " << i << " is not finite (" << camera.params[i]
               << ")";
        break;
      }
    }
  }
  return reason.str();
}

}  // namespace

Camera Camera::FromModelName(const std::string& model_name, uint64_t width,
                             uint64_t height,
                             const std::vector<double>& params) {
  const CameraModelId model_id = CameraModelNameToId(model_name);
  THROW_CHECK(model_id != CameraModelId::kInvalid,
              "Unknown camera model name '" << model_name << "'");
  const int num_params = CameraModelNumParams(model_id);
  THROW_CHECK(static_cast<int>(params.size()) == num_params,
              "Camera model " << model_name << " expects " << num_params
                              << " parameters ("
                              << CameraModelParamsInfo(model_id) << "), got "
                              << params.size());
  Camera camera;
  camera.model_id = model_id;
  camera.width = width;
  camera.height = height;
  camera.params = params;
  return camera;
}

std::string Camera::ModelName() const { return CameraModelIdToName(model_id); }

bool Camera::IsValid() const { return InvalidReason(*this).empty(); }

void Camera::Check() const {
  const std::string reason = InvalidReason(*this);
  THROW_CHECK(reason.empty(), "Invalid camera " << camera_id << ": " << reason);
}

double Camera::MeanFocalLength() const {
  Check();
  const std::vector<size_t> idxs = CameraModelFocalLengthIdxs(model_id);
  double sum = 0.0;
  for (const size_t idx : idxs) {
    sum += params[idx];
  }
  return sum / static_cast<double>(idxs.size());
}

Eigen::Matrix3d Camera::CalibrationMatrix() const {
  Check();
  const std::vector<size_t> focal_idxs = CameraModelFocalLengthIdxs(model_id);
  const std::vector<size_t> pp_idxs = CameraModelPrincipalPointIdxs(model_id);
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = params[focal_idxs.front()];
  K(1, 1) = params[focal_idxs.back()];
  K(0, 2) = params[pp_idxs[0]];
  K(1, 2) = params[pp_idxs[1]];
  return K;
}

Eigen::Vector2d Camera::ImgFromCam(const Eigen::Vector3d& point_in_cam) const {
  THROW_CHECK(static_cast<int>(params.size()) == CameraModelNumParams(model_id),
              "Invalid camera " << camera_id << " for projection");
  Eigen::Vector2d pixel;
  CameraModelImgFromCam(model_id, params.data(), point_in_cam.x(),
                        point_in_cam.y(), point_in_cam.z(), &pixel.x(),
                        &pixel.y());
  return pixel;
}

Eigen::Vector2d Camera::CamFromImg(const Eigen::Vector2d& pixel) const {
  THROW_CHECK(static_cast<int>(params.size()) == CameraModelNumParams(model_id),
              "Invalid camera " << camera_id << " for unprojection");
  double u, v, w;
  CameraModelCamFromImg(model_id, params.data(), pixel.x(), pixel.y(), &u, &v,
                        &w);
  return Eigen::Vector2d(u / w, v / w);
}

}  // namespace colmap_lidar
