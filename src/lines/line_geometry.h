// Small 3D line helpers shared by the line detection stages: least-squares
// line fit, point-line distance, and the back-projection of a pixel onto a
// 3D line (the endpoint rule of section III-B).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/camera.h"

namespace colmap_lidar {

// An infinite 3D line: a point on it and a unit direction.
struct Line3 {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
};

// Total least squares (PCA) fit through points[idxs] (all points when idxs
// is empty); needs at least two distinct points, else throws.
Line3 FitLineLeastSquares(const std::vector<Eigen::Vector3d>& points,
                          const std::vector<int>& idxs = {});

double DistanceToLine(const Line3& line, const Eigen::Vector3d& point);

// Unit normal of the viewing plane of a 2D segment: the plane through the
// camera centre (origin of the camera frame) and the segment's rays.
Eigen::Vector3d ViewingPlaneNormal(const Camera& camera,
                                   const Eigen::Vector2d& start,
                                   const Eigen::Vector2d& end);

// Least-squares line through points[idxs] after projecting them onto the
// viewing plane with normal `plane_normal` (through the origin): the image
// fixes the line's plane to sub-pixel precision, the LIDAR points fix the
// line within it. Needs two distinct projected points, else throws.
Line3 FitLineInPlane(const std::vector<Eigen::Vector3d>& points,
                     const std::vector<int>& idxs,
                     const Eigen::Vector3d& plane_normal);

// Signed coordinate of the point's projection along the line.
inline double LineCoordinate(const Line3& line, const Eigen::Vector3d& point) {
  return line.direction.dot(point - line.point);
}

// The point of `line` (camera frame) closest to the viewing ray of `pixel`.
// Returns false when the ray and the line make an angle below
// min_angle_deg (the intersection is ill-conditioned) or when the point is
// not in front of the camera (z <= 0).
bool BackProjectOntoLine(const Camera& camera, const Eigen::Vector2d& pixel,
                         const Line3& line, double min_angle_deg,
                         Eigen::Vector3d* point_in_cam);

// Distance in pixels from `pixel` to the infinite 2D line through a and b.
double DistanceToLine2D(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                        const Eigen::Vector2d& pixel);

}  // namespace colmap_lidar
