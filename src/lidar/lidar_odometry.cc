#include "src/lidar/lidar_odometry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include <glog/logging.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/common/transforms.h>
#include <pcl/registration/ndt.h>
#include <pcl/search/kdtree.h>

#include "colmap_ext/util/logging.h"
#include "src/lidar/gicp_helpers.h"

namespace colmap_lidar {
namespace {

using Cloud = GicpCloud;
using KdTree = pcl::search::KdTree<pcl::PointXYZ>;
using Gicp = pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>;
using Covariances = GicpCovariances;

// Fewer points than this after filtering: not a usable scan.
constexpr size_t kMinNumPoints = 10;

// Range filter and voxel grid, in the LIDAR frame.
Cloud::Ptr Downsample(const LidarScan& scan,
                      const LidarOdometryOptions& options) {
  return RangeFilterAndDownsample(scan, options.min_range_m,
                                  options.max_range_m, options.voxel_size_m);
}

// Per-point GICP covariances of `cloud` in its own frame.
Covariances ComputeCovariances(const Cloud::ConstPtr& cloud, int num_neighbors,
                               int num_threads) {
  return ComputeGicpCovariances(cloud, num_neighbors, num_threads);
}

}  // namespace

// One registered scan of the local map, in the world frame.
struct LidarOdometry::MapScan {
  Cloud::Ptr points_in_world;
  Covariances covariances_in_world;
};

bool LidarOdometryOptions::Check() const {
  if (method != "gicp" && method != "ndt") {
    LOG(ERROR) << "LidarOdometry.method must be gicp or ndt, not '" << method
               << "'";
    return false;
  }
  if (!(voxel_size_m > 0)) {
    LOG(ERROR) << "LidarOdometry.voxel_size_m must be > 0";
    return false;
  }
  if (!(min_range_m >= 0) || !(max_range_m > min_range_m)) {
    LOG(ERROR) << "LidarOdometry.min_range_m / max_range_m: need "
                  "0 <= min_range_m < max_range_m";
    return false;
  }
  if (local_map_num_scans < 1) {
    LOG(ERROR) << "LidarOdometry.local_map_num_scans must be >= 1";
    return false;
  }
  if (!(max_correspondence_distance_m > 0)) {
    LOG(ERROR) << "LidarOdometry.max_correspondence_distance_m must be > 0";
    return false;
  }
  if (max_iterations < 1) {
    LOG(ERROR) << "LidarOdometry.max_iterations must be >= 1";
    return false;
  }
  if (!(transformation_epsilon > 0)) {
    LOG(ERROR) << "LidarOdometry.transformation_epsilon must be > 0";
    return false;
  }
  if (gicp_num_neighbors < 3) {
    LOG(ERROR) << "LidarOdometry.gicp_num_neighbors must be >= 3";
    return false;
  }
  if (!(ndt_resolution_m > 0) || !(ndt_step_size > 0)) {
    LOG(ERROR) << "LidarOdometry.ndt_resolution_m and ndt_step_size must be "
                  "> 0";
    return false;
  }
  if (!(min_overlap >= 0 && min_overlap <= 1)) {
    LOG(ERROR) << "LidarOdometry.min_overlap must be in [0, 1]";
    return false;
  }
  return true;
}

LidarOdometry::LidarOdometry(const LidarOdometryOptions& options,
                             const Rigid3d& world_from_first_lidar)
    : options_(options), world_from_first_lidar_(world_from_first_lidar) {
  THROW_CHECK(options_.Check(), "invalid LidarOdometry options");
}

LidarOdometry::~LidarOdometry() = default;

LidarOdometryFrame LidarOdometry::AddScan(const LidarScan& scan,
                                          const std::string& frame_name) {
  const auto start = std::chrono::steady_clock::now();
  const Cloud::Ptr points_in_lidar = Downsample(scan, options_);
  THROW_CHECK(points_in_lidar->size() >= kMinNumPoints,
              "LIDAR odometry, frame " << frame_name << ": only "
                                       << points_in_lidar->size()
                                       << " points left after the range "
                                          "filter and the voxel grid");
  const bool use_gicp = options_.method == "gicp";
  auto covariances_in_lidar = std::make_shared<Covariances>();
  if (use_gicp) {
    *covariances_in_lidar = ComputeCovariances(
        points_in_lidar, options_.gicp_num_neighbors, options_.num_threads);
  }

  LidarOdometryFrame frame;
  frame.num_points = points_in_lidar->size();
  if (poses_.empty()) {
    frame.world_from_lidar = world_from_first_lidar_;
  } else {
    // Constant velocity: the last frame-to-frame motion once more.
    Rigid3d prediction = poses_.back();
    if (poses_.size() >= 2) {
      const Rigid3d previous_from_current =
          poses_[poses_.size() - 2].Inverse() * poses_.back();
      prediction = poses_.back() * previous_from_current;
    }

    Cloud::Ptr map(new Cloud);
    auto map_covariances = std::make_shared<Covariances>();
    for (const auto& map_scan : local_map_) {
      *map += *map_scan->points_in_world;
      map_covariances->insert(map_covariances->end(),
                              map_scan->covariances_in_world.begin(),
                              map_scan->covariances_in_world.end());
    }
    KdTree::Ptr map_tree(new KdTree);
    map_tree->setInputCloud(map);

    Cloud aligned;
    Eigen::Matrix4f world_from_lidar;
    if (use_gicp) {
      Gicp gicp;
      gicp.setInputSource(points_in_lidar);
      gicp.setSourceCovariances(covariances_in_lidar);
      gicp.setInputTarget(map);
      gicp.setTargetCovariances(map_covariances);
      gicp.setSearchMethodTarget(map_tree, /*force_no_recompute=*/true);
      gicp.setMaxCorrespondenceDistance(options_.max_correspondence_distance_m);
      gicp.setMaximumIterations(options_.max_iterations);
      gicp.setTransformationEpsilon(options_.transformation_epsilon);
      gicp.setRotationEpsilon(options_.transformation_epsilon);
      gicp.align(aligned, ToMatrix4f(prediction));
      frame.converged = gicp.hasConverged();
      world_from_lidar = gicp.getFinalTransformation();
    } else {
      pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ> ndt;
      ndt.setResolution(static_cast<float>(options_.ndt_resolution_m));
      ndt.setStepSize(options_.ndt_step_size);
      ndt.setMaximumIterations(options_.max_iterations);
      ndt.setTransformationEpsilon(options_.transformation_epsilon);
      ndt.setInputSource(points_in_lidar);
      ndt.setInputTarget(map);
      ndt.align(aligned, ToMatrix4f(prediction));
      frame.converged = ndt.hasConverged();
      world_from_lidar = ndt.getFinalTransformation();
    }
    frame.world_from_lidar = FromMatrix4f(world_from_lidar);

    // Overlap and residual against the map, from our own nearest
    // neighbours so that both methods are judged alike.
    Cloud points_in_world;
    pcl::transformPointCloud(*points_in_lidar, points_in_world,
                             world_from_lidar);
    const double max_distance2 = options_.max_correspondence_distance_m *
                                 options_.max_correspondence_distance_m;
    std::vector<float> nearest_distance2(points_in_world.size());
    ParallelFor(points_in_world.size(), options_.num_threads,
                [&](size_t begin, size_t end) {
                  pcl::Indices indices(1);
                  std::vector<float> distances2(1);
                  for (size_t i = begin; i < end; ++i) {
                    map_tree->nearestKSearch(points_in_world[i], 1, indices,
                                             distances2);
                    nearest_distance2[i] = distances2[0];
                  }
                });
    size_t num_inliers = 0;
    double sum_distance2 = 0;
    for (const float distance2 : nearest_distance2) {
      if (distance2 <= max_distance2) {
        ++num_inliers;
        sum_distance2 += distance2;
      }
    }
    frame.overlap = static_cast<double>(num_inliers) / points_in_world.size();
    frame.rmse_m = num_inliers > 0 ? std::sqrt(sum_distance2 / num_inliers) : 0;
    const bool finite = world_from_lidar.allFinite();
    if (!finite || frame.overlap < options_.min_overlap) {
      std::ostringstream message;
      message << "LIDAR odometry, frame " << frame_name
              << ": registration failed (overlap " << frame.overlap
              << " < LidarOdometry.min_overlap " << options_.min_overlap
              << ", converged " << frame.converged << ")";
      THROW_CHECK(!options_.abort_on_failure,
                  message.str() << "; set LidarOdometry.abort_on_failure 0 to "
                                   "keep the constant-velocity prediction");
      LOG(WARNING) << message.str() << "; keeping the constant-velocity "
                                       "prediction";
      frame.world_from_lidar = prediction;
      frame.registered = false;
    } else if (!frame.converged) {
      LOG(WARNING) << "LIDAR odometry, frame " << frame_name
                   << ": registration did not converge in "
                   << options_.max_iterations << " iterations (overlap "
                   << frame.overlap << ")";
    }
  }

  poses_.push_back(frame.world_from_lidar);
  // A failed registration is not added to the map: its points would be
  // misplaced and pull the next frames.
  if (frame.registered) {
    auto map_scan = std::make_shared<MapScan>();
    map_scan->points_in_world.reset(new Cloud);
    pcl::transformPointCloud(*points_in_lidar, *map_scan->points_in_world,
                             ToMatrix4f(frame.world_from_lidar));
    if (use_gicp) {
      // Covariances rotate with their points: C_world = R C_lidar R^T.
      const Eigen::Matrix3d rotation =
          frame.world_from_lidar.rotation.toRotationMatrix();
      map_scan->covariances_in_world.reserve(covariances_in_lidar->size());
      for (const Eigen::Matrix3d& covariance : *covariances_in_lidar) {
        map_scan->covariances_in_world.push_back(rotation * covariance *
                                                 rotation.transpose());
      }
    }
    local_map_.push_back(map_scan);
    while (local_map_.size() > static_cast<size_t>(options_.local_map_num_scans)) {
      local_map_.pop_front();
    }
  }
  frame.seconds = std::chrono::duration<double>(
                      std::chrono::steady_clock::now() - start)
                      .count();
  return frame;
}

std::vector<LidarOdometryFrame> RunLidarOdometry(
    const std::vector<LidarScan>& scans,
    const std::vector<std::string>& frame_names,
    const LidarOdometryOptions& options,
    const Rigid3d& world_from_first_lidar) {
  THROW_CHECK(frame_names.empty() || frame_names.size() == scans.size(),
              "RunLidarOdometry: " << frame_names.size() << " names for "
                                   << scans.size() << " scans");
  LidarOdometry odometry(options, world_from_first_lidar);
  std::vector<LidarOdometryFrame> frames;
  frames.reserve(scans.size());
  for (size_t i = 0; i < scans.size(); ++i) {
    frames.push_back(odometry.AddScan(
        scans[i], frame_names.empty() ? "frame " + std::to_string(i)
                                      : frame_names[i]));
  }
  return frames;
}

}  // namespace colmap_lidar
