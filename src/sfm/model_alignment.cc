#include "src/sfm/model_alignment.h"

#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

void TransformReconstruction(const Sim3d& target_from_source,
                             Reconstruction* model) {
  const Eigen::Quaterniond rotation(target_from_source.rotation);
  for (Image& image : model->images) {
    // world_from_cam' = sim3 * world_from_cam: centre c' = s R c + t,
    // orientation R_cw' = R_cw R^T.
    const Eigen::Vector3d centre =
        target_from_source * image.ProjectionCenter();
    const Eigen::Quaterniond cam_from_world_rotation =
        (image.cam_from_world.rotation * rotation.conjugate()).normalized();
    image.cam_from_world = Rigid3d(cam_from_world_rotation,
                                   -(cam_from_world_rotation * centre));
  }
  for (auto& [point3D_id, point3D] : model->points3D) {
    point3D.xyz = target_from_source * point3D.xyz;
  }
  for (auto& [line3D_id, line3D] : model->lines3D) {
    line3D.start_in_world = target_from_source * line3D.start_in_world;
    line3D.end_in_world = target_from_source * line3D.end_in_world;
  }
}

PriorAlignmentSummary AlignReconstructionToPriors(
    const std::unordered_map<image_t, Rigid3d>& cam_from_world_priors,
    Reconstruction* model) {
  std::vector<Eigen::Vector3d> model_centres;
  std::vector<Eigen::Vector3d> prior_centres;
  for (const Image& image : model->images) {
    const auto it = cam_from_world_priors.find(image.image_id);
    if (it == cam_from_world_priors.end()) {
      continue;
    }
    model_centres.push_back(image.ProjectionCenter());
    prior_centres.push_back(it->second.Inverse().translation);
  }
  const int num_images = static_cast<int>(model_centres.size());
  THROW_CHECK(num_images >= 3, "Sim3 alignment to the priors needs at least 3 "
                               "model images with a prior pose, got "
                                   << num_images);
  Eigen::Matrix3Xd source(3, num_images);
  Eigen::Matrix3Xd target(3, num_images);
  for (int i = 0; i < num_images; ++i) {
    source.col(i) = model_centres[i];
    target.col(i) = prior_centres[i];
  }
  // Degenerate configurations (all centres on a line) leave the rotation
  // about that line undetermined.
  const Eigen::Matrix3Xd centred =
      source.colwise() - source.rowwise().mean();
  const Eigen::JacobiSVD<Eigen::Matrix3Xd> svd(centred);
  const Eigen::Vector3d singular_values = svd.singularValues();
  THROW_CHECK(singular_values(1) > 1e-3 * std::sqrt(num_images) &&
                  singular_values(1) > 1e-6 * singular_values(0),
              "Sim3 alignment to the priors: the " << num_images
                  << " model camera centres are collinear or identical");

  const Eigen::Matrix4d transform = Eigen::umeyama(source, target, true);
  PriorAlignmentSummary summary;
  summary.num_images = num_images;
  const Eigen::Matrix3d scaled_rotation = transform.topLeftCorner<3, 3>();
  summary.prior_from_model.scale = std::cbrt(scaled_rotation.determinant());
  summary.prior_from_model.rotation =
      scaled_rotation / summary.prior_from_model.scale;
  summary.prior_from_model.translation = transform.topRightCorner<3, 1>();
  double sum_squared = 0.0;
  for (int i = 0; i < num_images; ++i) {
    sum_squared += (summary.prior_from_model * model_centres[i] -
                    prior_centres[i])
                       .squaredNorm();
  }
  summary.rms_residual_m = std::sqrt(sum_squared / num_images);
  TransformReconstruction(summary.prior_from_model, model);
  return summary;
}

}  // namespace colmap_lidar
