// Point samples of simple structured scenes for the LIDAR registration
// tests (odometry, pairwise registration, pose graph): planar patches drawn
// uniformly at random, freshly per call, so that two scans of one scene
// never share a point, as with a real sensor. World frame, metres.
#pragma once

#include <random>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/rigid3.h"

namespace colmap_lidar {

// Angle of a.rotation^-1 * b.rotation, degrees.
double RotationErrorDeg(const Rigid3d& a, const Rigid3d& b);

// Rotation by yaw about z, then roll about x (degrees), and translation t.
Rigid3d PoseFromYawRoll(double yaw_deg, double roll_deg,
                        const Eigen::Vector3d& t);

// Uniform samples on the rectangle origin + [0,1] u + [0,1] v, about
// points_per_m2 per square metre, appended to `points`.
void SampleRectangle(const Eigen::Vector3d& origin, const Eigen::Vector3d& u,
                     const Eigen::Vector3d& v, double points_per_m2,
                     std::mt19937* rng, std::vector<Eigen::Vector3d>* points);

// The four sides and the top of the axis-aligned box [min, min + size].
void SampleBox(const Eigen::Vector3d& min, const Eigen::Vector3d& size,
               double points_per_m2, std::mt19937* rng,
               std::vector<Eigen::Vector3d>* points);

// A street-like scene: ground at z = -1.7, facades, boxes and a ramp; the
// ramp and the box faces pin down all six degrees of freedom of a
// registration.
std::vector<Eigen::Vector3d> SampleStreetScene(unsigned seed,
                                               double points_per_m2);

}  // namespace colmap_lidar
