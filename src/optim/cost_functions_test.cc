#include "src/optim/cost_functions.h"

#include <memory>
#include <random>

#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include "src/optim/line_manifold.h"

namespace colmap_lidar {
namespace {

// A camera about 8 m from a line and a point, both in view.
struct Fixture {
  Rigid3d cam_from_world{
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized())),
      Eigen::Vector3d(0.4, -0.3, 8.0)};
  Eigen::Vector3d line_start{-1.0, 0.5, 0.2};
  Eigen::Vector3d line_end{1.5, -0.4, -0.6};
  Eigen::Vector3d point3D{0.3, 0.6, -0.2};
  Vector6d line_params = PluckerToOrthonormal(PluckerFromPoints(line_start, line_end));
};

const std::vector<double> kPinholeParams = {500, 510, 320, 240};
const std::vector<double> kOpenCVParams = {500, 510, 320, 240,
                                           -0.2, 0.05, 0.001, -0.002};

// Probes a cost function with Ceres' GradientChecker (autodiff vs numeric
// differentiation in the tangent spaces of the manifolds). 1e-5 relative:
// a wrong derivative is off by O(1), central differences on the smallest
// entries (e.g. d/dk4 of a fisheye, ~1e-8) by ~1e-6.
void ExpectGradientsMatch(const ceres::CostFunction& cost_function,
                          const std::vector<const ceres::Manifold*>& manifolds,
                          std::vector<double*> parameters) {
  ceres::NumericDiffOptions numeric_diff_options;
  ceres::GradientChecker checker(&cost_function, &manifolds,
                                 numeric_diff_options);
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(parameters.data(), 1e-5, &results))
      << results.error_log;
  EXPECT_TRUE(results.return_value);
}

template <typename CameraModel>
void CheckPointReprojection(std::vector<double> params) {
  Fixture f;
  Camera camera;
  camera.model_id = CameraModel::kModelId;
  camera.params = params;
  const Eigen::Vector2d observed = camera.ImgFromCam(f.cam_from_world * f.point3D);
  ASSERT_GT(observed.x(), 0.0);
  ASSERT_LT(observed.x(), 640.0);
  const std::unique_ptr<ceres::CostFunction> cost(
      PointReprojectionCostFunctor<CameraModel>::Create(observed + Eigen::Vector2d(3, -4)));
  double residuals[2];
  const double* parameters[4] = {f.cam_from_world.rotation.coeffs().data(),
                                 f.cam_from_world.translation.data(),
                                 f.point3D.data(), params.data()};
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  EXPECT_NEAR(residuals[0], -3.0, 1e-9);
  EXPECT_NEAR(residuals[1], 4.0, 1e-9);

  const ceres::EigenQuaternionManifold quaternion_manifold;
  ExpectGradientsMatch(*cost, {&quaternion_manifold, nullptr, nullptr, nullptr},
                       {f.cam_from_world.rotation.coeffs().data(),
                        f.cam_from_world.translation.data(), f.point3D.data(),
                        params.data()});
}

TEST(PointReprojectionCostFunctor, Pinhole) {
  CheckPointReprojection<PinholeCameraModel>(kPinholeParams);
}
TEST(PointReprojectionCostFunctor, SimplePinhole) {
  CheckPointReprojection<SimplePinholeCameraModel>({500, 320, 240});
}
TEST(PointReprojectionCostFunctor, OpenCV) {
  CheckPointReprojection<OpenCVCameraModel>(kOpenCVParams);
}
TEST(PointReprojectionCostFunctor, OpenCVFisheye) {
  CheckPointReprojection<OpenCVFisheyeCameraModel>(
      {500, 510, 320, 240, 0.05, -0.01, 0.002, 0.001});
}
TEST(PointReprojectionCostFunctor, RuntimeDispatch) {
  const std::unique_ptr<ceres::CostFunction> cost(
      CreatePointReprojectionCostFunction(CameraModelId::kFullOpenCV,
                                          Eigen::Vector2d(1, 2)));
  ASSERT_EQ(cost->parameter_block_sizes().size(), 4u);
  EXPECT_EQ(cost->parameter_block_sizes()[3], 12);
}

