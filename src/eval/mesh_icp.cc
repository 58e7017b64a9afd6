#include "src/eval/mesh_icp.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <tuple>

#include <Eigen/Eigenvalues>
#include <pcl/common/transforms.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/search/kdtree.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "src/eval/mesh_sampling.h"

namespace colmap_lidar {
namespace {

using Cloud = pcl::PointCloud<pcl::PointNormal>;

pcl::PointNormal ToPcl(const Eigen::Vector3d& point) {
  pcl::PointNormal p;
  p.x = static_cast<float>(point.x());
  p.y = static_cast<float>(point.y());
  p.z = static_cast<float>(point.z());
  p.normal_x = p.normal_y = p.normal_z = 0.0f;
  p.curvature = 0.0f;
  return p;
}

// Unit normals of `cloud` from the plane fit of each point's k nearest
// neighbours (the eigenvector of the smallest eigenvalue of their
// covariance).
void EstimateNormals(int num_neighbors, Cloud* cloud) {
  pcl::search::KdTree<pcl::PointNormal> tree;
  tree.setInputCloud(Cloud::ConstPtr(cloud, [](Cloud*) {}));
  const int k = std::min<int>(num_neighbors, static_cast<int>(cloud->size()));
  pcl::Indices indices;
  std::vector<float> distances;
  for (pcl::PointNormal& point : cloud->points) {
    tree.nearestKSearch(point, k, indices, distances);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto index : indices) {
      mean += (*cloud)[index].getVector3fMap().cast<double>();
    }
    mean /= static_cast<double>(indices.size());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const auto index : indices) {
      const Eigen::Vector3d d =
          (*cloud)[index].getVector3fMap().cast<double>() - mean;
      covariance += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
    const Eigen::Vector3f normal = solver.eigenvectors().col(0).cast<float>();
    point.normal_x = normal.x();
    point.normal_y = normal.y();
    point.normal_z = normal.z();
  }
}

// Share of `source` points within `max_distance` of the target and the RMS
// of those distances.
std::pair<double, double> InlierStats(
    const Cloud& source, const pcl::search::KdTree<pcl::PointNormal>& tree,
    double max_distance) {
  size_t count = 0;
  double sum2 = 0.0;
  pcl::Indices indices;
  std::vector<float> distances;
  for (const pcl::PointNormal& point : source.points) {
    if (tree.nearestKSearch(point, 1, indices, distances) == 1 &&
        distances[0] <= max_distance * max_distance) {
      ++count;
      sum2 += distances[0];
    }
  }
  if (count == 0) {
    return {0.0, 0.0};
  }
  return {static_cast<double>(count) / source.size(),
          std::sqrt(sum2 / count)};
}

}  // namespace

bool MeshIcpOptions::Check() const {
  bool ok = true;
  if (method != "point_to_plane" && method != "point_to_point") {
    LOG(ERROR) << "MeshIcp.method must be point_to_plane or point_to_point, "
                  "got '"
               << method << "'";
    ok = false;
  }
  if (!(max_distance_factor > 0.0) || !std::isfinite(max_distance_factor)) {
    LOG(ERROR) << "MeshIcp.max_distance_factor must be positive, got "
               << max_distance_factor;
    ok = false;
  }
  if (num_stages < 1) {
    LOG(ERROR) << "MeshIcp.num_stages must be >= 1, got " << num_stages;
    ok = false;
  }
  if (max_num_iterations < 1) {
    LOG(ERROR) << "MeshIcp.max_num_iterations must be >= 1, got "
               << max_num_iterations;
    ok = false;
  }
  if (max_num_samples < 100) {
    LOG(ERROR) << "MeshIcp.max_num_samples must be >= 100, got "
               << max_num_samples;
    ok = false;
  }
  if (normal_num_neighbors < 3) {
    LOG(ERROR) << "MeshIcp.normal_num_neighbors must be >= 3, got "
               << normal_num_neighbors;
    ok = false;
  }
  if (seed < 0) {
    LOG(ERROR) << "MeshIcp.seed must be >= 0, got " << seed;
    ok = false;
  }
  return ok;
}

