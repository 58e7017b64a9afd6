// COLMAP 3.8 camera models (base/camera_models.h): the same ids, names,
// parameter orders and distortion formulas, so that cameras read from a
// COLMAP database or model project exactly as colmap projects them.
//
// Each model is a struct with static members:
//   kModelId, kModelName, kNumParams, kParamsInfo,
//   kFocalLengthIdxs, kPrincipalPointIdxs, kExtraParamsIdxs,
//   ImgFromCam<T>(params, u, v, w, &x, &y): a point (u, v, w) in the camera
//     frame (x right, y down, z forward) to a pixel. Only w > 0 is meaningful;
//     the point is divided by w first (COLMAP 3.8's WorldToImage on u/w, v/w).
//   CamFromImg<T>(params, x, y, &u, &v, &w): a pixel to the ray (u, v, 1) in
//     the camera frame, undistorting (iteratively where COLMAP does).
// Pixels use COLMAP's SfM convention: the centre of the upper-left pixel is
// (0.5, 0.5), and x = fx * u_distorted + cx.
//
// ImgFromCam is templated so that Ceres Jets can be used in cost functors:
// the maths calls sqrt/atan/tan/... unqualified after `using std::...`, so
// ceres' Jet overloads are found by argument-dependent lookup without this
// header depending on Ceres.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

enum class CameraModelId : int {
  kInvalid = -1,
  kSimplePinhole = 0,
  kPinhole = 1,
  kSimpleRadial = 2,
  kRadial = 3,
  kOpenCV = 4,
  kOpenCVFisheye = 5,
  kFullOpenCV = 6,
  kFOV = 7,
  kSimpleRadialFisheye = 8,
  kRadialFisheye = 9,
  kThinPrismFisheye = 10,
};

// True for the ids 0..10 above.
bool ExistsCameraModelWithId(int model_id);
// Upper-case COLMAP name ("PINHOLE") -> id; kInvalid for an unknown name.
CameraModelId CameraModelNameToId(const std::string& model_name);
// Id -> COLMAP name; "INVALID" for an unknown id.
std::string CameraModelIdToName(CameraModelId model_id);
// Number of parameters; -1 for an unknown id.
int CameraModelNumParams(CameraModelId model_id);
// Human-readable parameter order, e.g. "fx, fy, cx, cy"; empty if unknown.
std::string CameraModelParamsInfo(CameraModelId model_id);
// Indices into the parameter vector; empty for an unknown id.
std::vector<size_t> CameraModelFocalLengthIdxs(CameraModelId model_id);
std::vector<size_t> CameraModelPrincipalPointIdxs(CameraModelId model_id);
std::vector<size_t> CameraModelExtraParamsIdxs(CameraModelId model_id);
// All known model ids, in id order.
std::vector<CameraModelId> AllCameraModelIds();

// Runtime dispatch over the model structs: calls visitor(ModelStruct{}) for
// the model with this id and returns its result. Throws colmap_lidar::Error
// for an unknown id. Example:
//   VisitCameraModel(id, [&](auto model) {
//     using Model = decltype(model);
//     Model::ImgFromCam(params, u, v, w, &x, &y);
//   });
template <typename Visitor>
decltype(auto) VisitCameraModel(CameraModelId model_id, Visitor&& visitor);

// Pixel <-> camera frame for a runtime model id; params must hold
// CameraModelNumParams(model_id) values (not checked here; Camera::Check does).
void CameraModelImgFromCam(CameraModelId model_id, const double* params,
                           double u, double v, double w, double* x, double* y);
void CameraModelCamFromImg(CameraModelId model_id, const double* params,
                           double x, double y, double* u, double* v, double* w);

