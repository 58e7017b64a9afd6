// Nearest-neighbour distances for the evaluators, exact: to a point set and
// to a triangle mesh (exact point-to-triangle distance, as CloudCompare's
// cloud-to-mesh distance). Both use Embree BVH point queries (fast also for
// queries far from the data, where a kd-tree over surface-like clouds
// degrades badly) and run the queries on all cores.
//
// Precision: the search structures hold single-precision coordinates
// relative to the centroid of the indexed data (so that georeferenced
// coordinates such as UTM keep millimetre resolution); the returned
// distances are recomputed in double precision from the original
// coordinates.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {

// Exact Euclidean distance from `point` to the triangle abc (its interior,
// edges or vertices; a degenerate triangle acts as a segment or a point).
double PointTriangleDistance(const Eigen::Vector3d& point,
                             const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c);

// Exact Euclidean distance from `point` to the segment [a, b].
double PointSegmentDistance(const Eigen::Vector3d& point,
                            const Eigen::Vector3d& a,
                            const Eigen::Vector3d& b);

class PointCloudIndex {
 public:
  // Throws colmap_lidar::Error when `points` is empty.
  explicit PointCloudIndex(const std::vector<Eigen::Vector3d>& points);
  ~PointCloudIndex();

  size_t NumPoints() const { return points_.size(); }
  // Distance of each query to its nearest indexed point.
  std::vector<double> NearestDistances(
      const std::vector<Eigen::Vector3d>& queries) const;

 private:
  struct Impl;
  std::vector<Eigen::Vector3d> points_;
  std::unique_ptr<Impl> impl_;
};

class TriangleMeshIndex {
 public:
  // Throws colmap_lidar::Error when there are no triangles or an index is
  // out of range.
  TriangleMeshIndex(const std::vector<Eigen::Vector3d>& vertices,
                    const std::vector<Eigen::Vector3i>& triangles);
  ~TriangleMeshIndex();

  // Distance of each query to the closest point of the mesh surface.
  std::vector<double> NearestDistances(
      const std::vector<Eigen::Vector3d>& queries) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace colmap_lidar