MeshIcpResult RefineMeshAlignmentIcp(
    const std::vector<Eigen::Vector3d>& vertices,
    const std::vector<Eigen::Vector3i>& triangles,
    const std::vector<Eigen::Vector3d>& reference,
    double evaluation_threshold_m, double crop_margin_m,
    const MeshIcpOptions& options) {
  THROW_CHECK(options.Check(), "Invalid MeshIcp options");
  THROW_CHECK(evaluation_threshold_m > 0.0,
              "ICP: the evaluation threshold must be positive, got "
                  << evaluation_threshold_m);
  THROW_CHECK(!vertices.empty(), "ICP: the estimate has no vertices");
  THROW_CHECK(!reference.empty(), "ICP: the reference cloud has no points");

  MeshIcpResult result;
  const double final_distance =
      options.max_distance_factor * evaluation_threshold_m;
  for (int stage = options.num_stages - 1; stage >= 0; --stage) {
    result.stage_distances_m.push_back(final_distance * std::pow(2.0, stage));
  }
  const double coarse_distance = result.stage_distances_m.front();

  // Source: mesh samples in the reference's (enlarged) box.
  std::vector<Eigen::Vector3d> samples;
  if (triangles.empty()) {
    samples = vertices;
  } else {
    const double area = TriangleMeshArea(vertices, triangles);
    THROW_CHECK(area > 0.0, "ICP: the estimate mesh has zero area");
    samples = SampleTriangleMesh(vertices, triangles,
                                 options.max_num_samples / area,
                                 static_cast<uint64_t>(options.seed));
  }
  Eigen::Vector3d reference_min = reference.front();
  Eigen::Vector3d reference_max = reference.front();
  for (const Eigen::Vector3d& point : reference) {
    reference_min = reference_min.cwiseMin(point);
    reference_max = reference_max.cwiseMax(point);
  }
  if (crop_margin_m >= 0.0) {
    const Eigen::Vector3d margin = Eigen::Vector3d::Constant(crop_margin_m);
    samples.erase(
        std::remove_if(samples.begin(), samples.end(),
                       [&](const Eigen::Vector3d& p) {
                         return (p.array() < (reference_min - margin).array())
                                    .any() ||
                                (p.array() > (reference_max + margin).array())
                                    .any();
                       }),
        samples.end());
  }
  THROW_CHECK(!samples.empty(),
              "ICP: no estimate point lies in the reference's bounding box");
  if (samples.size() > static_cast<size_t>(options.max_num_samples)) {
    std::mt19937_64 rng(static_cast<uint64_t>(options.seed) + 1);
    std::shuffle(samples.begin(), samples.end(), rng);
    samples.resize(options.max_num_samples);
  }
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d source_min = samples.front();
  Eigen::Vector3d source_max = samples.front();
  for (const Eigen::Vector3d& point : samples) {
    centre += point;
    source_min = source_min.cwiseMin(point);
    source_max = source_max.cwiseMax(point);
  }
  centre /= static_cast<double>(samples.size());
  Cloud::Ptr source(new Cloud);
  source->reserve(samples.size());
  for (const Eigen::Vector3d& point : samples) {
    source->push_back(ToPcl(point - centre));
  }

  // Target: the reference near the source's box, on a voxel grid.
  Cloud::Ptr near_reference(new Cloud);
  const Eigen::Vector3d reach = Eigen::Vector3d::Constant(coarse_distance);
  for (const Eigen::Vector3d& point : reference) {
    if ((point.array() >= (source_min - reach).array()).all() &&
        (point.array() <= (source_max + reach).array()).all()) {
      near_reference->push_back(ToPcl(point - centre));
    }
  }
  THROW_CHECK(near_reference->size() >= 3,
              "ICP: fewer than 3 reference points within "
                  << coarse_distance << " m of the estimate's box");
  Cloud::Ptr target(new Cloud);
  pcl::VoxelGrid<pcl::PointNormal> voxel_grid;
  const float leaf = static_cast<float>(final_distance / 3.0);
  voxel_grid.setLeafSize(leaf, leaf, leaf);
  voxel_grid.setInputCloud(near_reference);
  voxel_grid.filter(*target);
  if (options.method == "point_to_plane") {
    EstimateNormals(options.normal_num_neighbors, target.get());
  }
  result.num_source_points = source->size();
  result.num_target_points = target->size();

  pcl::search::KdTree<pcl::PointNormal> tree;
  tree.setInputCloud(target);
  std::tie(result.inlier_ratio_before, result.inlier_rmse_before_m) =
      InlierStats(*source, tree, final_distance);

  std::unique_ptr<pcl::IterativeClosestPoint<pcl::PointNormal,
                                             pcl::PointNormal>>
      icp;
  if (options.method == "point_to_plane") {
    icp = std::make_unique<pcl::IterativeClosestPointWithNormals<
        pcl::PointNormal, pcl::PointNormal>>();
  } else {
    icp = std::make_unique<
        pcl::IterativeClosestPoint<pcl::PointNormal, pcl::PointNormal>>();
  }
  icp->setInputSource(source);
  icp->setInputTarget(target);
  icp->setMaximumIterations(options.max_num_iterations);
  icp->setTransformationEpsilon(1e-10);
  icp->setEuclideanFitnessEpsilon(1e-12);
  Eigen::Matrix4f local = Eigen::Matrix4f::Identity();
  Cloud aligned;
  for (const double distance : result.stage_distances_m) {
    icp->setMaxCorrespondenceDistance(distance);
    icp->align(aligned, local);
    local = icp->getFinalTransformation();
  }
  result.converged = icp->hasConverged();

  Cloud moved;
  pcl::transformPointCloud(*source, moved, local);
  std::tie(result.inlier_ratio, result.inlier_rmse_m) =
      InlierStats(moved, tree, final_distance);

  // Back from the centred frame: x -> local (x - c) + c.
  Eigen::Affine3d local_d(local.cast<double>());
  local_d.linear() =
      Eigen::Quaterniond(local_d.rotation()).normalized().toRotationMatrix();
  Eigen::Affine3d refined = Eigen::Affine3d::Identity();
  refined.linear() = local_d.linear();
  refined.translation() =
      local_d.translation() + centre - local_d.linear() * centre;
  result.refined_from_aligned = refined;
  result.rotation_deg =
      Eigen::AngleAxisd(refined.linear()).angle() * 180.0 / M_PI;
  result.translation_m = local_d.translation().norm();
  LOG(INFO) << "ICP (" << options.method << "): " << FormatMeshIcpResult(result);
  if (result.translation_m > coarse_distance) {
    LOG(WARNING) << "ICP moved the mesh by " << result.translation_m
                 << " m, more than its largest correspondence distance ("
                 << coarse_distance << " m): a slide along a degenerate "
                                       "geometry?";
  }
  return result;
}