namespace internal {

// Solves u_d = u + du(u) for u with Newton's method and a central-difference
// Jacobian, as COLMAP's IterativeUndistortion does: `distortion(u, v, &du,
// &dv)` is the model's additive distortion on normalised coordinates. On
// input (*u, *v) is the distorted point, on output the undistorted one.
template <typename T, typename DistortionFn>
void IterativeUndistortion(const DistortionFn& distortion, T* u, T* v) {
  using std::abs;
  // Enough for every model and reasonable distortion; Newton converges
  // quadratically, so the cap only matters for a diverging (invalid) camera.
  constexpr int kMaxNumIterations = 100;
  constexpr double kMaxStepSquaredNorm = 1e-28;
  constexpr double kRelStepSize = 1e-6;
  const T x0 = *u;
  const T y0 = *v;
  T x = *u;
  T y = *v;
  for (int iteration = 0; iteration < kMaxNumIterations; ++iteration) {
    const T step_x = std::max(T(std::numeric_limits<double>::epsilon()),
                              T(abs(kRelStepSize * x)));
    const T step_y = std::max(T(std::numeric_limits<double>::epsilon()),
                              T(abs(kRelStepSize * y)));
    T dx, dy, dx_xb, dy_xb, dx_xf, dy_xf, dx_yb, dy_yb, dx_yf, dy_yf;
    distortion(x, y, &dx, &dy);
    distortion(x - step_x, y, &dx_xb, &dy_xb);
    distortion(x + step_x, y, &dx_xf, &dy_xf);
    distortion(x, y - step_y, &dx_yb, &dy_yb);
    distortion(x, y + step_y, &dx_yf, &dy_yf);
    // J = d(u + du(u)) / du.
    const T j00 = T(1) + (dx_xf - dx_xb) / (T(2) * step_x);
    const T j01 = (dx_yf - dx_yb) / (T(2) * step_y);
    const T j10 = (dy_xf - dy_xb) / (T(2) * step_x);
    const T j11 = T(1) + (dy_yf - dy_yb) / (T(2) * step_y);
    const T residual_x = x + dx - x0;
    const T residual_y = y + dy - y0;
    const T det = j00 * j11 - j01 * j10;
    if (!(abs(det) > T(0))) {
      break;
    }
    const T delta_x = (j11 * residual_x - j01 * residual_y) / det;
    const T delta_y = (-j10 * residual_x + j00 * residual_y) / det;
    x -= delta_x;
    y -= delta_y;
    if (delta_x * delta_x + delta_y * delta_y < T(kMaxStepSquaredNorm)) {
      break;
    }
  }
  *u = x;
  *v = y;
}

// Equidistant fisheye helpers shared by the fisheye models: for r = |(u, v)|
// the ray angle is theta = atan(r); models distort theta and place the point
// at radius theta_d along the same direction.
template <typename T>
bool FisheyeRadius(T u, T v, T* r) {
  using std::sqrt;
  *r = sqrt(u * u + v * v);
  return *r > T(std::numeric_limits<double>::epsilon());
}

}  // namespace internal

////////////////////////////////////////////////////////////////////////////////
// Models without distortion.
////////////////////////////////////////////////////////////////////////////////

// f, cx, cy.
struct SimplePinholeCameraModel {
  static constexpr CameraModelId kModelId = CameraModelId::kSimplePinhole;
  static constexpr const char* kModelName = "SIMPLE_PINHOLE";
  static constexpr int kNumParams = 3;
  static constexpr const char* kParamsInfo = "f, cx, cy";
  static constexpr std::array<size_t, 1> kFocalLengthIdxs = {0};
  static constexpr std::array<size_t, 2> kPrincipalPointIdxs = {1, 2};
  static constexpr std::array<size_t, 0> kExtraParamsIdxs = {};

  template <typename T>
  static void ImgFromCam(const T* params, T u, T v, T w, T* x, T* y) {
    *x = params[0] * (u / w) + params[1];
    *y = params[0] * (v / w) + params[2];
  }
  template <typename T>
  static void CamFromImg(const T* params, T x, T y, T* u, T* v, T* w) {
    *u = (x - params[1]) / params[0];
    *v = (y - params[2]) / params[0];
    *w = T(1);
  }
};

// fx, fy, cx, cy.
struct PinholeCameraModel {
  static constexpr CameraModelId kModelId = CameraModelId::kPinhole;
  static constexpr const char* kModelName = "PINHOLE";
  static constexpr int kNumParams = 4;
  static constexpr const char* kParamsInfo = "fx, fy, cx, cy";
  static constexpr std::array<size_t, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<size_t, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<size_t, 0> kExtraParamsIdxs = {};

