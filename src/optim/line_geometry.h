// Geometry of infinite 3D lines for the line bundle adjustment (paper
// section III-D): Pluecker coordinates, the orthonormal representation of
// Bartoli & Sturm ("Structure-from-motion using lines: representation,
// triangulation and bundle adjustment", CVIU 2005), projection into images
// and point-to-line distances.
//
// Conventions. A Pluecker vector is (d, m): direction d and moment
// m = p x d for any point p of the line; it is defined up to a non-zero
// scale and satisfies d . m = 0. "Normalised" means |d| = 1, so that |m| is
// the distance of the line to the origin.
//
// The orthonormal representation stores a line as (U, W), U in SO(3),
// W in SO(2), with (m, d) ~ (w1 u1, w2 u2) where u1, u2 are the first two
// columns of U and (w1, w2) = (cos phi, sin phi) the first column of W:
// u1 = m / |m|, u2 = d / |d|, u3 = u1 x u2 and (w1, w2) ~ (|m|, |d|). It is
// stored as 6 doubles [qx, qy, qz, qw, w1, w2]: U as a unit quaternion in
// Eigen's memory order, then W's first column. It has 4 degrees of freedom
// (line_manifold.h).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/rigid3.h"

namespace colmap_lidar {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Number of doubles of the orthonormal representation and its layout.
constexpr int kLineOrthonormalSize = 6;
constexpr int kLineQuaternionOffset = 0;  // qx, qy, qz, qw
constexpr int kLineWOffset = 4;           // w1 = cos(phi), w2 = sin(phi)

// Pluecker vector of the line through a and b (direction b - a, not
// normalised). a == b gives a zero vector.
Vector6d PluckerFromPoints(const Eigen::Vector3d& a, const Eigen::Vector3d& b);
// Pluecker vector of the line through `point` with `direction`.
Vector6d PluckerFromPointAndDirection(const Eigen::Vector3d& point,
                                      const Eigen::Vector3d& direction);

// Scales to |d| = 1 and removes the component of m along d (Klein
// constraint). Throws colmap_lidar::Error when |d| is zero or not finite.
Vector6d NormalizePlucker(const Vector6d& plucker);

// Pluecker (any scale, |d| > 0) -> orthonormal [q, w]. For a line through
// the origin (m = 0) u1 is any unit vector orthogonal to d. Throws
// colmap_lidar::Error when |d| is zero.
Vector6d PluckerToOrthonormal(const Vector6d& plucker);
// Orthonormal -> normalised Pluecker (|d| = 1). Throws when w2 = 0 (a line
// at infinity).
Vector6d OrthonormalToPlucker(const Vector6d& orthonormal);

// The same as OrthonormalToPlucker without normalisation, for cost
// functors: d = w2 u2, m = w1 u1, (d, m) up to scale. The quaternion must
// be unit (the manifold keeps it so).
template <typename T>
void OrthonormalToPluckerUnnormalized(const T* orthonormal, T* direction,
                                      T* moment) {
  const Eigen::Map<const Eigen::Quaternion<T>> rotation(
      orthonormal + kLineQuaternionOffset);
  const Eigen::Matrix<T, 3, 3> u = rotation.toRotationMatrix();
  const T w1 = orthonormal[kLineWOffset];
  const T w2 = orthonormal[kLineWOffset + 1];
  for (int i = 0; i < 3; ++i) {
    moment[i] = w1 * u(i, 0);
    direction[i] = w2 * u(i, 1);
  }
}

// Pluecker vector in frame b from one in frame a, x_b = R x_a + t:
// d_b = R d_a, m_b = R m_a + t x d_b. Works for any scale.
Vector6d TransformPlucker(const Rigid3d& b_from_a, const Vector6d& plucker_in_a);

// Point of the line closest to the origin: d x m / |d|^2.
Eigen::Vector3d PluckerClosestPointToOrigin(const Vector6d& plucker);
// Coordinate of the orthogonal projection of `point` on the line, along
// d / |d|, measured from PluckerClosestPointToOrigin.
double PluckerLineCoordinate(const Vector6d& plucker,
                             const Eigen::Vector3d& point);
// Point at that coordinate.
Eigen::Vector3d PluckerPointAt(const Vector6d& plucker, double coordinate);
// Euclidean distance of a 3D point to the line: |p x d - m| / |d|.
double PointToPluckerLineDistance(const Vector6d& plucker,
                                  const Eigen::Vector3d& point);

// Coordinate (as PluckerLineCoordinate) of the point of the line closest to
// the ray origin + s * ray_direction (s > 0). Returns false when the ray is
// within ~0.1 deg of parallel to the line or the closest point of the ray
// is behind its origin.
bool ClosestLineCoordinateToRay(const Vector6d& plucker,
                                const Eigen::Vector3d& ray_origin,
                                const Eigen::Vector3d& ray_direction,
                                double* coordinate);

// Projection of a 3D line given in the camera frame into the image, as the
// homogeneous image line l (l . (x, y, 1) = 0) in *undistorted* pixels:
// l ~ K^-T m_cam, with K from the model's focal lengths and principal
// point (the line in normalised coordinates is m_cam itself). Exact for
// pinhole-like models (SIMPLE_PINHOLE, PINHOLE). A straight 3D line is a
// curve in a distorted image, so for the other models observations must be
// undistorted first (UndistortPixel) and distances are measured in the
// undistorted image with the same focal length: this is how the line
// residual (cost_functions.h) handles every model.
Eigen::Vector3d ProjectPluckerToImageLine(const Camera& camera,
                                          const Vector6d& plucker_in_cam);
// Pixel -> undistorted pixel K * CamFromImg(pixel); identity for pinhole
// models.
Eigen::Vector2d UndistortPixel(const Camera& camera,
                               const Eigen::Vector2d& pixel);
// Signed distance of a point to the image line l (same units as the
// point): l . (x, y, 1) / |(l0, l1)|.
double ImageLinePointDistance(const Eigen::Vector3d& line,
                              const Eigen::Vector2d& point);

// Viewing plane (n, c) with n . x + c = 0, |n| = 1, in the world frame, of
// an observed 2D segment: the plane through the camera centre and the
// segment (endpoints undistorted).
Eigen::Vector4d ViewingPlaneInWorld(const Camera& camera,
                                    const Rigid3d& cam_from_world,
                                    const Eigen::Vector2d& start2D,
                                    const Eigen::Vector2d& end2D);
// Intersection line of two planes (n . x + c = 0), as Pluecker
// (n1 x n2, c1 n2 - c2 n1), not normalised; zero direction when parallel.
Vector6d IntersectPlanes(const Eigen::Vector4d& plane1,
                         const Eigen::Vector4d& plane2);

}  // namespace colmap_lidar
