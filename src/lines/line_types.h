// Value types of the line detection module (paper section III-B): a 2D
// line segment detected in an image and a view's 3D line segment, i.e. a 2D
// segment lifted to 3D with LIDAR edge points.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {

// LBD descriptor: 256 bits as OpenCV's BinaryDescriptor computes it.
using LbdDescriptor = std::array<uint8_t, 32>;

// A 2D segment in pixels with COLMAP's convention (the centre of the
// upper-left pixel is (0.5, 0.5)).
struct LineSegment2D {
  Eigen::Vector2d start = Eigen::Vector2d::Zero();
  Eigen::Vector2d end = Eigen::Vector2d::Zero();

  double Length() const { return (end - start).norm(); }
  // Unit direction from start to end; undefined for a zero-length segment.
  Eigen::Vector2d Direction() const { return (end - start).normalized(); }
};

// A 3D line segment of one view: the 2D segment it was detected as, its 3D
// endpoints in the camera frame (metres; the back-projections of the 2D
// endpoints onto the 3D line fitted to LIDAR edge points) and the support.
struct ViewLineSegment {
  LineSegment2D segment2D;
  Eigen::Vector3d start3D_in_cam = Eigen::Vector3d::Zero();
  Eigen::Vector3d end3D_in_cam = Eigen::Vector3d::Zero();
  // Indices into the scan of the LIDAR edge points that are RANSAC inliers
  // (increasing), and their positions as used for the fit (camera frame;
  // refined along their ring, see EdgeAssociationOptions). Same size.
  std::vector<int> inlier_point_idxs;
  std::vector<Eigen::Vector3d> inlier_points_in_cam;
  LbdDescriptor descriptor{};

  int NumInliers() const { return static_cast<int>(inlier_point_idxs.size()); }
  Eigen::Vector3d Direction3D() const {
    return (end3D_in_cam - start3D_in_cam).normalized();
  }
};

}  // namespace colmap_lidar