  template <typename T>
  static void ImgFromCam(const T* params, T u, T v, T w, T* x, T* y) {
    *x = params[0] * (u / w) + params[2];
    *y = params[1] * (v / w) + params[3];
  }
  template <typename T>
  static void CamFromImg(const T* params, T x, T y, T* u, T* v, T* w) {
    *u = (x - params[2]) / params[0];
    *v = (y - params[3]) / params[1];
    *w = T(1);
  }
};

////////////////////////////////////////////////////////////////////////////////
// Models with additive distortion u_d = u + du(u, v): projection applies the
// distortion, unprojection inverts it with internal::IterativeUndistortion.
// `Base` provides ImgFromCam/CamFromImg from Model::Distortion and the focal
// and principal point layout (one shared focal length or fx, fy).
////////////////////////////////////////////////////////////////////////////////

namespace internal {

template <typename Model, bool kSharedFocal>
struct DistortedCameraModelBase {
  // Number of focal + principal point parameters before the extra ones.
  static constexpr int kNumIntrinsics = kSharedFocal ? 3 : 4;

  template <typename T>
  static void ImgFromCam(const T* params, T u, T v, T w, T* x, T* y) {
    const T uu = u / w;
    const T vv = v / w;
    T du, dv;
    Model::Distortion(params + kNumIntrinsics, uu, vv, &du, &dv);
    if constexpr (kSharedFocal) {
      *x = params[0] * (uu + du) + params[1];
      *y = params[0] * (vv + dv) + params[2];
    } else {
      *x = params[0] * (uu + du) + params[2];
      *y = params[1] * (vv + dv) + params[3];
    }
  }

  template <typename T>
  static void CamFromImg(const T* params, T x, T y, T* u, T* v, T* w) {
    if constexpr (kSharedFocal) {
      *u = (x - params[1]) / params[0];
      *v = (y - params[2]) / params[0];
    } else {
      *u = (x - params[2]) / params[0];
      *v = (y - params[3]) / params[1];
    }
    const T* extra_params = params + kNumIntrinsics;
    IterativeUndistortion(
        [extra_params](T uu, T vv, T* du, T* dv) {
          Model::Distortion(extra_params, uu, vv, du, dv);
        },
        u, v);
    *w = T(1);
  }
};

}  // namespace internal

// f, cx, cy, k: du = u * k * r^2.
struct SimpleRadialCameraModel
    : internal::DistortedCameraModelBase<SimpleRadialCameraModel, true> {
  static constexpr CameraModelId kModelId = CameraModelId::kSimpleRadial;
  static constexpr const char* kModelName = "SIMPLE_RADIAL";
  static constexpr int kNumParams = 4;
  static constexpr const char* kParamsInfo = "f, cx, cy, k";
  static constexpr std::array<size_t, 1> kFocalLengthIdxs = {0};
  static constexpr std::array<size_t, 2> kPrincipalPointIdxs = {1, 2};
  static constexpr std::array<size_t, 1> kExtraParamsIdxs = {3};

  template <typename T>
  static void Distortion(const T* extra, T u, T v, T* du, T* dv) {
    const T radial = extra[0] * (u * u + v * v);
    *du = u * radial;
    *dv = v * radial;
  }
};

// f, cx, cy, k1, k2: du = u * (k1 r^2 + k2 r^4).
struct RadialCameraModel
    : internal::DistortedCameraModelBase<RadialCameraModel, true> {
  static constexpr CameraModelId kModelId = CameraModelId::kRadial;
  static constexpr const char* kModelName = "RADIAL";
  static constexpr int kNumParams = 5;
  static constexpr const char* kParamsInfo = "f, cx, cy, k1, k2";
  static constexpr std::array<size_t, 1> kFocalLengthIdxs = {0};
  static constexpr std::array<size_t, 2> kPrincipalPointIdxs = {1, 2};
  static constexpr std::array<size_t, 2> kExtraParamsIdxs = {3, 4};

  template <typename T>
  static void Distortion(const T* extra, T u, T v, T* du, T* dv) {
    const T r2 = u * u + v * v;
    const T radial = extra[0] * r2 + extra[1] * r2 * r2;
    *du = u * radial;
    *dv = v * radial;
  }
};