MeshIcpResult RefineMeshAlignmentIcpFiles(
    const std::string& estimate_path, const std::string& reference_path,
    const Eigen::Affine3d& reference_from_estimate,
    double evaluation_threshold_m, double crop_margin_m,
    const MeshIcpOptions& options) {
  THROW_CHECK(options.Check(), "Invalid MeshIcp options");
  CheckFileExists(estimate_path, "Estimate mesh or point cloud");
  CheckFileExists(reference_path, "Reference cloud");
  EvaluationMesh estimate = ReadEvaluationMesh(estimate_path, "Estimate");
  for (Eigen::Vector3d& vertex : estimate.vertices) {
    vertex = reference_from_estimate * vertex;
  }
  const std::vector<Eigen::Vector3d> reference =
      ReadEvaluationMesh(reference_path, "Reference cloud").vertices;
  return RefineMeshAlignmentIcp(estimate.vertices, estimate.triangles,
                                reference, evaluation_threshold_m,
                                crop_margin_m, options);
}

std::string FormatMeshIcpResult(const MeshIcpResult& result) {
  char line[512];
  std::snprintf(
      line, sizeof(line),
      "%zu mesh samples against %zu reference points, distances %g..%g m; "
      "moved by %.4f deg and %.4f m; inliers %.1f %% (rms %.4f m) -> "
      "%.1f %% (rms %.4f m)%s",
      result.num_source_points, result.num_target_points,
      result.stage_distances_m.empty() ? 0.0
                                       : result.stage_distances_m.front(),
      result.stage_distances_m.empty() ? 0.0 : result.stage_distances_m.back(),
      result.rotation_deg, result.translation_m,
      100.0 * result.inlier_ratio_before, result.inlier_rmse_before_m,
      100.0 * result.inlier_ratio, result.inlier_rmse_m,
      result.converged ? "" : " (not converged)");
  return line;
}

}  // namespace colmap_lidar
