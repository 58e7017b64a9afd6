// Small helpers shared by the PCL GICP users (lidar_odometry,
// scan_registration): range filter + voxel grid, per-point plane
// covariances, a parallel loop, and Rigid3d <-> PCL 4x4 matrices.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/StdVector>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {

using GicpCloud = pcl::PointCloud<pcl::PointXYZ>;
// Same type as pcl::GeneralizedIterativeClosestPoint<>::MatricesVector.
using GicpCovariances =
    std::vector<Eigen::Matrix3d, Eigen::aligned_allocator<Eigen::Matrix3d>>;

// GICP's regularisation of a point's covariance: eigenvalues (1, 1, eps),
// i.e. the point is a sample of a plane (Segal et al., "plane-to-plane").
constexpr double kGicpPlaneEpsilon = 1e-3;

// num_threads > 0, else all cores (at least 1).
int NumThreadsOrAll(int num_threads);

// Calls body(begin, end) on contiguous chunks of [0, n) on up to
// `num_threads` threads (<= 0: all cores). `body` must only write to its
// own indices.
void ParallelFor(size_t n, int num_threads,
                 const std::function<void(size_t, size_t)>& body);

Eigen::Matrix4f ToMatrix4f(const Rigid3d& transform);
Rigid3d FromMatrix4f(const Eigen::Matrix4f& matrix);

// Points of `scan` (LIDAR frame) with min_range_m <= range <= max_range_m,
// then a voxel grid of edge voxel_size_m (centroid per voxel), in the LIDAR
// frame.
GicpCloud::Ptr RangeFilterAndDownsample(const LidarScan& scan,
                                        double min_range_m, double max_range_m,
                                        double voxel_size_m);

// Per-point GICP covariances of `cloud` in its own frame, from its
// `num_neighbors` nearest neighbours: the local plane, eigenvalues
// (1, 1, kGicpPlaneEpsilon). When `normals` is not null it receives the
// unit normal (smallest eigenvector) of each point's neighbourhood.
GicpCovariances ComputeGicpCovariances(
    const GicpCloud::ConstPtr& cloud, int num_neighbors, int num_threads,
    std::vector<Eigen::Vector3d>* normals = nullptr);

}  // namespace colmap_lidar
