// The mesh against the LIDAR points (see real_data_evaluator.h).
#include "src/eval/real_data_evaluator.h"

#include <algorithm>

#include "colmap_ext/util/logging.h"
#include "src/eval/eval_stats.h"
#include "src/eval/mesh_sampling.h"
#include "src/eval/nearest_neighbor.h"

namespace colmap_lidar {

MeshVsLidar EvaluateMeshVsLidar(const std::vector<Eigen::Vector3d>& vertices,
                                const std::vector<Eigen::Vector3i>& triangles,
                                const std::vector<Eigen::Vector3d>& lidar_points,
                                const RealDataEvaluationOptions& options,
                                const std::vector<bool>& in_view) {
  THROW_CHECK(options.Check(), "invalid RealDataEvaluation options");
  THROW_CHECK(in_view.empty() || in_view.size() == lidar_points.size(),
              "Mesh vs LIDAR: " << in_view.size() << " view flags for "
                                << lidar_points.size() << " points");
  THROW_CHECK(!triangles.empty(), "Mesh vs LIDAR: the mesh has no triangles");
  THROW_CHECK(!lidar_points.empty(), "Mesh vs LIDAR: no LIDAR points");
  MeshVsLidar result;
  result.thresholds_m = options.mesh_thresholds_m;
  result.num_lidar_points = lidar_points.size();
  result.mesh_area_m2 = TriangleMeshArea(vertices, triangles);
  const double density =
      std::min(options.mesh_sample_density_per_m2,
               result.mesh_area_m2 > 0.0
                   ? options.max_mesh_samples / result.mesh_area_m2
                   : options.mesh_sample_density_per_m2);
  const std::vector<Eigen::Vector3d> samples =
      SampleTriangleMesh(vertices, triangles, density,
                         static_cast<uint64_t>(options.seed));
  result.num_mesh_samples = samples.size();
  const std::vector<double> lidar_to_mesh =
      TriangleMeshIndex(vertices, triangles).NearestDistances(lidar_points);
  std::vector<double> mesh_to_lidar;
  if (!samples.empty()) {
    mesh_to_lidar = PointCloudIndex(lidar_points).NearestDistances(samples);
  }
  std::vector<double> in_view_to_mesh;
  for (size_t i = 0; i < in_view.size(); ++i) {
    if (in_view[i]) in_view_to_mesh.push_back(lidar_to_mesh[i]);
  }
  result.num_lidar_points_in_view = in_view_to_mesh.size();
  for (const double threshold : result.thresholds_m) {
    result.lidar_within.push_back(ShareBelow(lidar_to_mesh, threshold));
    result.mesh_within.push_back(ShareBelow(mesh_to_lidar, threshold));
    if (!in_view.empty()) {
      result.lidar_in_view_within.push_back(
          ShareBelow(in_view_to_mesh, threshold));
    }
  }
  return result;
}

std::vector<bool> InCameraView(const Reconstruction& model,
                               const std::vector<Eigen::Vector3d>& points,
                               double max_depth_m) {
  std::vector<bool> in_view(points.size(), false);
  for (const Image& image : model.images) {
    const auto camera = model.cameras.find(image.camera_id);
    if (camera == model.cameras.end()) continue;
    const double width = static_cast<double>(camera->second.width);
    const double height = static_cast<double>(camera->second.height);
    for (size_t i = 0; i < points.size(); ++i) {
      if (in_view[i]) continue;
      const Eigen::Vector3d point_in_cam = image.cam_from_world * points[i];
      if (!(point_in_cam.z() > 0.0 && point_in_cam.z() <= max_depth_m)) {
        continue;
      }
      const Eigen::Vector2d pixel = camera->second.ImgFromCam(point_in_cam);
      in_view[i] = pixel.x() >= 0.0 && pixel.x() < width && pixel.y() >= 0.0 &&
                   pixel.y() < height;
    }
  }
  return in_view;
}

}  // namespace colmap_lidar
