// Residuals of the point + line bundle adjustment (paper section III-D,
// equations 1-3) and of the LIDAR and pose-prior terms that give it metric
// scale. Each functor is templated for ceres::AutoDiffCostFunction and has
// a static Create().
//
// Parameter blocks, shared by all functors:
//   cam_from_world_rotation    4  unit quaternion, Eigen memory order
//                                 (x, y, z, w) as Rigid3d stores it
//                                 (ceres::EigenQuaternionManifold)
//   cam_from_world_translation 3
//   point3D_in_world           3
//   line_in_world              6  orthonormal line [qx qy qz qw w1 w2]
//                                 (line_geometry.h, OrthonormalLineManifold)
//   camera_params              CameraModel::kNumParams, COLMAP order
#pragma once

#include <cmath>
#include <vector>

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "colmap_ext/scene/camera_models.h"
#include "colmap_ext/scene/rigid3.h"
#include "src/optim/line_geometry.h"

namespace colmap_lidar {
namespace internal {

// Focal lengths and principal point of a model's parameter vector (the
// SIMPLE_* models share one focal length).
template <typename CameraModel, typename T>
void ModelCalibration(const T* params, T* fx, T* fy, T* cx, T* cy) {
  *fx = params[CameraModel::kFocalLengthIdxs[0]];
  *fy = params[CameraModel::kFocalLengthIdxs[CameraModel::kFocalLengthIdxs
                                                 .size() -
                                             1]];
  *cx = params[CameraModel::kPrincipalPointIdxs[0]];
  *cy = params[CameraModel::kPrincipalPointIdxs[1]];
}

// The infinite line of an orthonormal parameter block taken to the camera
// frame, as an unnormalised Pluecker vector: d_cam = R d, m_cam = R m +
// t x d_cam.
template <typename T>
void LineInCamera(const T* cam_from_world_rotation,
                  const T* cam_from_world_translation, const T* line_in_world,
                  Eigen::Matrix<T, 3, 1>* d_in_cam,
                  Eigen::Matrix<T, 3, 1>* m_in_cam) {
  Eigen::Matrix<T, 3, 1> d_in_world, m_in_world;
  OrthonormalToPluckerUnnormalized(line_in_world, d_in_world.data(),
                                   m_in_world.data());
  const Eigen::Map<const Eigen::Quaternion<T>> rotation(
      cam_from_world_rotation);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> translation(
      cam_from_world_translation);
  *d_in_cam = rotation * d_in_world;
  *m_in_cam = rotation * m_in_world + translation.cross(*d_in_cam);
}

}  // namespace internal

// Point reprojection error (paper eq. 1), in pixels:
//
//   r = pi(R_cw X_w + t_cw; params) - x_obs
//
// with pi = CameraModel::ImgFromCam. Like COLMAP's BA residual, no special
// case for points behind the camera.
template <typename CameraModel>
class PointReprojectionCostFunctor {
 public:
  explicit PointReprojectionCostFunctor(const Eigen::Vector2d& point2D)
      : observed_x_(point2D.x()), observed_y_(point2D.y()) {}

  static ceres::CostFunction* Create(const Eigen::Vector2d& point2D) {
    return new ceres::AutoDiffCostFunction<PointReprojectionCostFunctor, 2, 4,
                                           3, 3, CameraModel::kNumParams>(
        new PointReprojectionCostFunctor(point2D));
  }

  template <typename T>
  bool operator()(const T* cam_from_world_rotation,
                  const T* cam_from_world_translation,
                  const T* point3D_in_world, const T* camera_params,
                  T* residuals) const {
    const Eigen::Map<const Eigen::Quaternion<T>> rotation(
        cam_from_world_rotation);
    const Eigen::Matrix<T, 3, 1> point3D_in_cam =
        rotation * Eigen::Map<const Eigen::Matrix<T, 3, 1>>(point3D_in_world) +
        Eigen::Map<const Eigen::Matrix<T, 3, 1>>(cam_from_world_translation);
    CameraModel::ImgFromCam(camera_params, point3D_in_cam[0],
                            point3D_in_cam[1], point3D_in_cam[2],
                            &residuals[0], &residuals[1]);
    residuals[0] -= T(observed_x_);
    residuals[1] -= T(observed_y_);
    return true;
  }

