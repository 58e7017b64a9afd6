#include "src/lidar/lidar_test_scene.h"

#include <Eigen/Geometry>

namespace colmap_lidar {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

double RotationErrorDeg(const Rigid3d& a, const Rigid3d& b) {
  return a.rotation.angularDistance(b.rotation) * 180.0 / kPi;
}

Rigid3d PoseFromYawRoll(double yaw_deg, double roll_deg,
                        const Eigen::Vector3d& t) {
  return Rigid3d(Eigen::Quaterniond(
                     Eigen::AngleAxisd(yaw_deg * kPi / 180,
                                       Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(roll_deg * kPi / 180,
                                       Eigen::Vector3d::UnitX())),
                 t);
}

void SampleRectangle(const Eigen::Vector3d& origin, const Eigen::Vector3d& u,
                     const Eigen::Vector3d& v, double points_per_m2,
                     std::mt19937* rng, std::vector<Eigen::Vector3d>* points) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int n = static_cast<int>(u.cross(v).norm() * points_per_m2);
  for (int i = 0; i < n; ++i) {
    points->push_back(origin + unit(*rng) * u + unit(*rng) * v);
  }
}

void SampleBox(const Eigen::Vector3d& min, const Eigen::Vector3d& size,
               double points_per_m2, std::mt19937* rng,
               std::vector<Eigen::Vector3d>* points) {
  const Eigen::Vector3d ex(size.x(), 0, 0), ey(0, size.y(), 0),
      ez(0, 0, size.z());
  SampleRectangle(min, ex, ez, points_per_m2, rng, points);
  SampleRectangle(min + ey, ex, ez, points_per_m2, rng, points);
  SampleRectangle(min, ey, ez, points_per_m2, rng, points);
  SampleRectangle(min + ex, ey, ez, points_per_m2, rng, points);
  SampleRectangle(min + ez, ex, ey, points_per_m2, rng, points);
}

std::vector<Eigen::Vector3d> SampleStreetScene(unsigned seed,
                                               double points_per_m2) {
  std::mt19937 rng(seed);
  std::vector<Eigen::Vector3d> points;
  const double density = points_per_m2;
  SampleRectangle({-25, -25, -1.7}, {50, 0, 0}, {0, 50, 0}, density, &rng,
                  &points);
  SampleRectangle({-25, 12, -1.7}, {50, 0, 0}, {0, 0, 8}, density, &rng,
                  &points);
  SampleRectangle({-25, -10, -1.7}, {30, 0, 0}, {0, 0, 6}, density, &rng,
                  &points);
  SampleRectangle({22, -25, -1.7}, {0, 50, 0}, {0, 0, 7}, density, &rng,
                  &points);
  SampleRectangle({-5, -9, -1.7}, {10, 0, 0}, {0, 4, 3}, density, &rng,
                  &points);
  SampleBox({6, 3, -1.7}, {2, 4, 1.5}, density, &rng, &points);
  SampleBox({-8, 5, -1.7}, {1.5, 1.5, 3}, density, &rng, &points);
  SampleBox({12, -6, -1.7}, {3, 1, 2}, density, &rng, &points);
  SampleBox({-15, -4, -1.7}, {0.5, 0.5, 4}, density, &rng, &points);
  return points;
}

}  // namespace colmap_lidar
