#include "src/mvs/mvs_test_scene.h"

#include <cmath>
#include <limits>

namespace colmap_lidar {
namespace {

float Hash01(uint32_t seed, int64_t i, int64_t j) {
  uint64_t x = (static_cast<uint64_t>(seed) << 40) ^
               (static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ull) ^
               (static_cast<uint64_t>(j) * 0xC2B2AE3D27D4EB4Full);
  x ^= x >> 31;
  x *= 0xBF58476D1CE4E5B9ull;
  x ^= x >> 29;
  x *= 0x94D049BB133111EBull;
  x ^= x >> 32;
  return static_cast<float>(x & 0xFFFFFF) / 16777216.0f;
}

float ValueNoise(uint32_t seed, double u, double v) {
  const double fu = std::floor(u);
  const double fv = std::floor(v);
  const int64_t i = static_cast<int64_t>(fu);
  const int64_t j = static_cast<int64_t>(fv);
  const float a = static_cast<float>(u - fu);
  const float b = static_cast<float>(v - fv);
  const float sa = a * a * (3 - 2 * a);
  const float sb = b * b * (3 - 2 * b);
  const float v00 = Hash01(seed, i, j), v10 = Hash01(seed, i + 1, j);
  const float v01 = Hash01(seed, i, j + 1), v11 = Hash01(seed, i + 1, j + 1);
  return (v00 * (1 - sa) + v10 * sa) * (1 - sb) + (v01 * (1 - sa) + v11 * sa) * sb;
}

float Texture(const TexturedPlane& plane, double u, double v) {
  const double s = 1.0 / plane.texture_cell_m;
  return 0.15f + 0.5f * ValueNoise(plane.texture_seed, u * s, v * s) +
         0.3f * ValueNoise(plane.texture_seed + 1, u * s * 0.37, v * s * 0.37);
}

}  // namespace

bool PlaneScene::Intersect(const Eigen::Vector3d& origin,
                           const Eigen::Vector3d& direction, double* t,
                           Eigen::Vector3d* normal, float* intensity) const {
  double best = std::numeric_limits<double>::infinity();
  for (const TexturedPlane& plane : planes) {
    const Eigen::Vector3d n = plane.u_axis.cross(plane.v_axis);
    const double denominator = n.dot(direction);
    if (std::abs(denominator) < 1e-12) continue;
    const double hit = n.dot(plane.origin - origin) / denominator;
    if (!(hit > 1e-9) || hit >= best) continue;
    const Eigen::Vector3d local = origin + hit * direction - plane.origin;
    const double u = local.dot(plane.u_axis);
    const double v = local.dot(plane.v_axis);
    if (u < plane.u_min || u > plane.u_max || v < plane.v_min || v > plane.v_max) {
      continue;
    }
    if (plane.has_hole && u > plane.hole_u_min && u < plane.hole_u_max &&
        v > plane.hole_v_min && v < plane.hole_v_max) {
      continue;
    }
    best = hit;
    if (normal) *normal = denominator < 0 ? n : Eigen::Vector3d(-n);
    if (intensity) *intensity = Texture(plane, u, v);
  }
  if (!std::isfinite(best)) return false;
  if (t) *t = best;
  return true;
}

MvsView PlaneScene::Render(const std::string& name, const Eigen::Matrix3d& K,
                           const Rigid3d& cam_from_world, int width, int height,
                           std::vector<float>* gt_depth) const {
  const Eigen::Matrix3d K_inv = K.inverse();
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const Eigen::Matrix3d R = world_from_cam.rotation.toRotationMatrix();
  const Eigen::Vector3d center = world_from_cam.translation;
  std::vector<float> gray(static_cast<size_t>(width) * height, 0.0f);
  if (gt_depth) gt_depth->assign(gray.size(), 0.0f);
  static constexpr double kSub[2] = {-0.25, 0.25};
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      float sum = 0.0f;
      for (double dy : kSub) {
        for (double dx : kSub) {
          const Eigen::Vector3d ray = K_inv * Eigen::Vector3d(col + dx, row + dy, 1);
          float intensity = 0.0f;
          if (Intersect(center, R * ray, nullptr, nullptr, &intensity)) {
            sum += intensity;
          }
        }
      }
      gray[row * width + col] = sum / 4.0f;
      if (gt_depth) {
        const Eigen::Vector3d ray = K_inv * Eigen::Vector3d(col, row, 1);
        double t = 0;
        if (Intersect(center, R * ray, &t, nullptr, nullptr)) {
          (*gt_depth)[row * width + col] = static_cast<float>(t);  // ray z = 1
        }
      }
    }
  }
  return MakeMvsView(name, K, cam_from_world, width, height, std::move(gray));
}