 private:
  const double observed_x_;
  const double observed_y_;
};

// Line reprojection error (paper eq. 2, after PL-SLAM): signed pixel
// distances of the observed segment's endpoints s, e to the projection of
// the infinite line,
//
//   l   = K^-T m_cam  (homogeneous image line, undistorted pixels)
//   r_k = l . (x_k, 1) / sqrt(l_0^2 + l_1^2),   k in {s, e}
//
// where K holds the current focal length(s) and principal point. For the
// pinhole models (no distortion) x_k are the observed pixels, so the
// residual is the exact pixel distance and also constrains K. A 3D line is
// a curve in a distorted image; for the other models the observed endpoints
// are undistorted once, at creation, with the camera parameters given then
// (n_k = CamFromImg(obs_k)), and x_k = K n_k: the distance is measured in
// the undistorted image. Line residuals therefore carry no information on
// the distortion parameters of those models (points still do).
template <typename CameraModel>
class LineReprojectionCostFunctor {
 public:
  LineReprojectionCostFunctor(const Eigen::Vector2d& start2D,
                              const Eigen::Vector2d& end2D,
                              const double* camera_params) {
    const Eigen::Vector2d observed[2] = {start2D, end2D};
    for (int k = 0; k < 2; ++k) {
      if constexpr (kUsesPixels) {
        observed_[k] = observed[k];
      } else {
        double u, v, w;
        CameraModel::CamFromImg(camera_params, observed[k].x(),
                                observed[k].y(), &u, &v, &w);
        observed_[k] = Eigen::Vector2d(u / w, v / w);
      }
    }
  }

  // camera_params: the model's parameters used to undistort the
  // observations of distorted models (ignored for pinhole models).
  static ceres::CostFunction* Create(const Eigen::Vector2d& start2D,
                                     const Eigen::Vector2d& end2D,
                                     const double* camera_params) {
    return new ceres::AutoDiffCostFunction<LineReprojectionCostFunctor, 2, 4,
                                           3, 6, CameraModel::kNumParams>(
        new LineReprojectionCostFunctor(start2D, end2D, camera_params));
  }

  template <typename T>
  bool operator()(const T* cam_from_world_rotation,
                  const T* cam_from_world_translation,
                  const T* line_in_world, const T* camera_params,
                  T* residuals) const {
    using std::sqrt;
    Eigen::Matrix<T, 3, 1> d_in_cam, m_in_cam;
    internal::LineInCamera(cam_from_world_rotation, cam_from_world_translation,
                           line_in_world, &d_in_cam, &m_in_cam);
    T fx, fy, cx, cy;
    internal::ModelCalibration<CameraModel>(camera_params, &fx, &fy, &cx, &cy);
    // m . (u, v, 1) = 0 with u = (x - cx) / fx, v = (y - cy) / fy, times
    // fx * fy.
    const T l0 = fy * m_in_cam[0];
    const T l1 = fx * m_in_cam[1];
    const T l2 = fx * fy * m_in_cam[2] - cx * l0 - cy * l1;
    const T inv_norm = T(1) / sqrt(l0 * l0 + l1 * l1);
    for (int k = 0; k < 2; ++k) {
      T x, y;
      if constexpr (kUsesPixels) {
        x = T(observed_[k].x());
        y = T(observed_[k].y());
      } else {
        x = fx * T(observed_[k].x()) + cx;
        y = fy * T(observed_[k].y()) + cy;
      }
      residuals[k] = (l0 * x + l1 * y + l2) * inv_norm;
    }
    return true;
  }

 private:
  static constexpr bool kUsesPixels = CameraModel::kExtraParamsIdxs.size() == 0;
  // Pixels (pinhole models) or undistorted normalised coordinates.
  Eigen::Vector2d observed_[2];
};

// LIDAR line error (metric scale, not in the paper's eq. 3): the 3D offsets
// of the view's LIDAR segment endpoints p_k (camera frame, metres) from the
// line taken to the camera frame, divided by the LIDAR range noise sigma:
//
//   p0  = d x m / |d|^2                 (closest point to the origin)
//   r_k = (p_k - p0 - ((p_k - p0) . d) d / |d|^2) / sigma,   k in {s, e}
//
// (d, m) = the line in the camera frame. |r_k| sigma is the point-to-line
// distance; the offset vector (3 residuals per endpoint, perpendicular to
// d, so 2 effective) is used rather than its norm so that the residual is
// smooth at zero. Because p_k are metric and in the camera frame, these
// residuals fix the scale and tie each pose to the line.
class LidarLineCostFunctor {
 public:
  LidarLineCostFunctor(const Eigen::Vector3d& start_in_cam,
                       const Eigen::Vector3d& end_in_cam, double sigma_m)
      : endpoints_in_cam_{start_in_cam, end_in_cam},
        inv_sigma_(1.0 / sigma_m) {}