template <typename CameraModel>
void CheckLineReprojection(std::vector<double> params) {
  Fixture f;
  Camera camera;
  camera.model_id = CameraModel::kModelId;
  camera.params = params;
  camera.width = 640;
  camera.height = 480;
  // Observed endpoints: projections of two points of the line, one of them
  // shifted 2.5 undistorted pixels off the line.
  const Eigen::Vector3d a = f.line_start + 0.1 * (f.line_end - f.line_start);
  const Eigen::Vector3d b = f.line_start + 0.8 * (f.line_end - f.line_start);
  const Eigen::Vector2d start2D = camera.ImgFromCam(f.cam_from_world * a);
  const Eigen::Vector3d image_line = ProjectPluckerToImageLine(
      camera, TransformPlucker(f.cam_from_world,
                               PluckerFromPoints(f.line_start, f.line_end)));
  const Eigen::Vector2d normal = image_line.head<2>().normalized();
  const Eigen::Vector2d end_undistorted =
      UndistortPixel(camera, camera.ImgFromCam(f.cam_from_world * b)) +
      2.5 * normal;
  // Back to distorted pixels through the camera (normalised -> pixel).
  const Eigen::Matrix3d k = camera.CalibrationMatrix();
  const Eigen::Vector3d ray =
      k.inverse() * end_undistorted.homogeneous();
  const Eigen::Vector2d end2D = camera.ImgFromCam(ray);

  const std::unique_ptr<ceres::CostFunction> cost(
      LineReprojectionCostFunctor<CameraModel>::Create(start2D, end2D,
                                                       params.data()));
  double residuals[2];
  const double* parameters[4] = {f.cam_from_world.rotation.coeffs().data(),
                                 f.cam_from_world.translation.data(),
                                 f.line_params.data(), params.data()};
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  EXPECT_NEAR(residuals[0], 0.0, 1e-6);
  EXPECT_NEAR(std::abs(residuals[1]), 2.5, 1e-6);

  // Gradients away from zero residuals: near-zero Jacobian entries only
  // carry numeric noise, which the relative test would flag.
  const std::unique_ptr<ceres::CostFunction> off_cost(
      LineReprojectionCostFunctor<CameraModel>::Create(
          start2D + Eigen::Vector2d(1.5, -2.0), end2D, params.data()));
  const ceres::EigenQuaternionManifold quaternion_manifold;
  const OrthonormalLineManifold line_manifold;
  ExpectGradientsMatch(
      *off_cost, {&quaternion_manifold, nullptr, &line_manifold, nullptr},
      {f.cam_from_world.rotation.coeffs().data(),
       f.cam_from_world.translation.data(), f.line_params.data(), params.data()});
}

TEST(LineReprojectionCostFunctor, Pinhole) {
  CheckLineReprojection<PinholeCameraModel>(kPinholeParams);
}
TEST(LineReprojectionCostFunctor, OpenCV) {
  CheckLineReprojection<OpenCVCameraModel>(kOpenCVParams);
}

TEST(LineReprojectionCostFunctor, ScaleOfLineDoesNotMatter) {
  // The same line with another moment/direction ratio representation:
  // the residual only depends on the line, not on the (w1, w2) scale.
  Fixture f;
  const std::unique_ptr<ceres::CostFunction> cost(
      LineReprojectionCostFunctor<PinholeCameraModel>::Create(
          Eigen::Vector2d(100, 120), Eigen::Vector2d(400, 300),
          kPinholeParams.data()));
  double residuals[2];
  const double* parameters[4] = {f.cam_from_world.rotation.coeffs().data(),
                                 f.cam_from_world.translation.data(),
                                 f.line_params.data(), kPinholeParams.data()};
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  // Move the line: residuals must change (the functor can fail).
  Vector6d other = PluckerToOrthonormal(
      PluckerFromPoints(f.line_start + Eigen::Vector3d(0, 0.2, 0), f.line_end));
  double other_residuals[2];
  parameters[2] = other.data();
  ASSERT_TRUE(cost->Evaluate(parameters, other_residuals, nullptr));
  EXPECT_GT(std::abs(other_residuals[0] - residuals[0]) +
                std::abs(other_residuals[1] - residuals[1]),
            1.0);
}

