#include "src/lidar/gicp_helpers.h"

#include <algorithm>
#include <thread>

#include <Eigen/SVD>
#include <pcl/filters/voxel_grid.h>
#include <pcl/search/kdtree.h>

namespace colmap_lidar {

int NumThreadsOrAll(int num_threads) {
  if (num_threads > 0) {
    return num_threads;
  }
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

void ParallelFor(size_t n, int num_threads,
                 const std::function<void(size_t, size_t)>& body) {
  const size_t num_chunks =
      std::min<size_t>(static_cast<size_t>(NumThreadsOrAll(num_threads)),
                       std::max<size_t>(1, n / 256));
  if (num_chunks <= 1) {
    body(0, n);
    return;
  }
  std::vector<std::thread> threads;
  for (size_t c = 0; c < num_chunks; ++c) {
    threads.emplace_back(body, n * c / num_chunks, n * (c + 1) / num_chunks);
  }
  for (std::thread& thread : threads) {
    thread.join();
  }
}

Eigen::Matrix4f ToMatrix4f(const Rigid3d& transform) {
  Eigen::Matrix4f matrix = Eigen::Matrix4f::Identity();
  matrix.topLeftCorner<3, 4>() = transform.ToMatrix().cast<float>();
  return matrix;
}

Rigid3d FromMatrix4f(const Eigen::Matrix4f& matrix) {
  return Rigid3d::FromMatrix(matrix.topLeftCorner<3, 4>().cast<double>());
}

GicpCloud::Ptr RangeFilterAndDownsample(const LidarScan& scan,
                                        double min_range_m, double max_range_m,
                                        double voxel_size_m) {
  GicpCloud::Ptr filtered(new GicpCloud);
  filtered->reserve(scan.size());
  const float min_range2 = static_cast<float>(min_range_m * min_range_m);
  const float max_range2 = static_cast<float>(max_range_m * max_range_m);
  for (const Eigen::Vector3f& point : scan.points) {
    const float range2 = point.squaredNorm();
    if (range2 >= min_range2 && range2 <= max_range2) {
      filtered->push_back(pcl::PointXYZ(point.x(), point.y(), point.z()));
    }
  }
  GicpCloud::Ptr downsampled(new GicpCloud);
  pcl::VoxelGrid<pcl::PointXYZ> voxel_grid;
  const float leaf = static_cast<float>(voxel_size_m);
  voxel_grid.setLeafSize(leaf, leaf, leaf);
  voxel_grid.setInputCloud(filtered);
  voxel_grid.filter(*downsampled);
  return downsampled;
}

GicpCovariances ComputeGicpCovariances(const GicpCloud::ConstPtr& cloud,
                                       int num_neighbors, int num_threads,
                                       std::vector<Eigen::Vector3d>* normals) {
  pcl::search::KdTree<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  GicpCovariances covariances(cloud->size());
  if (normals != nullptr) {
    normals->assign(cloud->size(), Eigen::Vector3d::UnitZ());
  }
  const int k = std::min<int>(num_neighbors, static_cast<int>(cloud->size()));
  ParallelFor(cloud->size(), num_threads, [&](size_t begin, size_t end) {
    pcl::Indices indices;
    std::vector<float> distances2;
    for (size_t i = begin; i < end; ++i) {
      tree.nearestKSearch((*cloud)[i], k, indices, distances2);
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
      for (const auto index : indices) {
        const Eigen::Vector3d p =
            (*cloud)[index].getVector3fMap().cast<double>();
        mean += p;
        second += p * p.transpose();
      }
      const double n = static_cast<double>(indices.size());
      mean /= n;
      const Eigen::Matrix3d covariance = second / n - mean * mean.transpose();
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                                  Eigen::ComputeFullU);
      const Eigen::Vector3d values(1.0, 1.0, kGicpPlaneEpsilon);
      covariances[i] =
          svd.matrixU() * values.asDiagonal() * svd.matrixU().transpose();
      if (normals != nullptr) {
        (*normals)[i] = svd.matrixU().col(2);
      }
    }
  });
  return covariances;
}

}  // namespace colmap_lidar