// fx, fy, cx, cy, k1, k2, p1, p2: OpenCV's radial + tangential model.
struct OpenCVCameraModel
    : internal::DistortedCameraModelBase<OpenCVCameraModel, false> {
  static constexpr CameraModelId kModelId = CameraModelId::kOpenCV;
  static constexpr const char* kModelName = "OPENCV";
  static constexpr int kNumParams = 8;
  static constexpr const char* kParamsInfo = "fx, fy, cx, cy, k1, k2, p1, p2";
  static constexpr std::array<size_t, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<size_t, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<size_t, 4> kExtraParamsIdxs = {4, 5, 6, 7};

  template <typename T>
  static void Distortion(const T* extra, T u, T v, T* du, T* dv) {
    const T k1 = extra[0];
    const T k2 = extra[1];
    const T p1 = extra[2];
    const T p2 = extra[3];
    const T u2 = u * u;
    const T v2 = v * v;
    const T uv = u * v;
    const T r2 = u2 + v2;
    const T radial = k1 * r2 + k2 * r2 * r2;
    *du = u * radial + T(2) * p1 * uv + p2 * (r2 + T(2) * u2);
    *dv = v * radial + T(2) * p2 * uv + p1 * (r2 + T(2) * v2);
  }
};

// fx, fy, cx, cy, k1, k2, k3, k4: OpenCV's fisheye (equidistant) model,
// theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8).
struct OpenCVFisheyeCameraModel
    : internal::DistortedCameraModelBase<OpenCVFisheyeCameraModel, false> {
  static constexpr CameraModelId kModelId = CameraModelId::kOpenCVFisheye;
  static constexpr const char* kModelName = "OPENCV_FISHEYE";
  static constexpr int kNumParams = 8;
  static constexpr const char* kParamsInfo = "fx, fy, cx, cy, k1, k2, k3, k4";
  static constexpr std::array<size_t, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<size_t, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<size_t, 4> kExtraParamsIdxs = {4, 5, 6, 7};

  template <typename T>
  static void Distortion(const T* extra, T u, T v, T* du, T* dv) {
    using std::atan;
    T r;
    if (!internal::FisheyeRadius(u, v, &r)) {
      *du = T(0);
      *dv = T(0);
      return;
    }
    const T theta = atan(r);
    const T theta2 = theta * theta;
    const T theta4 = theta2 * theta2;
    const T theta6 = theta4 * theta2;
    const T theta8 = theta4 * theta4;
    const T theta_d = theta * (T(1) + extra[0] * theta2 + extra[1] * theta4 +
                               extra[2] * theta6 + extra[3] * theta8);
    *du = u * theta_d / r - u;
    *dv = v * theta_d / r - v;
  }
};

// fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6: OpenCV's rational model,
// radial = (1 + k1 r^2 + k2 r^4 + k3 r^6) / (1 + k4 r^2 + k5 r^4 + k6 r^6).
struct FullOpenCVCameraModel
    : internal::DistortedCameraModelBase<FullOpenCVCameraModel, false> {
  static constexpr CameraModelId kModelId = CameraModelId::kFullOpenCV;
  static constexpr const char* kModelName = "FULL_OPENCV";
  static constexpr int kNumParams = 12;
  static constexpr const char* kParamsInfo =
      "fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6";
  static constexpr std::array<size_t, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<size_t, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<size_t, 8> kExtraParamsIdxs = {4, 5, 6,  7,
                                                             8, 9, 10, 11};

  template <typename T>
  static void Distortion(const T* extra, T u, T v, T* du, T* dv) {
    const T k1 = extra[0];
    const T k2 = extra[1];
    const T p1 = extra[2];
    const T p2 = extra[3];
    const T k3 = extra[4];
    const T k4 = extra[5];
    const T k5 = extra[6];
    const T k6 = extra[7];
    const T u2 = u * u;
    const T v2 = v * v;
    const T uv = u * v;
    const T r2 = u2 + v2;
    const T r4 = r2 * r2;
    const T r6 = r4 * r2;
    const T radial = (T(1) + k1 * r2 + k2 * r4 + k3 * r6) /
                     (T(1) + k4 * r2 + k5 * r4 + k6 * r6);
    *du = u * radial + T(2) * p1 * uv + p2 * (r2 + T(2) * u2) - u;
    *dv = v * radial + T(2) * p2 * uv + p1 * (r2 + T(2) * v2) - v;
  }
};