TEST(LidarLineCostFunctor, ValuesAndGradients) {
  Fixture f;
  // LIDAR endpoints in the camera frame: one on the line, one 0.1 m off it.
  const Eigen::Vector3d start_in_cam = f.cam_from_world * f.line_start;
  const Eigen::Vector3d direction_in_cam =
      f.cam_from_world.rotation * (f.line_end - f.line_start).normalized();
  const Eigen::Vector3d off = direction_in_cam.unitOrthogonal();
  const Eigen::Vector3d end_in_cam =
      f.cam_from_world * f.line_end + 0.1 * off + 0.5 * direction_in_cam;
  constexpr double kSigma = 0.02;
  const std::unique_ptr<ceres::CostFunction> cost(
      LidarLineCostFunctor::Create(start_in_cam, end_in_cam, kSigma));
  double residuals[6];
  const double* parameters[3] = {f.cam_from_world.rotation.coeffs().data(),
                                 f.cam_from_world.translation.data(),
                                 f.line_params.data()};
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  const Eigen::Map<const Eigen::Vector3d> r_start(residuals);
  const Eigen::Map<const Eigen::Vector3d> r_end(residuals + 3);
  EXPECT_NEAR(r_start.norm(), 0.0, 1e-9);
  EXPECT_NEAR(r_end.norm(), 0.1 / kSigma, 1e-9);
  EXPECT_LT((r_end * kSigma - 0.1 * off).norm(), 1e-9);

  // Gradients with both endpoints off the line (see CheckLineReprojection).
  const std::unique_ptr<ceres::CostFunction> off_cost(LidarLineCostFunctor::Create(
      start_in_cam + Eigen::Vector3d(0.05, -0.03, 0.02),
      end_in_cam + Eigen::Vector3d(-0.02, 0.04, 0.01), kSigma));
  const ceres::EigenQuaternionManifold quaternion_manifold;
  const OrthonormalLineManifold line_manifold;
  ExpectGradientsMatch(*off_cost, {&quaternion_manifold, nullptr, &line_manifold},
                       {f.cam_from_world.rotation.coeffs().data(),
                        f.cam_from_world.translation.data(),
                        f.line_params.data()});
}

TEST(LidarPointPlaneCostFunctor, ValuesAndGradients) {
  Fixture f;
  // A plane through the point (in the camera frame), then the same plane
  // moved 0.07 m along its normal: the residual is the signed distance over
  // sigma.
  const Eigen::Vector3d point_in_cam = f.cam_from_world * f.point3D;
  const Eigen::Vector3d normal = Eigen::Vector3d(0.2, -0.3, 1.0).normalized();
  constexpr double kSigma = 0.02;
  double residual = 0.0;
  const double* parameters[3] = {f.cam_from_world.rotation.coeffs().data(),
                                 f.cam_from_world.translation.data(),
                                 f.point3D.data()};
  const std::unique_ptr<ceres::CostFunction> on(
      LidarPointPlaneCostFunctor::Create(normal, normal.dot(point_in_cam),
                                         kSigma));
  ASSERT_TRUE(on->Evaluate(parameters, &residual, nullptr));
  EXPECT_NEAR(residual, 0.0, 1e-9);
  const std::unique_ptr<ceres::CostFunction> off(
      LidarPointPlaneCostFunctor::Create(
          normal, normal.dot(point_in_cam) + 0.07, kSigma));
  ASSERT_TRUE(off->Evaluate(parameters, &residual, nullptr));
  EXPECT_NEAR(residual, -0.07 / kSigma, 1e-9);
  // Moving the point along the plane changes nothing.
  f.point3D += f.cam_from_world.rotation.inverse() * normal.unitOrthogonal();
  ASSERT_TRUE(off->Evaluate(parameters, &residual, nullptr));
  EXPECT_NEAR(residual, -0.07 / kSigma, 1e-9);

  const ceres::EigenQuaternionManifold quaternion_manifold;
  ExpectGradientsMatch(*off, {&quaternion_manifold, nullptr, nullptr},
                       {f.cam_from_world.rotation.coeffs().data(),
                        f.cam_from_world.translation.data(), f.point3D.data()});
}

