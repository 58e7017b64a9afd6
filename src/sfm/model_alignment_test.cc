#include "src/sfm/model_alignment.h"

#include <cmath>
#include <iostream>
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

// A walk around a 18 m x 10 m courtyard (cameras looking outwards, level),
// its priors with the synthesizer's noise (0.5 m per axis, 5 deg RMS angle)
// and a stock-mapper-like model of it (another frame and scale).
struct BrokenModelScene {
  static constexpr int kNumImages = 40;
  Reconstruction truth;
  std::unordered_map<image_t, Rigid3d> priors;

  BrokenModelScene() {
    std::mt19937 rng(7);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (int i = 0; i < kNumImages; ++i) {
      const double angle = 2.0 * M_PI * i / kNumImages;
      const Eigen::Vector3d centre(9.0 * std::cos(angle),
                                   5.0 * std::sin(angle), 1.5);
      // Camera z (viewing direction) outwards, y down.
      const Eigen::Vector3d z(std::cos(angle), std::sin(angle), 0.0);
      const Eigen::Vector3d y(0.0, 0.0, -1.0);
      Eigen::Matrix3d world_from_cam;
      world_from_cam << y.cross(z), y, z;
      Image image;
      image.image_id = i + 1;
      image.camera_id = 1;
      const Eigen::Quaterniond rotation(world_from_cam.transpose());
      image.cam_from_world = Rigid3d(rotation, -(rotation * centre));
      truth.images.push_back(image);

      const Eigen::Vector3d noisy_centre =
          centre + 0.5 * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
      const Eigen::Vector3d axis =
          Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
      const Eigen::Matrix3d noisy_world_from_cam =
          Eigen::AngleAxisd(5.0 * M_PI / 180.0 * normal(rng), axis)
              .toRotationMatrix() *
          world_from_cam;
      const Eigen::Quaterniond prior_rotation(
          noisy_world_from_cam.transpose());
      priors[image.image_id] =
          Rigid3d(prior_rotation, -(prior_rotation * noisy_centre));
    }
  }

  // The truth in an arbitrary frame at scale 0.4, as stock mapper gives it.
  Reconstruction Mapped() const {
    Reconstruction model = truth;
    Sim3d model_from_world;
    model_from_world.scale = 0.4;
    model_from_world.rotation =
        Eigen::AngleAxisd(2.0, Eigen::Vector3d(0.3, -1, 0.5).normalized())
            .toRotationMatrix();
    model_from_world.translation = Eigen::Vector3d(3, -2, 7);
    TransformReconstruction(model_from_world, &model);
    return model;
  }

  double MeanCentreError(const Reconstruction& model) const {
    double sum = 0.0;
    for (const Image& image : model.images) {
      sum += (image.ProjectionCenter() -
              truth.FindImage(image.image_id)->ProjectionCenter())
                 .norm();
    }
    return sum / model.images.size();
  }
};

TEST(RobustModelAlignment, AcceptsAnIntactModel) {
  const BrokenModelScene scene;
  Reconstruction model = scene.Mapped();
  const RobustPriorAlignmentSummary summary =
      RobustAlignReconstructionToPriors(scene.priors,
                                        RobustPriorAlignmentOptions(), &model);
  std::cout << summary.Format() << std::endl;
  EXPECT_TRUE(summary.accepted) << summary.rejection;
  EXPECT_EQ(summary.num_images, BrokenModelScene::kNumImages);
  EXPECT_GE(summary.inlier_image_ids.size(), 38u);
  EXPECT_NEAR(summary.prior_from_model.scale, 2.5, 0.1);
  // The sim3 is applied; the gauge error from 40 noisy priors is about
  // 0.1 m.
  EXPECT_LT(scene.MeanCentreError(model), 0.3);
  // Orientations too: the aligned model's rotations are the truth's within
  // the alignment error. The walk is level, so the tilt rests on the 0.5 m
  // height noise of the priors over a 10 m wide loop (1.3 deg per axis).
  double max_angle_deg = 0.0;
  for (const Image& image : model.images) {
    max_angle_deg = std::max(
        max_angle_deg, image.cam_from_world.rotation.angularDistance(
                           scene.truth.FindImage(image.image_id)
                               ->cam_from_world.rotation) *
                           180.0 / M_PI);
  }
  EXPECT_LT(max_angle_deg, 5.0);
}