// fx, fy, cx, cy, omega: Devernay & Faugeras' field-of-view model,
// r_d = atan(2 r tan(omega / 2)) / omega. COLMAP projects and unprojects it
// in closed form; near omega = 0 or r = 0 the second-order Taylor expansions
// of the factors r_d / r and r / r_d are used.
struct FOVCameraModel {
  static constexpr CameraModelId kModelId = CameraModelId::kFOV;
  static constexpr const char* kModelName = "FOV";
  static constexpr int kNumParams = 5;
  static constexpr const char* kParamsInfo = "fx, fy, cx, cy, omega";
  static constexpr std::array<size_t, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<size_t, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<size_t, 1> kExtraParamsIdxs = {4};

  // Below this, omega^2 or r^2 switch to the Taylor expansions.
  static constexpr double kEpsilon = 1e-4;

  // Distorted normalised coordinates (not an offset).
  template <typename T>
  static void Distort(T omega, T u, T v, T* ud, T* vd) {
    using std::atan;
    using std::sqrt;
    using std::tan;
    const T r2 = u * u + v * v;
    const T omega2 = omega * omega;
    T factor;
    if (omega2 < T(kEpsilon)) {
      // atan(2 r tan(w/2)) / (r w) = 1 + w^2 / 12 - r^2 w^2 / 3 + O(w^4).
      factor = T(1) + omega2 / T(12) - omega2 * r2 / T(3);
    } else if (r2 < T(kEpsilon)) {
      // With t = tan(w/2): 2t/w (1 - 4 r^2 t^2 / 3) + O(r^4).
      const T t = tan(omega / T(2));
      factor = T(2) * t / omega * (T(1) - T(4) * r2 * t * t / T(3));
    } else {
      const T r = sqrt(r2);
      factor = atan(r * T(2) * tan(omega / T(2))) / (r * omega);
    }
    *ud = u * factor;
    *vd = v * factor;
  }

  // Inverse of Distort.
  template <typename T>
  static void Undistort(T omega, T ud, T vd, T* u, T* v) {
    using std::sqrt;
    using std::tan;
    const T r2 = ud * ud + vd * vd;
    const T omega2 = omega * omega;
    T factor;
    if (omega2 < T(kEpsilon)) {
      // tan(r w) / (2 r tan(w/2)) = 1 - w^2 / 12 + r^2 w^2 / 3 + O(w^4).
      factor = T(1) - omega2 / T(12) + omega2 * r2 / T(3);
    } else if (r2 < T(kEpsilon)) {
      // w (3 + w^2 r^2) / (6 tan(w/2)) + O(r^4).
      factor = omega * (T(3) + omega2 * r2) / (T(6) * tan(omega / T(2)));
    } else {
      const T r = sqrt(r2);
      factor = tan(r * omega) / (r * T(2) * tan(omega / T(2)));
    }
    *u = ud * factor;
    *v = vd * factor;
  }

  template <typename T>
  static void ImgFromCam(const T* params, T u, T v, T w, T* x, T* y) {
    T ud, vd;
    Distort(params[4], u / w, v / w, &ud, &vd);
    *x = params[0] * ud + params[2];
    *y = params[1] * vd + params[3];
  }
  template <typename T>
  static void CamFromImg(const T* params, T x, T y, T* u, T* v, T* w) {
    Undistort(params[4], (x - params[2]) / params[0],
              (y - params[3]) / params[1], u, v);
    *w = T(1);
  }
};