  static ceres::CostFunction* Create(const Eigen::Vector3d& start_in_cam,
                                     const Eigen::Vector3d& end_in_cam,
                                     double sigma_m) {
    return new ceres::AutoDiffCostFunction<LidarLineCostFunctor, 6, 4, 3, 6>(
        new LidarLineCostFunctor(start_in_cam, end_in_cam, sigma_m));
  }

  template <typename T>
  bool operator()(const T* cam_from_world_rotation,
                  const T* cam_from_world_translation,
                  const T* line_in_world, T* residuals) const {
    Eigen::Matrix<T, 3, 1> d_in_cam, m_in_cam;
    internal::LineInCamera(cam_from_world_rotation, cam_from_world_translation,
                           line_in_world, &d_in_cam, &m_in_cam);
    const T inv_d_squared = T(1) / d_in_cam.squaredNorm();
    const Eigen::Matrix<T, 3, 1> p0 = d_in_cam.cross(m_in_cam) * inv_d_squared;
    for (int k = 0; k < 2; ++k) {
      const Eigen::Matrix<T, 3, 1> offset =
          endpoints_in_cam_[k].cast<T>() - p0;
      const Eigen::Matrix<T, 3, 1> perpendicular =
          offset - d_in_cam * (offset.dot(d_in_cam) * inv_d_squared);
      for (int i = 0; i < 3; ++i) {
        residuals[3 * k + i] = perpendicular[i] * T(inv_sigma_);
      }
    }
    return true;
  }

 private:
  const Eigen::Vector3d endpoints_in_cam_[2];
  const double inv_sigma_;
};

// Pose prior (e.g. VIO poses or the noisy initial poses, paper section
// III / IV-A), on the camera centre and orientation:
//
//   C   = -R_cw^T t_cw
//   r_C = (C - C_prior) / sigma_position                     (metres)
//   r_R = AngleAxis(R_cw R_cw,prior^T) / sigma_rotation      (radians)
//
// Tying the centre rather than t_cw keeps the position and rotation terms
// independent.
class PosePriorCostFunctor {
 public:
  PosePriorCostFunctor(const Rigid3d& prior_cam_from_world,
                       double position_sigma_m, double rotation_sigma_rad)
      : prior_center_in_world_(prior_cam_from_world.Inverse().translation),
        prior_world_from_cam_rotation_(
            prior_cam_from_world.rotation.normalized().conjugate()),
        inv_position_sigma_(1.0 / position_sigma_m),
        inv_rotation_sigma_(1.0 / rotation_sigma_rad) {}

  static ceres::CostFunction* Create(const Rigid3d& prior_cam_from_world,
                                     double position_sigma_m,
                                     double rotation_sigma_rad) {
    return new ceres::AutoDiffCostFunction<PosePriorCostFunctor, 6, 4, 3>(
        new PosePriorCostFunctor(prior_cam_from_world, position_sigma_m,
                                 rotation_sigma_rad));
  }

  template <typename T>
  bool operator()(const T* cam_from_world_rotation,
                  const T* cam_from_world_translation, T* residuals) const {
    const Eigen::Map<const Eigen::Quaternion<T>> rotation(
        cam_from_world_rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> translation(
        cam_from_world_translation);
    const Eigen::Matrix<T, 3, 1> center = -(rotation.conjugate() * translation);
    for (int i = 0; i < 3; ++i) {
      residuals[i] =
          (center[i] - T(prior_center_in_world_[i])) * T(inv_position_sigma_);
    }
    const Eigen::Quaternion<T> delta =
        rotation * prior_world_from_cam_rotation_.cast<T>();
    const T delta_wxyz[4] = {delta.w(), delta.x(), delta.y(), delta.z()};
    T angle_axis[3];
    ceres::QuaternionToAngleAxis(delta_wxyz, angle_axis);
    for (int i = 0; i < 3; ++i) {
      residuals[3 + i] = angle_axis[i] * T(inv_rotation_sigma_);
    }
    return true;
  }

 private:
  const Eigen::Vector3d prior_center_in_world_;
  const Eigen::Quaterniond prior_world_from_cam_rotation_;
  const double inv_position_sigma_;
  const double inv_rotation_sigma_;
};

// Distance of a sparse 3D point to the LIDAR surface its image saw there
// (a local plane of that image's scan, src/sfm/lidar_point_planes.h), in
// units of the plane's sigma:
//
//   r = (n_cam . (R_cw X_w + t_cw) - d_cam) / sigma
//
// with the unit normal n_cam and offset d_cam = n_cam . c_cam of the plane
// in the camera frame (c_cam a point of it). Like the LIDAR line residuals
// these are metric: they fix the scale, and, through the point's bearing,
// the camera's position along surfaces that leave a scan registration
// blind (a corridor's axis): a wall point seen at a known distance from the
// wall sits at a known position along it.
class LidarPointPlaneCostFunctor {
 public:
  LidarPointPlaneCostFunctor(const Eigen::Vector3d& normal_in_cam,
                             double offset_m, double sigma_m)
      : normal_in_cam_(normal_in_cam),
        offset_m_(offset_m),
        inv_sigma_(1.0 / sigma_m) {}