TEST(GradientChecker, DetectsAWrongJacobian) {
  // The checks above can fail: with a line manifold whose Plus Jacobian has
  // the wrong sign, the chained Jacobian no longer matches numeric
  // differentiation through Plus.
  class FlippedLineManifold : public OrthonormalLineManifold {
   public:
    bool PlusJacobian(const double* x, double* jacobian) const override {
      OrthonormalLineManifold::PlusJacobian(x, jacobian);
      for (int i = 0; i < 24; ++i) jacobian[i] = -jacobian[i];
      return true;
    }
  };
  Fixture f;
  const std::unique_ptr<ceres::CostFunction> cost(LidarLineCostFunctor::Create(
      Eigen::Vector3d(0.1, 0.2, 7.0), Eigen::Vector3d(0.5, -0.3, 8.0), 0.02));
  const ceres::EigenQuaternionManifold quaternion_manifold;
  const FlippedLineManifold line_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {
      &quaternion_manifold, nullptr, &line_manifold};
  ceres::GradientChecker checker(cost.get(), &manifolds,
                                 ceres::NumericDiffOptions());
  ceres::GradientChecker::ProbeResults results;
  double* parameters[3] = {f.cam_from_world.rotation.coeffs().data(),
                           f.cam_from_world.translation.data(),
                           f.line_params.data()};
  EXPECT_FALSE(checker.Probe(parameters, 1e-5, &results));
}

TEST(PosePriorCostFunctor, ValuesAndGradients) {
  Fixture f;
  const Rigid3d prior = f.cam_from_world;
  // Move the camera centre by (0.1, 0, 0) and rotate it by 2 deg about z.
  const double angle = 2.0 * M_PI / 180.0;
  const Eigen::Vector3d center = prior.Inverse().translation + Eigen::Vector3d(0.1, 0, 0);
  Rigid3d moved;
  moved.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ())) *
      prior.rotation;
  moved.translation = -(moved.rotation * center);
  const std::unique_ptr<ceres::CostFunction> cost(
      PosePriorCostFunctor::Create(prior, 0.5, 5.0 * M_PI / 180.0));
  double residuals[6];
  const double* parameters[2] = {moved.rotation.coeffs().data(),
                                 moved.translation.data()};
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  EXPECT_NEAR(residuals[0], 0.1 / 0.5, 1e-9);
  EXPECT_NEAR(residuals[1], 0.0, 1e-9);
  EXPECT_NEAR(residuals[2], 0.0, 1e-9);
  EXPECT_NEAR(residuals[3], 0.0, 1e-9);
  EXPECT_NEAR(residuals[4], 0.0, 1e-9);
  EXPECT_NEAR(residuals[5], 2.0 / 5.0, 1e-9);

  // Gradients at a generic offset (no zero residual components).
  Rigid3d generic = moved;
  generic.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d(3, -1, 2).normalized())) *
      moved.rotation;
  generic.translation += Eigen::Vector3d(0.2, -0.1, 0.3);
  const ceres::EigenQuaternionManifold quaternion_manifold;
  ExpectGradientsMatch(*cost, {&quaternion_manifold, nullptr},
                       {generic.rotation.coeffs().data(), generic.translation.data()});
}

