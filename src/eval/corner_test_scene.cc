#include "src/eval/corner_test_scene.h"

#include <cmath>
#include <cstdint>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/scene/reconstruction.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/poses.h"

namespace colmap_lidar {
namespace testing {

Corner CornerMesh() {
  Corner corner;
  const auto add_rectangle = [&corner](const Eigen::Vector3d& origin,
                                       const Eigen::Vector3d& u,
                                       const Eigen::Vector3d& v) {
    const int base = static_cast<int>(corner.vertices.size());
    corner.vertices.insert(corner.vertices.end(),
                           {origin, origin + u, origin + u + v, origin + v});
    corner.triangles.emplace_back(base, base + 1, base + 2);
    corner.triangles.emplace_back(base, base + 2, base + 3);
  };
  add_rectangle({0, 0, 0}, {6, 0, 0}, {0, 6, 0});
  add_rectangle({0, 0, 0}, {0, 6, 0}, {0, 0, 3});
  add_rectangle({0, 0, 0}, {6, 0, 0}, {0, 0, 3});
  return corner;
}

void WritePointsPly(const std::string& path,
                    const std::vector<Eigen::Vector3d>& points,
                    const std::vector<Eigen::Vector3i>& triangles) {
  std::vector<std::vector<uint32_t>> faces;
  for (const Eigen::Vector3i& triangle : triangles) {
    faces.push_back({static_cast<uint32_t>(triangle[0]),
                     static_cast<uint32_t>(triangle[1]),
                     static_cast<uint32_t>(triangle[2])});
  }
  WriteXyzPly(path, points, faces);
}

Eigen::Affine3d EstimateFromReference() {
  Eigen::Affine3d transform(Eigen::AngleAxisd(
      20.0 * M_PI / 180.0, Eigen::Vector3d(0.2, -0.1, 1.0).normalized()));
  transform.translation() = Eigen::Vector3d(2.0, -1.0, 0.5);
  return transform;
}

Eigen::Affine3d Displacement() {
  Eigen::Affine3d displacement(Eigen::AngleAxisd(
      1.5 * M_PI / 180.0, Eigen::Vector3d(1, 2, -1).normalized()));
  displacement.translation() = Eigen::Vector3d(0.08, -0.05, 0.06);
  return displacement;
}

void WriteCornerCameras(const std::string& ground_truth_poses_path,
                        const std::string& model_path) {
  const Eigen::Affine3d estimate_from_reference = EstimateFromReference();
  Rigid3d estimate_from_reference_rigid;
  estimate_from_reference_rigid.rotation =
      Eigen::Quaterniond(estimate_from_reference.linear());
  estimate_from_reference_rigid.translation =
      estimate_from_reference.translation();
  const std::vector<Eigen::Vector3d> centres = {{1, 1, 1.5},     {4, 1, 1.2},
                                                {4, 4, 1.8},     {1, 4, 1.4},
                                                {2.5, 2.5, 2.5}, {3, 2, 0.8}};
  std::vector<FramePose> ground_truth;
  Reconstruction model;
  Camera camera = Camera::FromModelName("PINHOLE", 100, 80, {80, 80, 50, 40});
  camera.camera_id = 1;
  model.cameras[1] = camera;
  for (size_t i = 0; i < centres.size(); ++i) {
    FramePose pose;
    pose.frame = "00000" + std::to_string(i);
    pose.world_from_cam.translation = centres[i];
    pose.world_from_cam.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(
        0.4 * i, Eigen::Vector3d(1, 0.5 * i, 2).normalized()));
    ground_truth.push_back(pose);
    Image image;
    image.image_id = i + 1;
    image.camera_id = 1;
    image.name = pose.frame + ".png";
    image.cam_from_world =
        (estimate_from_reference_rigid * pose.world_from_cam).Inverse();
    model.images.push_back(image);
  }
  WritePoses(ground_truth_poses_path, ground_truth);
  WriteReconstruction(model_path, model, ModelFormat::kBinary);
}

}  // namespace testing
}  // namespace colmap_lidar
