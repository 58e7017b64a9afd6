#include "src/sfm/model_alignment.h"

#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

Reconstruction RandomModel(int num_images, std::mt19937* rng) {
  std::normal_distribution<double> normal(0.0, 3.0);
  Reconstruction model;
  for (int i = 0; i < num_images; ++i) {
    Image image;
    image.image_id = i + 1;
    image.camera_id = 1;
    const Eigen::Quaterniond rotation =
        Eigen::Quaterniond::UnitRandom().normalized();
    const Eigen::Vector3d centre(normal(*rng), normal(*rng), normal(*rng));
    image.cam_from_world = Rigid3d(rotation, -(rotation * centre));
    model.images.push_back(image);
  }
  Point3D point;
  point.xyz = Eigen::Vector3d(1, 2, 3);
  model.points3D[1] = point;
  return model;
}

TEST(ModelAlignment, RecoversAKnownSim3) {
  std::mt19937 rng(3);
  Reconstruction model = RandomModel(10, &rng);
  Sim3d truth;
  truth.scale = 2.5;
  truth.rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())
          .toRotationMatrix();
  truth.translation = Eigen::Vector3d(-4, 5, 0.5);
  Reconstruction target = model;
  TransformReconstruction(truth, &target);
  // The transform keeps each camera's view of the (scaled) point.
  const Eigen::Vector3d in_cam_before =
      model.images[3].cam_from_world * model.points3D[1].xyz;
  const Eigen::Vector3d in_cam_after =
      target.images[3].cam_from_world * target.points3D[1].xyz;
  EXPECT_TRUE(in_cam_after.isApprox(truth.scale * in_cam_before, 1e-9));

  std::unordered_map<image_t, Rigid3d> priors;
  for (const Image& image : target.images) {
    priors[image.image_id] = image.cam_from_world;
  }
  const PriorAlignmentSummary summary =
      AlignReconstructionToPriors(priors, &model);
  EXPECT_EQ(summary.num_images, 10);
  EXPECT_NEAR(summary.prior_from_model.scale, 2.5, 1e-9);
  EXPECT_LT(summary.rms_residual_m, 1e-9);
  for (size_t i = 0; i < model.images.size(); ++i) {
    EXPECT_TRUE(model.images[i].ProjectionCenter().isApprox(
        target.images[i].ProjectionCenter(), 1e-9));
    EXPECT_NEAR(model.images[i].cam_from_world.rotation.angularDistance(
                    target.images[i].cam_from_world.rotation),
                0.0, 1e-9);
  }
  EXPECT_TRUE(model.points3D[1].xyz.isApprox(target.points3D[1].xyz, 1e-9));
}

TEST(ModelAlignment, TooFewOrCollinearCentresThrow) {
  std::mt19937 rng(4);
  Reconstruction model = RandomModel(2, &rng);
  std::unordered_map<image_t, Rigid3d> priors;
  for (const Image& image : model.images) {
    priors[image.image_id] = image.cam_from_world;
  }
  EXPECT_THROW(AlignReconstructionToPriors(priors, &model), Error);

  Reconstruction line = RandomModel(5, &rng);
  priors.clear();
  for (size_t i = 0; i < line.images.size(); ++i) {
    Image& image = line.images[i];
    // Centres on the z axis.
    image.cam_from_world.translation =
        -(image.cam_from_world.rotation * Eigen::Vector3d(0, 0, i));
    priors[image.image_id] = image.cam_from_world;
  }
  EXPECT_THROW(AlignReconstructionToPriors(priors, &line), Error);
}

}  // namespace
}  // namespace colmap_lidar