void PlaneScene::Scan(const Eigen::Vector3d& origin,
                      const Eigen::Vector3d& forward, int num_rows,
                      int num_cols, double half_angle_horizontal,
                      double half_angle_vertical,
                      std::vector<Eigen::Vector3f>* points,
                      std::vector<Eigen::Vector3f>* normals) const {
  const Eigen::Vector3d f = forward.normalized();
  Eigen::Vector3d right = Eigen::Vector3d::UnitY().cross(f);
  if (right.norm() < 1e-6) right = Eigen::Vector3d::UnitX();
  right.normalize();
  const Eigen::Vector3d down = f.cross(right);
  for (int r = 0; r < num_rows; ++r) {
    const double elevation =
        -half_angle_vertical + 2 * half_angle_vertical * r / std::max(1, num_rows - 1);
    for (int c = 0; c < num_cols; ++c) {
      const double azimuth = -half_angle_horizontal +
                             2 * half_angle_horizontal * c / std::max(1, num_cols - 1);
      const Eigen::Vector3d direction =
          (f + std::tan(azimuth) * right + std::tan(elevation) * down).normalized();
      double t = 0;
      Eigen::Vector3d normal;
      if (Intersect(origin, direction, &t, &normal, nullptr)) {
        points->push_back((origin + t * direction).cast<float>());
        if (normals) normals->push_back(normal.cast<float>());
      }
    }
  }
}

PlaneScene MakeTestPlaneScene() {
  PlaneScene scene;
  TexturedPlane wall;
  wall.origin = Eigen::Vector3d(0, 0, 4.0);
  wall.texture_seed = 11;
  scene.planes.push_back(wall);
  TexturedPlane slanted;
  slanted.origin = Eigen::Vector3d(-0.4, 0.1, 2.6);
  const double angle = 0.5;  // About the y axis.
  slanted.u_axis = Eigen::Vector3d(std::cos(angle), 0, std::sin(angle));
  slanted.v_axis = Eigen::Vector3d::UnitY();
  slanted.u_min = -0.6;
  slanted.u_max = 0.6;
  slanted.v_min = -0.6;
  slanted.v_max = 0.5;
  slanted.texture_seed = 23;
  slanted.texture_cell_m = 0.04;
  scene.planes.push_back(slanted);
  return scene;
}

Eigen::Matrix3d TestCalibration(int width, int height) {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = K(1, 1) = 0.625 * width;
  K(0, 2) = width / 2.0;
  K(1, 2) = height / 2.0;
  return K;
}

std::vector<Rigid3d> TestCameraPoses(int num) {
  static const double kPositions[][2] = {{0, 0},     {0.2, 0},  {-0.2, 0},
                                         {0, 0.15},  {0, -0.15}, {0.35, 0.1},
                                         {-0.35, -0.1}};
  std::vector<Rigid3d> poses;
  for (int i = 0; i < num; ++i) {
    const double* p = kPositions[i % 7];
    // A slight toe-in towards the scene centre keeps the overlap large.
    const Eigen::Vector3d center(p[0], p[1], 0.0);
    const Eigen::Quaterniond rotation(
        Eigen::AngleAxisd(-p[0] * 0.25, Eigen::Vector3d::UnitY()));
    const Rigid3d world_from_cam(rotation, center);
    poses.push_back(world_from_cam.Inverse());
  }
  return poses;
}

double ShareWithinTolerance(const std::vector<float>& depth,
                            const std::vector<float>& gt_depth,
                            double tolerance) {
  size_t total = 0;
  size_t good = 0;
  for (size_t i = 0; i < gt_depth.size() && i < depth.size(); ++i) {
    if (!(gt_depth[i] > 0)) continue;
    ++total;
    if (depth[i] > 0 && std::abs(depth[i] - gt_depth[i]) <= tolerance) ++good;
  }
  return total == 0 ? 0.0 : static_cast<double>(good) / total;
}

GrazingWall MakeGrazingWall() {
  const int width = 320, height = 240;
  GrazingWall wall;
  wall.K = TestCalibration(width, height);
  wall.view = MakeMvsView("v", wall.K, Rigid3d(), width, height,
                          std::vector<float>(width * height, 0.5f));
  wall.normal = Eigen::Vector3f(1.0f, 0, -0.1f).normalized();
  return wall;
}

PlaneMap GroundPlaneMap(const MvsView& view, float height, float max_depth) {
  PlaneMap map(view.width, view.height);
  for (int row = 0; row < view.height; ++row) {
    for (int col = 0; col < view.width; ++col) {
      const Eigen::Vector3f ray =
          view.Ray(static_cast<float>(row), static_cast<float>(col));
      if (!(ray.y() > 0) || height / ray.y() > max_depth) continue;
      const size_t i = map.Index(row, col);
      map.depth[i] = height / ray.y();
      map.normal[i] = Eigen::Vector3f(0.0f, -1.0f, 0.0f);
    }
  }
  return map;
}

GroundViewPair::GroundViewPair(int width, int height, float ground_height,
                               const Eigen::Vector3d& src_center) {
  const Eigen::Matrix3d K = TestCalibration(width, height);
  const std::vector<float> gray(static_cast<size_t>(width) * height, 0.5f);
  ref = MakeMvsView("ref", K, Rigid3d(), width, height, gray);
  src = MakeMvsView("src", K,
                    Rigid3d(Eigen::Quaterniond::Identity(), -src_center),
                    width, height, gray);
  src_map = GroundPlaneMap(src, ground_height, 30.0f);
}

}  // namespace colmap_lidar