  static ceres::CostFunction* Create(const Eigen::Vector3d& normal_in_cam,
                                     double offset_m, double sigma_m) {
    return new ceres::AutoDiffCostFunction<LidarPointPlaneCostFunctor, 1, 4, 3,
                                           3>(
        new LidarPointPlaneCostFunctor(normal_in_cam, offset_m, sigma_m));
  }

  template <typename T>
  bool operator()(const T* cam_from_world_rotation,
                  const T* cam_from_world_translation,
                  const T* point3D_in_world, T* residuals) const {
    const Eigen::Map<const Eigen::Quaternion<T>> rotation(
        cam_from_world_rotation);
    const Eigen::Matrix<T, 3, 1> point3D_in_cam =
        rotation * Eigen::Map<const Eigen::Matrix<T, 3, 1>>(point3D_in_world) +
        Eigen::Map<const Eigen::Matrix<T, 3, 1>>(cam_from_world_translation);
    residuals[0] =
        (normal_in_cam_.cast<T>().dot(point3D_in_cam) - T(offset_m_)) *
        T(inv_sigma_);
    return true;
  }

 private:
  const Eigen::Vector3d normal_in_cam_;
  const double offset_m_;
  const double inv_sigma_;
};

// The whitened error of a relative LIDAR pose edge, shared by the pose
// graph (src/sfm/lidar_pose_graph.h, world_from_cam variables) and the
// adjustment (cam_from_world variables). Given cam_i_from_cam_j = (rel_q,
// rel_t), the fixed lidar_i_from_cam_i, cam_j_from_lidar_j and the inverse
// of the measurement M = lidar_i_from_lidar_j:
//   E = M^-1 * C_i^-1 * rel * C_j,   r = S * [AngleAxis(E.R); E.t]   (6)
template <typename T>
void WhitenedRelativeLidarPoseError(
    const Eigen::Quaternion<T>& rel_q, const Eigen::Matrix<T, 3, 1>& rel_t,
    const Rigid3d& measured_inverse, const Rigid3d& lidar_i_from_cam_i,
    const Rigid3d& cam_j_from_lidar_j,
    const Eigen::Matrix<double, 6, 6>& sqrt_information, T* residuals) {
  using Quaternion = Eigen::Quaternion<T>;
  using Vector3 = Eigen::Matrix<T, 3, 1>;
  // lidar_i_from_lidar_j = C_i^-1 * rel * C_j.
  const Quaternion cj_q = cam_j_from_lidar_j.rotation.cast<T>();
  const Vector3 cj_t = cam_j_from_lidar_j.translation.cast<T>();
  const Quaternion ci_q = lidar_i_from_cam_i.rotation.cast<T>();
  const Vector3 ci_t = lidar_i_from_cam_i.translation.cast<T>();
  const Quaternion est_q = ci_q * rel_q * cj_q;
  const Vector3 est_t = ci_q * (rel_q * cj_t + rel_t) + ci_t;
  // E = M^-1 * est.
  const Quaternion m_q = measured_inverse.rotation.cast<T>();
  const Vector3 m_t = measured_inverse.translation.cast<T>();
  const Quaternion error_q = m_q * est_q;
  const Vector3 error_t = m_q * est_t + m_t;
  const T error_wxyz[4] = {error_q.w(), error_q.x(), error_q.y(),
                           error_q.z()};
  T angle_axis[3];
  ceres::QuaternionToAngleAxis(error_wxyz, angle_axis);
  Eigen::Matrix<T, 6, 1> error;
  error << angle_axis[0], angle_axis[1], angle_axis[2], error_t[0],
      error_t[1], error_t[2];
  Eigen::Map<Eigen::Matrix<T, 6, 1>> whitened(residuals);
  whitened = sqrt_information.cast<T>() * error;
}

// Relative LIDAR pose edge (a scan registration kept from the LIDAR pose
// graph, src/sfm/lidar_pose_graph.h) in the adjuster's parameterisation.
// With P_i, P_j = cam_from_world of images i and j, the fixed cam_from_lidar
// C_i, C_j and the measurement M = lidar_i_from_lidar_j:
//
//   E = M^-1 * C_i^-1 * P_i * P_j^-1 * C_j      (identity when consistent)
//   r = S * [AngleAxis(E.R); E.t]               (6, whitened)
//
// This is exactly RelativePoseCostFunctor's E (P = W^-1), so the same
// square-root information S (S^T S = Lambda of the registration, right
// perturbation of lidar_i_from_lidar_j, rotation first) applies.
class RelativeLidarPoseCostFunctor {
 public:
  RelativeLidarPoseCostFunctor(
      const Rigid3d& lidar_i_from_lidar_j, const Rigid3d& cam_from_lidar_i,
      const Rigid3d& cam_from_lidar_j,
      const Eigen::Matrix<double, 6, 6>& sqrt_information)
      : measured_inverse_(lidar_i_from_lidar_j.Inverse()),
        lidar_i_from_cam_i_(cam_from_lidar_i.Inverse()),
        cam_j_from_lidar_j_(cam_from_lidar_j),
        sqrt_information_(sqrt_information) {}