TEST(RobustModelAlignment, FlagsACollapsedPartAsOutliers) {
  // What stock mapper produced on the default scene once: a third of the
  // images registered at one centre with wrong orientations.
  const BrokenModelScene scene;
  Reconstruction model = scene.Mapped();
  const Eigen::Vector3d collapsed = model.images[27].ProjectionCenter();
  for (int i = 27; i < BrokenModelScene::kNumImages; ++i) {
    Image& image = model.images[i];
    const Eigen::Quaterniond rotation =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.4 * (i - 26), Eigen::Vector3d::UnitY())) *
        model.images[27].cam_from_world.rotation;
    image.cam_from_world = Rigid3d(rotation, -(rotation * collapsed));
  }
  const RobustPriorAlignmentSummary summary =
      RobustAlignReconstructionToPriors(scene.priors,
                                        RobustPriorAlignmentOptions(), &model);
  std::cout << summary.Format() << std::endl;
  ASSERT_TRUE(summary.accepted) << summary.rejection;
  EXPECT_GE(summary.inlier_image_ids.size(), 25u);
  for (const image_t image_id : summary.inlier_image_ids) {
    EXPECT_LE(image_id, 28u) << "image " << image_id << " of the collapsed part";
  }
  // The consensus is aligned as if the rest did not exist.
  Reconstruction consensus;
  for (const image_t image_id : summary.inlier_image_ids) {
    consensus.images.push_back(*model.FindImage(image_id));
  }
  EXPECT_LT(scene.MeanCentreError(consensus), 0.3);
}

TEST(RobustModelAlignment, RejectsAMirroredModel) {
  // The mirror ambiguity: a reflected model (proper rotations, mirrored
  // centres). Its centres fit the planar walk after a half turn, its
  // orientations do not.
  const BrokenModelScene scene;
  Reconstruction model = scene.truth;
  const Eigen::Matrix3d mirror = Eigen::Vector3d(-1, 1, 1).asDiagonal();
  for (Image& image : model.images) {
    const Eigen::Vector3d centre = mirror * image.ProjectionCenter();
    const Eigen::Matrix3d world_from_cam =
        mirror * image.cam_from_world.rotation.toRotationMatrix().transpose() *
        mirror;
    const Eigen::Quaterniond rotation(world_from_cam.transpose());
    image.cam_from_world = Rigid3d(rotation, -(rotation * centre));
  }
  const Reconstruction before = model;
  const RobustPriorAlignmentSummary summary =
      RobustAlignReconstructionToPriors(scene.priors,
                                        RobustPriorAlignmentOptions(), &model);
  std::cout << summary.Format() << std::endl;
  EXPECT_FALSE(summary.accepted);
  EXPECT_TRUE(summary.inlier_image_ids.empty());
  EXPECT_EQ(summary.outlier_image_ids.size(),
            static_cast<size_t>(BrokenModelScene::kNumImages));
  // A rejected model is left as it was.
  EXPECT_TRUE(model.images[5].ProjectionCenter().isApprox(
      before.images[5].ProjectionCenter()));
}

TEST(RobustModelAlignment, RejectsAScaleDrift) {
  // Scale drift along the walk: each step 4 % longer than the previous.
  const BrokenModelScene scene;
  Reconstruction model = scene.truth;
  Eigen::Vector3d drifted = model.images[0].ProjectionCenter();
  double step_scale = 1.0;
  for (int i = 1; i < BrokenModelScene::kNumImages; ++i) {
    step_scale *= 1.04;
    const Eigen::Vector3d step = scene.truth.images[i].ProjectionCenter() -
                                 scene.truth.images[i - 1].ProjectionCenter();
    drifted += step_scale * step;
    Image& image = model.images[i];
    image.cam_from_world.translation =
        -(image.cam_from_world.rotation * drifted);
  }
  const RobustPriorAlignmentSummary summary =
      RobustAlignReconstructionToPriors(scene.priors,
                                        RobustPriorAlignmentOptions(), &model);
  std::cout << summary.Format() << std::endl;
  EXPECT_FALSE(summary.accepted);
  EXPECT_FALSE(summary.rejection.empty());
}

}  // namespace
}  // namespace colmap_lidar
