#include "src/sfm/pose_prior_checks.h"

#include <cmath>
#include <utility>

namespace colmap_lidar {

int PriorOutlierLevel(const Rigid3d& cam_from_world, const Rigid3d& prior,
                      double position_sigma_m, double rotation_rms_deg) {
  const double centre_error = (cam_from_world.Inverse().translation -
                               prior.Inverse().translation)
                                  .norm() /
                              position_sigma_m;
  const double angle = cam_from_world.rotation.normalized().angularDistance(
                           prior.rotation.normalized()) *
                       180.0 / M_PI / rotation_rms_deg;
  const double chi_square = centre_error * centre_error;
  if (chi_square > 30.66 || angle > 4.89) {
    return 2;
  }
  return chi_square > 16.27 || angle > 3.29 ? 1 : 0;
}

double PerAxisRotationSigmaDeg(double rms_angle_deg) {
  return rms_angle_deg / std::sqrt(3.0);
}

double RotationAngleDeg(const Eigen::Quaterniond& a,
                        const Eigen::Quaterniond& b) {
  return a.normalized().angularDistance(b.normalized()) * 180.0 / M_PI;
}

Reconstruction PriorModel(const Database& database) {
  Reconstruction model;
  for (const Camera& camera : database.ReadAllCameras()) {
    model.cameras[camera.camera_id] = camera;
  }
  for (const DatabaseImage& db_image : database.ReadAllImages()) {
    if (!db_image.prior_q || !db_image.prior_t) {
      continue;
    }
    Image image;
    image.image_id = db_image.image_id;
    image.name = db_image.name;
    image.camera_id = db_image.camera_id;
    const Eigen::Quaterniond rotation = db_image.prior_q->normalized();
    image.cam_from_world = Rigid3d(rotation, -(rotation * *db_image.prior_t));
    model.images.push_back(std::move(image));
  }
  return model;
}

}  // namespace colmap_lidar