// f, cx, cy, k: theta_d = theta (1 + k theta^2).
struct SimpleRadialFisheyeCameraModel
    : internal::DistortedCameraModelBase<SimpleRadialFisheyeCameraModel, true> {
  static constexpr CameraModelId kModelId = CameraModelId::kSimpleRadialFisheye;
  static constexpr const char* kModelName = "SIMPLE_RADIAL_FISHEYE";
  static constexpr int kNumParams = 4;
  static constexpr const char* kParamsInfo = "f, cx, cy, k";
  static constexpr std::array<size_t, 1> kFocalLengthIdxs = {0};
  static constexpr std::array<size_t, 2> kPrincipalPointIdxs = {1, 2};
  static constexpr std::array<size_t, 1> kExtraParamsIdxs = {3};

  template <typename T>
  static void Distortion(const T* extra, T u, T v, T* du, T* dv) {
    using std::atan;
    T r;
    if (!internal::FisheyeRadius(u, v, &r)) {
      *du = T(0);
      *dv = T(0);
      return;
    }
    const T theta = atan(r);
    const T theta_d = theta * (T(1) + extra[0] * theta * theta);
    *du = u * theta_d / r - u;
    *dv = v * theta_d / r - v;
  }
};

// f, cx, cy, k1, k2: theta_d = theta (1 + k1 theta^2 + k2 theta^4).
struct RadialFisheyeCameraModel
    : internal::DistortedCameraModelBase<RadialFisheyeCameraModel, true> {
  static constexpr CameraModelId kModelId = CameraModelId::kRadialFisheye;
  static constexpr const char* kModelName = "RADIAL_FISHEYE";
  static constexpr int kNumParams = 5;
  static constexpr const char* kParamsInfo = "f, cx, cy, k1, k2";
  static constexpr std::array<size_t, 1> kFocalLengthIdxs = {0};
  static constexpr std::array<size_t, 2> kPrincipalPointIdxs = {1, 2};
  static constexpr std::array<size_t, 2> kExtraParamsIdxs = {3, 4};

  template <typename T>
  static void Distortion(const T* extra, T u, T v, T* du, T* dv) {
    using std::atan;
    T r;
    if (!internal::FisheyeRadius(u, v, &r)) {
      *du = T(0);
      *dv = T(0);
      return;
    }
    const T theta = atan(r);
    const T theta2 = theta * theta;
    const T theta_d =
        theta * (T(1) + extra[0] * theta2 + extra[1] * theta2 * theta2);
    *du = u * theta_d / r - u;
    *dv = v * theta_d / r - v;
  }
};

// fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, sx1, sy1: the ETH3D thin-prism
// fisheye model. The point is first mapped to the equidistant fisheye plane
// (radius theta = atan(r)), then radial (in theta^2), tangential and
// thin-prism terms are added there.
struct ThinPrismFisheyeCameraModel {
  static constexpr CameraModelId kModelId = CameraModelId::kThinPrismFisheye;
  static constexpr const char* kModelName = "THIN_PRISM_FISHEYE";
  static constexpr int kNumParams = 12;
  static constexpr const char* kParamsInfo =
      "fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, sx1, sy1";
  static constexpr std::array<size_t, 2> kFocalLengthIdxs = {0, 1};
  static constexpr std::array<size_t, 2> kPrincipalPointIdxs = {2, 3};
  static constexpr std::array<size_t, 8> kExtraParamsIdxs = {4, 5, 6,  7,
                                                             8, 9, 10, 11};