// Two cameras with different cam_from_lidar; the measurement is the true
// lidar_i_from_lidar_j times a known error E^-1, so the residual must be
// S [AngleAxis(E.R); E.t] (the convention of RelativePoseCostFunctor in
// src/sfm/lidar_pose_graph.h, whose information matrix it reuses).
TEST(RelativeLidarPoseCostFunctor, ValuesAndGradients) {
  Fixture f;
  const Rigid3d cam_i_from_world = f.cam_from_world;
  const Rigid3d cam_j_from_world(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d(-1, 1, 2).normalized())) *
          cam_i_from_world.rotation,
      cam_i_from_world.translation + Eigen::Vector3d(0.8, -0.1, 0.3));
  const Rigid3d cam_from_lidar_i(
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX())),
      Eigen::Vector3d(0.05, -0.1, 0.02));
  const Rigid3d cam_from_lidar_j(
      Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY())),
      Eigen::Vector3d(-0.03, 0.08, 0.1));
  const Rigid3d true_lidar_i_from_lidar_j = cam_from_lidar_i.Inverse() *
                                            cam_i_from_world *
                                            cam_j_from_world.Inverse() *
                                            cam_from_lidar_j;
  Eigen::Matrix<double, 6, 6> sqrt_information = Eigen::Matrix<double, 6, 6>::Zero();
  sqrt_information.diagonal() << 100, 200, 300, 10, 20, 30;
  const double* parameters[4] = {
      cam_i_from_world.rotation.coeffs().data(), cam_i_from_world.translation.data(),
      cam_j_from_world.rotation.coeffs().data(), cam_j_from_world.translation.data()};
  double residuals[6];

  // Consistent measurement: zero residual.
  {
    const std::unique_ptr<ceres::CostFunction> cost(RelativeLidarPoseCostFunctor::Create(
        true_lidar_i_from_lidar_j, cam_from_lidar_i, cam_from_lidar_j, sqrt_information));
    ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(residuals[k], 0.0, 1e-9) << k;
  }

  // Known error E: 1 deg about z, (0.1, -0.2, 0) m.
  const double angle = M_PI / 180.0;
  const Rigid3d error(Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ())),
                      Eigen::Vector3d(0.1, -0.2, 0.0));
  const std::unique_ptr<ceres::CostFunction> cost(RelativeLidarPoseCostFunctor::Create(
      true_lidar_i_from_lidar_j * error.Inverse(), cam_from_lidar_i, cam_from_lidar_j,
      sqrt_information));
  ASSERT_TRUE(cost->Evaluate(parameters, residuals, nullptr));
  EXPECT_NEAR(residuals[0], 0.0, 1e-7);
  EXPECT_NEAR(residuals[1], 0.0, 1e-7);
  EXPECT_NEAR(residuals[2], 300.0 * angle, 1e-7);
  EXPECT_NEAR(residuals[3], 10.0 * 0.1, 1e-7);
  EXPECT_NEAR(residuals[4], 20.0 * -0.2, 1e-7);
  EXPECT_NEAR(residuals[5], 0.0, 1e-7);

  // Gradients with a dense S (a diagonal S with the 90 deg mounts makes
  // Jacobian entries exactly zero, where relative errors mean nothing).
  Eigen::Matrix<double, 6, 6> dense_sqrt_information = sqrt_information;
  dense_sqrt_information.array() += 5.0;
  const std::unique_ptr<ceres::CostFunction> dense_cost(RelativeLidarPoseCostFunctor::Create(
      true_lidar_i_from_lidar_j * error.Inverse(), cam_from_lidar_i, cam_from_lidar_j,
      dense_sqrt_information));
  const ceres::EigenQuaternionManifold quaternion_manifold;
  Rigid3d generic_i = cam_i_from_world;
  Rigid3d generic_j = cam_j_from_world;
  generic_j.translation += Eigen::Vector3d(0.2, -0.1, 0.3);
  ExpectGradientsMatch(*dense_cost, {&quaternion_manifold, nullptr, &quaternion_manifold, nullptr},
                       {generic_i.rotation.coeffs().data(), generic_i.translation.data(),
                        generic_j.rotation.coeffs().data(), generic_j.translation.data()});
}

}  // namespace
}  // namespace colmap_lidar
