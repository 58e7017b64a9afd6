#include "colmap_ext/scene/camera_models.h"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace colmap_lidar {
namespace {

// Parameters with realistic, invertible distortion for a 640x480 image.
std::vector<double> TestParams(CameraModelId model_id) {
  switch (model_id) {
    case CameraModelId::kSimplePinhole:
      return {500, 320, 240};
    case CameraModelId::kPinhole:
      return {500, 520, 320, 240};
    case CameraModelId::kSimpleRadial:
      return {500, 320, 240, -0.05};
    case CameraModelId::kRadial:
      return {500, 320, 240, -0.05, 0.01};
    case CameraModelId::kOpenCV:
      return {500, 520, 320, 240, -0.05, 0.01, 0.001, -0.002};
    case CameraModelId::kOpenCVFisheye:
      return {300, 310, 320, 240, 0.02, -0.01, 0.003, -0.001};
    case CameraModelId::kFullOpenCV:
      return {500,   520,    320,   240,  -0.05,  0.01,
              0.001, -0.002, 0.001, 0.02, -0.003, 0.0005};
    case CameraModelId::kFOV:
      return {500, 520, 320, 240, 0.6};
    case CameraModelId::kSimpleRadialFisheye:
      return {300, 320, 240, 0.02};
    case CameraModelId::kRadialFisheye:
      return {300, 320, 240, 0.02, -0.005};
    case CameraModelId::kThinPrismFisheye:
      return {300,   310,    320,   240,    0.02,   -0.01,
              0.001, -0.002, 0.003, -0.001, 0.0005, -0.0004};
    default:
      return {};
  }
}

TEST(CameraModels, NameIdNumParamsTable) {
  struct Row {
    int id;
    const char* name;
    int num_params;
    std::vector<size_t> focal;
    std::vector<size_t> principal_point;
  };
  const std::vector<Row> rows = {
      {0, "SIMPLE_PINHOLE", 3, {0}, {1, 2}},
      {1, "PINHOLE", 4, {0, 1}, {2, 3}},
      {2, "SIMPLE_RADIAL", 4, {0}, {1, 2}},
      {3, "RADIAL", 5, {0}, {1, 2}},
      {4, "OPENCV", 8, {0, 1}, {2, 3}},
      {5, "OPENCV_FISHEYE", 8, {0, 1}, {2, 3}},
      {6, "FULL_OPENCV", 12, {0, 1}, {2, 3}},
      {7, "FOV", 5, {0, 1}, {2, 3}},
      {8, "SIMPLE_RADIAL_FISHEYE", 4, {0}, {1, 2}},
      {9, "RADIAL_FISHEYE", 5, {0}, {1, 2}},
      {10, "THIN_PRISM_FISHEYE", 12, {0, 1}, {2, 3}},
  };
  ASSERT_EQ(AllCameraModelIds().size(), rows.size());
  for (const Row& row : rows) {
    const CameraModelId id = static_cast<CameraModelId>(row.id);
    EXPECT_TRUE(ExistsCameraModelWithId(row.id));
    EXPECT_EQ(CameraModelNameToId(row.name), id);
    EXPECT_EQ(CameraModelIdToName(id), row.name);
    EXPECT_EQ(CameraModelNumParams(id), row.num_params);
    EXPECT_EQ(CameraModelFocalLengthIdxs(id), row.focal);
    EXPECT_EQ(CameraModelPrincipalPointIdxs(id), row.principal_point);
    // Focal, principal point and extra indices partition 0..n-1.
    const size_t num_idxs = CameraModelFocalLengthIdxs(id).size() +
                            CameraModelPrincipalPointIdxs(id).size() +
                            CameraModelExtraParamsIdxs(id).size();
    EXPECT_EQ(static_cast<int>(num_idxs), row.num_params) << row.name;
    EXPECT_EQ(TestParams(id).size(), static_cast<size_t>(row.num_params));
    // The info string lists one name per parameter.
    const std::string info = CameraModelParamsInfo(id);
    EXPECT_EQ(std::count(info.begin(), info.end(), ',') + 1, row.num_params);
  }
  EXPECT_FALSE(ExistsCameraModelWithId(-1));
  EXPECT_FALSE(ExistsCameraModelWithId(11));
  EXPECT_EQ(CameraModelNameToId("pinhole"), CameraModelId::kInvalid);
  EXPECT_EQ(CameraModelNameToId("FISHEYE"), CameraModelId::kInvalid);
  EXPECT_EQ(CameraModelNumParams(CameraModelId::kInvalid), -1);
  EXPECT_EQ(CameraModelIdToName(static_cast<CameraModelId>(42)), "INVALID");
  EXPECT_THROW(VisitCameraModel(CameraModelId::kInvalid, [](auto) {}), Error);
}

TEST(CameraModels, RoundTripOverPixelGrid) {
  for (const CameraModelId id : AllCameraModelIds()) {
    const std::vector<double> params = TestParams(id);
    double max_error = 0;
    for (double x = 0; x <= 640; x += 20) {
      for (double y = 0; y <= 480; y += 20) {
        double u, v, w;
        CameraModelCamFromImg(id, params.data(), x, y, &u, &v, &w);
        ASSERT_EQ(w, 1.0);
        double x2, y2;
        // A scaled ray must project to the same pixel.
        CameraModelImgFromCam(id, params.data(), 3 * u, 3 * v, 3 * w, &x2, &y2);
        max_error = std::max({max_error, std::abs(x2 - x), std::abs(y2 - y)});
      }
    }
    EXPECT_LT(max_error, 1e-8) << CameraModelIdToName(id);
  }
}

TEST(CameraModels, DistortionModelsActuallyDistort) {
  // A corner ray must not project as a pinhole would for the distorted
  // models (guards against a dispatcher that ignores the extra params).
  for (const CameraModelId id : AllCameraModelIds()) {
    if (CameraModelExtraParamsIdxs(id).empty()) {
      continue;
    }
    const std::vector<double> params = TestParams(id);
    const std::vector<size_t> f = CameraModelFocalLengthIdxs(id);
    const std::vector<size_t> c = CameraModelPrincipalPointIdxs(id);
    // Not at r = 0.5, where FOV's distortion is the identity for any omega.
    double x, y;
    CameraModelImgFromCam(id, params.data(), 0.7, 0.3, 1.0, &x, &y);
    const double pinhole_x = params[f.front()] * 0.7 + params[c[0]];
    EXPECT_GT(std::abs(x - pinhole_x), 0.1) << CameraModelIdToName(id);
  }
}

TEST(CameraModels, HandComputedPinhole) {
  const double params[] = {500, 400, 320, 240};
  double x, y;
  PinholeCameraModel::ImgFromCam(params, 1.0, 2.0, 4.0, &x, &y);
  EXPECT_DOUBLE_EQ(x, 445.0);
  EXPECT_DOUBLE_EQ(y, 440.0);
  double u, v, w;
  PinholeCameraModel::CamFromImg(params, 445.0, 440.0, &u, &v, &w);
  EXPECT_DOUBLE_EQ(u, 0.25);
  EXPECT_DOUBLE_EQ(v, 0.5);
  EXPECT_DOUBLE_EQ(w, 1.0);
  // SIMPLE_PINHOLE shares f.
  const double simple_params[] = {100, 50, 60};
  SimplePinholeCameraModel::ImgFromCam(simple_params, 0.5, -0.25, 1.0, &x, &y);
  EXPECT_DOUBLE_EQ(x, 100.0);
  EXPECT_DOUBLE_EQ(y, 35.0);
}

TEST(CameraModels, HandComputedSimpleRadial) {
  // r^2 = 0.2, factor 1 + 0.1 * 0.2 = 1.02.
  const double params[] = {100, 50, 60, 0.1};
  double x, y;
  SimpleRadialCameraModel::ImgFromCam(params, 0.2, 0.4, 1.0, &x, &y);
  EXPECT_NEAR(x, 100 * 0.204 + 50, 1e-12);
  EXPECT_NEAR(y, 100 * 0.408 + 60, 1e-12);
  double u, v, w;
  SimpleRadialCameraModel::CamFromImg(params, x, y, &u, &v, &w);
  EXPECT_NEAR(u, 0.2, 1e-12);
  EXPECT_NEAR(v, 0.4, 1e-12);
}

TEST(CameraModels, HandComputedOpenCV) {
  // u = 0.5, v = -0.25: r^2 = 0.3125, radial = 0.1 r^2 + 0.01 r^4
  // = 0.0322265625; du = 0.01611328125 - 0.00025 + 0.001625,
  // dv = -0.008056640625 - 0.0005 + 0.0004375.
  const double params[] = {200, 300, 10, 20, 0.1, 0.01, 0.001, 0.002};
  double x, y;
  OpenCVCameraModel::ImgFromCam(params, 0.5, -0.25, 1.0, &x, &y);
  EXPECT_NEAR(x, 113.49765625, 1e-10);
  EXPECT_NEAR(y, -57.4357421875, 1e-10);
}

// Projects with OpenCV and with our model; both use x = fx * x_d + cx.
void ExpectMatchesOpenCV(CameraModelId id, const std::vector<double>& params,
                         const std::vector<double>& dist_coeffs, bool fisheye) {
  const cv::Matx33d K(params[0], 0, params[2], 0, params[1], params[3], 0, 0,
                      1);
  std::vector<cv::Point3d> points;
  for (double X = -1.0; X <= 1.0; X += 0.25) {
    for (double Y = -0.75; Y <= 0.75; Y += 0.25) {
      points.emplace_back(X, Y, 1.5 + 0.1 * X);
    }
  }
  std::vector<cv::Point2d> cv_pixels;
  const cv::Vec3d rvec(0, 0, 0);
  const cv::Vec3d tvec(0, 0, 0);
  if (fisheye) {
    cv::fisheye::projectPoints(points, cv_pixels, rvec, tvec, K, dist_coeffs);
  } else {
    cv::projectPoints(points, rvec, tvec, K, dist_coeffs, cv_pixels);
  }
  ASSERT_EQ(cv_pixels.size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    double x, y;
    CameraModelImgFromCam(id, params.data(), points[i].x, points[i].y,
                          points[i].z, &x, &y);
    EXPECT_NEAR(x, cv_pixels[i].x, 1e-9) << CameraModelIdToName(id) << " " << i;
    EXPECT_NEAR(y, cv_pixels[i].y, 1e-9) << CameraModelIdToName(id) << " " << i;
  }
}

TEST(CameraModels, OpenCVMatchesCvProjectPoints) {
  const std::vector<double> params = {500,   520,  320.5, 240.25,
                                      -0.12, 0.03, 0.004, -0.003};
  ExpectMatchesOpenCV(CameraModelId::kOpenCV, params,
                      {params[4], params[5], params[6], params[7]}, false);
}

TEST(CameraModels, FullOpenCVMatchesCvProjectPoints) {
  const std::vector<double> params = {500,   520,  320.5, 240.25,
                                      -0.12, 0.03, 0.004, -0.003,
                                      0.002, 0.05, -0.01, 0.003};
  // OpenCV's rational order k1 k2 p1 p2 k3 k4 k5 k6 is COLMAP's order.
  ExpectMatchesOpenCV(CameraModelId::kFullOpenCV, params,
                      std::vector<double>(params.begin() + 4, params.end()),
                      false);
}

TEST(CameraModels, OpenCVFisheyeMatchesCvFisheyeProjectPoints) {
  const std::vector<double> params = {300,  310,   320.5, 240.25,
                                      0.05, -0.02, 0.004, -0.001};
  ExpectMatchesOpenCV(CameraModelId::kOpenCVFisheye, params,
                      std::vector<double>(params.begin() + 4, params.end()),
                      true);
}

TEST(CameraModels, FOVClosedFormsAreInverse) {
  // Near omega = 0 and near r = 0 the Taylor branches are used; they must
  // agree with the exact formulas just outside their range.
  for (const double omega : {0.0, 0.005, 0.5, 1.2}) {
    for (const double r : {0.0, 0.002, 0.3, 0.8}) {
      double ud, vd, u, v;
      FOVCameraModel::Distort(omega, r, 0.5 * r, &ud, &vd);
      FOVCameraModel::Undistort(omega, ud, vd, &u, &v);
      EXPECT_NEAR(u, r, 1e-9) << omega << " " << r;
      EXPECT_NEAR(v, 0.5 * r, 1e-9) << omega << " " << r;
    }
  }
  // Exact value: r_d = atan(2 r tan(w/2)) / w.
  double ud, vd;
  FOVCameraModel::Distort(0.9, 0.6, 0.0, &ud, &vd);
  EXPECT_NEAR(ud, std::atan(2 * 0.6 * std::tan(0.45)) / 0.9, 1e-15);
}

TEST(CameraModels, ImgFromCamWorksWithJets) {
  // Derivatives from Jets must match central differences for every model.
  using Jet = ceres::Jet<double, 3>;
  for (const CameraModelId id : AllCameraModelIds()) {
    const std::vector<double> params = TestParams(id);
    const double point[3] = {0.3, -0.2, 1.4};
    VisitCameraModel(id, [&](auto model) {
      using Model = decltype(model);
      std::vector<Jet> jet_params(params.begin(), params.end());
      Jet jet_point[3];
      for (int i = 0; i < 3; ++i) {
        jet_point[i] = Jet(point[i], i);
      }
      Jet x, y;
      Model::ImgFromCam(jet_params.data(), jet_point[0], jet_point[1],
                        jet_point[2], &x, &y);
      for (int i = 0; i < 3; ++i) {
        double plus[3] = {point[0], point[1], point[2]};
        double minus[3] = {point[0], point[1], point[2]};
        const double h = 1e-6;
        plus[i] += h;
        minus[i] -= h;
        double xp, yp, xm, ym;
        Model::ImgFromCam(params.data(), plus[0], plus[1], plus[2], &xp, &yp);
        Model::ImgFromCam(params.data(), minus[0], minus[1], minus[2], &xm,
                          &ym);
        EXPECT_NEAR(x.v[i], (xp - xm) / (2 * h), 1e-4) << Model::kModelName;
        EXPECT_NEAR(y.v[i], (yp - ym) / (2 * h), 1e-4) << Model::kModelName;
      }
    });
  }
}

}  // namespace
}  // namespace colmap_lidar