  // Additive distortion on the fisheye plane.
  template <typename T>
  static void Distortion(const T* extra, T u, T v, T* du, T* dv) {
    const T k1 = extra[0];
    const T k2 = extra[1];
    const T p1 = extra[2];
    const T p2 = extra[3];
    const T k3 = extra[4];
    const T k4 = extra[5];
    const T sx1 = extra[6];
    const T sy1 = extra[7];
    const T u2 = u * u;
    const T v2 = v * v;
    const T uv = u * v;
    const T r2 = u2 + v2;
    const T r4 = r2 * r2;
    const T r6 = r4 * r2;
    const T r8 = r4 * r4;
    const T radial = k1 * r2 + k2 * r4 + k3 * r6 + k4 * r8;
    *du = u * radial + T(2) * p1 * uv + p2 * (r2 + T(2) * u2) + sx1 * r2;
    *dv = v * radial + T(2) * p2 * uv + p1 * (r2 + T(2) * v2) + sy1 * r2;
  }

  template <typename T>
  static void ImgFromCam(const T* params, T u, T v, T w, T* x, T* y) {
    using std::atan;
    const T uu = u / w;
    const T vv = v / w;
    T r;
    T fu = uu;
    T fv = vv;
    if (internal::FisheyeRadius(uu, vv, &r)) {
      const T theta = atan(r);
      fu = theta * uu / r;
      fv = theta * vv / r;
    }
    T du, dv;
    Distortion(params + 4, fu, fv, &du, &dv);
    *x = params[0] * (fu + du) + params[2];
    *y = params[1] * (fv + dv) + params[3];
  }

  template <typename T>
  static void CamFromImg(const T* params, T x, T y, T* u, T* v, T* w) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    *u = (x - params[2]) / params[0];
    *v = (y - params[3]) / params[1];
    const T* extra = params + 4;
    internal::IterativeUndistortion(
        [extra](T uu, T vv, T* du, T* dv) {
          Distortion(extra, uu, vv, du, dv);
        },
        u, v);
    // (u, v) is now on the fisheye plane with radius theta: back to
    // tan(theta) along the same direction.
    const T theta = sqrt(*u * *u + *v * *v);
    const T theta_cos_theta = theta * cos(theta);
    if (theta_cos_theta > T(std::numeric_limits<double>::epsilon())) {
      const T scale = sin(theta) / theta_cos_theta;
      *u *= scale;
      *v *= scale;
    }
    *w = T(1);
  }
};

////////////////////////////////////////////////////////////////////////////////
// Dispatch.
////////////////////////////////////////////////////////////////////////////////

// The list of all models, for code that loops over them at compile time.
#define COLMAP_LIDAR_CAMERA_MODEL_CASES                          \
  COLMAP_LIDAR_CAMERA_MODEL_CASE(SimplePinholeCameraModel)       \
  COLMAP_LIDAR_CAMERA_MODEL_CASE(PinholeCameraModel)             \
  COLMAP_LIDAR_CAMERA_MODEL_CASE(SimpleRadialCameraModel)        \
  COLMAP_LIDAR_CAMERA_MODEL_CASE(RadialCameraModel)              \
  COLMAP_LIDAR_CAMERA_MODEL_CASE(OpenCVCameraModel)              \
  COLMAP_LIDAR_CAMERA_MODEL_CASE(OpenCVFisheyeCameraModel)       \
  COLMAP_LIDAR_CAMERA_MODEL_CASE(FullOpenCVCameraModel)          \
  COLMAP_LIDAR_CAMERA_MODEL_CASE(FOVCameraModel)                 \
  COLMAP_LIDAR_CAMERA_MODEL_CASE(SimpleRadialFisheyeCameraModel) \
  COLMAP_LIDAR_CAMERA_MODEL_CASE(RadialFisheyeCameraModel)       \
  COLMAP_LIDAR_CAMERA_MODEL_CASE(ThinPrismFisheyeCameraModel)

template <typename Visitor>
decltype(auto) VisitCameraModel(CameraModelId model_id, Visitor&& visitor) {
  switch (model_id) {
#define COLMAP_LIDAR_CAMERA_MODEL_CASE(Model) \
  case Model::kModelId:                       \
    return std::forward<Visitor>(visitor)(Model{});
    COLMAP_LIDAR_CAMERA_MODEL_CASES
#undef COLMAP_LIDAR_CAMERA_MODEL_CASE
    default:
      break;
  }
  THROW_ERROR("Unknown camera model id " << static_cast<int>(model_id));
}

}  // namespace colmap_lidar