  static ceres::CostFunction* Create(
      const Rigid3d& lidar_i_from_lidar_j, const Rigid3d& cam_from_lidar_i,
      const Rigid3d& cam_from_lidar_j,
      const Eigen::Matrix<double, 6, 6>& sqrt_information) {
    return new ceres::AutoDiffCostFunction<RelativeLidarPoseCostFunctor, 6, 4,
                                           3, 4, 3>(
        new RelativeLidarPoseCostFunctor(lidar_i_from_lidar_j,
                                         cam_from_lidar_i, cam_from_lidar_j,
                                         sqrt_information));
  }

  template <typename T>
  bool operator()(const T* cam_i_from_world_rotation,
                  const T* cam_i_from_world_translation,
                  const T* cam_j_from_world_rotation,
                  const T* cam_j_from_world_translation, T* residuals) const {
    using Quaternion = Eigen::Quaternion<T>;
    using Vector3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Quaternion> pi_q(cam_i_from_world_rotation);
    const Eigen::Map<const Vector3> pi_t(cam_i_from_world_translation);
    const Eigen::Map<const Quaternion> pj_q(cam_j_from_world_rotation);
    const Eigen::Map<const Vector3> pj_t(cam_j_from_world_translation);
    // cam_i_from_cam_j = P_i * P_j^-1.
    const Quaternion rel_q = pi_q * pj_q.conjugate();
    const Vector3 rel_t = pi_t - rel_q * pj_t;
    WhitenedRelativeLidarPoseError(rel_q, rel_t, measured_inverse_,
                                   lidar_i_from_cam_i_, cam_j_from_lidar_j_,
                                   sqrt_information_, residuals);
    return true;
  }

 private:
  const Rigid3d measured_inverse_;
  const Rigid3d lidar_i_from_cam_i_;
  const Rigid3d cam_j_from_lidar_j_;
  const Eigen::Matrix<double, 6, 6> sqrt_information_;
};

// Runtime dispatch on the camera model id (throws colmap_lidar::Error for
// an unknown id).
inline ceres::CostFunction* CreatePointReprojectionCostFunction(
    CameraModelId model_id, const Eigen::Vector2d& point2D) {
  return VisitCameraModel(model_id, [&](auto model) -> ceres::CostFunction* {
    return PointReprojectionCostFunctor<decltype(model)>::Create(point2D);
  });
}

inline ceres::CostFunction* CreateLineReprojectionCostFunction(
    CameraModelId model_id, const Eigen::Vector2d& start2D,
    const Eigen::Vector2d& end2D, const double* camera_params) {
  return VisitCameraModel(model_id, [&](auto model) -> ceres::CostFunction* {
    return LineReprojectionCostFunctor<decltype(model)>::Create(start2D, end2D,
                                                                camera_params);
  });
}

}  // namespace colmap_lidar
