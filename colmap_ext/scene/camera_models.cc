#include "colmap_ext/scene/camera_models.h"

namespace colmap_lidar {
namespace {

template <size_t N>
std::vector<size_t> ToVector(const std::array<size_t, N>& idxs) {
  return std::vector<size_t>(idxs.begin(), idxs.end());
}

}  // namespace

bool ExistsCameraModelWithId(int model_id) {
  switch (static_cast<CameraModelId>(model_id)) {
#define COLMAP_LIDAR_CAMERA_MODEL_CASE(Model) case Model::kModelId:
    COLMAP_LIDAR_CAMERA_MODEL_CASES
#undef COLMAP_LIDAR_CAMERA_MODEL_CASE
    return true;
    default:
      return false;
  }
}

CameraModelId CameraModelNameToId(const std::string& model_name) {
#define COLMAP_LIDAR_CAMERA_MODEL_CASE(Model) \
  if (model_name == Model::kModelName) {      \
    return Model::kModelId;                   \
  }
  COLMAP_LIDAR_CAMERA_MODEL_CASES
#undef COLMAP_LIDAR_CAMERA_MODEL_CASE
  return CameraModelId::kInvalid;
}

std::string CameraModelIdToName(CameraModelId model_id) {
  if (!ExistsCameraModelWithId(static_cast<int>(model_id))) {
    return "INVALID";
  }
  return VisitCameraModel(model_id, [](auto model) {
    return std::string(decltype(model)::kModelName);
  });
}

int CameraModelNumParams(CameraModelId model_id) {
  if (!ExistsCameraModelWithId(static_cast<int>(model_id))) {
    return -1;
  }
  return VisitCameraModel(
      model_id, [](auto model) { return decltype(model)::kNumParams; });
}

std::string CameraModelParamsInfo(CameraModelId model_id) {
  if (!ExistsCameraModelWithId(static_cast<int>(model_id))) {
    return "";
  }
  return VisitCameraModel(model_id, [](auto model) {
    return std::string(decltype(model)::kParamsInfo);
  });
}

std::vector<size_t> CameraModelFocalLengthIdxs(CameraModelId model_id) {
  if (!ExistsCameraModelWithId(static_cast<int>(model_id))) {
    return {};
  }
  return VisitCameraModel(model_id, [](auto model) {
    return ToVector(decltype(model)::kFocalLengthIdxs);
  });
}

std::vector<size_t> CameraModelPrincipalPointIdxs(CameraModelId model_id) {
  if (!ExistsCameraModelWithId(static_cast<int>(model_id))) {
    return {};
  }
  return VisitCameraModel(model_id, [](auto model) {
    return ToVector(decltype(model)::kPrincipalPointIdxs);
  });
}

std::vector<size_t> CameraModelExtraParamsIdxs(CameraModelId model_id) {
  if (!ExistsCameraModelWithId(static_cast<int>(model_id))) {
    return {};
  }
  return VisitCameraModel(model_id, [](auto model) {
    return ToVector(decltype(model)::kExtraParamsIdxs);
  });
}

std::vector<CameraModelId> AllCameraModelIds() {
  return {
#define COLMAP_LIDAR_CAMERA_MODEL_CASE(Model) Model::kModelId,
      COLMAP_LIDAR_CAMERA_MODEL_CASES
#undef COLMAP_LIDAR_CAMERA_MODEL_CASE
  };
}

void CameraModelImgFromCam(CameraModelId model_id, const double* params,
                           double u, double v, double w, double* x, double* y) {
  VisitCameraModel(model_id, [&](auto model) {
    decltype(model)::ImgFromCam(params, u, v, w, x, y);
  });
}

void CameraModelCamFromImg(CameraModelId model_id, const double* params,
                           double x, double y, double* u, double* v,
                           double* w) {
  VisitCameraModel(model_id, [&](auto model) {
    decltype(model)::CamFromImg(params, x, y, u, v, w);
  });
}

}  // namespace colmap_lidar
