#include "src/lines/synthetic_view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace colmap_lidar {
namespace {

struct Hit {
  double t = std::numeric_limits<double>::infinity();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double albedo = 0.0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

// Ray (origin, unit direction) against the scene, LIDAR frame.
Hit CastRay(const SyntheticViewOptions& options, const Eigen::Vector3d& origin,
            const Eigen::Vector3d& direction) {
  Hit hit;
  if (direction.z() < -1e-9) {
    const double t = (options.ground_z - origin.z()) / direction.z();
    const Eigen::Vector3d point = origin + t * direction;
    if (t > 0 && std::abs(point.x()) < 40.0 && std::abs(point.y()) < 40.0) {
      hit.t = t;
      hit.normal = Eigen::Vector3d::UnitZ();
      const bool stripe = options.paint_stripe &&
                          point.x() >= options.stripe_x0 &&
                          point.x() <= options.stripe_x1;
      hit.albedo = stripe ? 0.95 : 0.3;
    }
  }
  for (const SyntheticBox& box : options.boxes) {
    const Eigen::Matrix3d rotation =
        Eigen::AngleAxisd(box.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d o = rotation.transpose() * (origin - box.center);
    const Eigen::Vector3d d = rotation.transpose() * direction;
    double t_near = -std::numeric_limits<double>::infinity();
    double t_far = std::numeric_limits<double>::infinity();
    int axis_near = -1;
    double sign_near = 0.0;
    bool miss = false;
    for (int axis = 0; axis < 3 && !miss; ++axis) {
      if (std::abs(d(axis)) < 1e-12) {
        miss = std::abs(o(axis)) > box.half_size(axis);
        continue;
      }
      double t0 = (-box.half_size(axis) - o(axis)) / d(axis);
      double t1 = (box.half_size(axis) - o(axis)) / d(axis);
      double sign = -1.0;
      if (t0 > t1) {
        std::swap(t0, t1);
        sign = 1.0;
      }
      if (t0 > t_near) {
        t_near = t0;
        axis_near = axis;
        sign_near = sign;
      }
      t_far = std::min(t_far, t1);
    }
    if (miss || t_near > t_far || t_near <= 0.0 || t_near >= hit.t) {
      continue;
    }
    hit.t = t_near;
    Eigen::Vector3d local_normal = Eigen::Vector3d::Zero();
    local_normal(axis_near) = sign_near;
    hit.normal = rotation * local_normal;
    hit.albedo = box.albedo;
  }
  if (std::isfinite(hit.t)) {
    hit.point = origin + hit.t * direction;
  }
  return hit;
}

double Shade(const Hit& hit) {
  if (!std::isfinite(hit.t)) {
    return 0.85;  // sky
  }
  const Eigen::Vector3d light = Eigen::Vector3d(-0.4, 0.6, 0.7).normalized();
  return hit.albedo * (0.35 + 0.65 * std::max(0.0, hit.normal.dot(light)));
}

}  // namespace

std::vector<SyntheticBox> DefaultSyntheticBoxes() {
  std::vector<SyntheticBox> boxes(3);
  boxes[0].center = Eigen::Vector3d(7.0, 1.8, -0.85);
  boxes[0].half_size = Eigen::Vector3d(0.8, 0.9, 0.75);
  boxes[0].yaw = 0.6;
  boxes[0].albedo = 0.8;
  boxes[1].center = Eigen::Vector3d(10.0, -2.5, -0.6);
  boxes[1].half_size = Eigen::Vector3d(1.0, 1.2, 1.0);
  boxes[1].yaw = -0.5;
  boxes[1].albedo = 0.6;
  boxes[2].center = Eigen::Vector3d(14.0, 3.5, -0.1);
  boxes[2].half_size = Eigen::Vector3d(1.5, 1.0, 1.5);
  boxes[2].yaw = 0.35;
  boxes[2].albedo = 0.9;
  return boxes;
}

SyntheticView MakeSyntheticView(const SyntheticViewOptions& options) {
  SyntheticView view;
  view.camera = Camera::FromModelName(
      "PINHOLE", options.width, options.height,
      {options.focal_length, options.focal_length, options.width / 2.0,
       options.height / 2.0});
  // Camera axes (x right, y down, z forward) from LIDAR axes (x forward,
  // y left, z up); the LIDAR sits 0.1 m above the camera.
  Eigen::Matrix3d cam_from_lidar_rotation;
  cam_from_lidar_rotation << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  const Eigen::Vector3d camera_in_lidar(0.0, 0.0, -0.1);
  view.cam_from_lidar = Rigid3d(Eigen::Quaterniond(cam_from_lidar_rotation),
                                -cam_from_lidar_rotation * camera_in_lidar);
  const Rigid3d lidar_from_cam = view.cam_from_lidar.Inverse();
  const Eigen::Matrix3d lidar_from_cam_rotation =
      lidar_from_cam.rotation.toRotationMatrix();

  // Image, 2x2 supersampled.
  std::mt19937 generator(options.seed);
  std::normal_distribution<double> pixel_noise(0.0, 1.0);
  view.image.create(options.height, options.width, CV_8UC1);
  for (int y = 0; y < options.height; ++y) {
    for (int x = 0; x < options.width; ++x) {
      double value = 0.0;
      for (int sy = 0; sy < 2; ++sy) {
        for (int sx = 0; sx < 2; ++sx) {
          // COLMAP convention: pixel (x, y) covers [x, x+1) x [y, y+1).
          const Eigen::Vector2d pixel(x + 0.25 + 0.5 * sx, y + 0.25 + 0.5 * sy);
          const Eigen::Vector2d normalized = view.camera.CamFromImg(pixel);
          const Eigen::Vector3d direction =
              (lidar_from_cam_rotation *
               Eigen::Vector3d(normalized.x(), normalized.y(), 1.0))
                  .normalized();
          value += Shade(CastRay(options, lidar_from_cam.translation, direction));
        }
      }
      view.image.at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(
          255.0 * value / 4.0 + pixel_noise(generator));
    }
  }

  // Scan, ring by ring.
  std::normal_distribution<double> range_noise(0.0, options.range_noise);
  for (int ring = 0; ring < options.num_rings; ++ring) {
    const double elevation =
        (options.min_elevation_deg +
         (options.max_elevation_deg - options.min_elevation_deg) * ring /
             std::max(1, options.num_rings - 1)) *
        M_PI / 180.0;
    for (int column = 0; column < options.num_columns; ++column) {
      const double azimuth = -M_PI + 2.0 * M_PI * column / options.num_columns;
      const Eigen::Vector3d direction(std::cos(elevation) * std::cos(azimuth),
                                      std::cos(elevation) * std::sin(azimuth),
                                      std::sin(elevation));
      const Hit hit = CastRay(options, Eigen::Vector3d::Zero(), direction);
      if (!(hit.t <= options.max_range)) {
        continue;
      }
      const double range =
          hit.t + (options.range_noise > 0 ? range_noise(generator) : 0.0);
      view.scan.points.push_back((range * direction).cast<float>());
      view.scan.intensities.push_back(static_cast<float>(hit.albedo));
      view.scan.rings.push_back(static_cast<uint16_t>(ring));
    }
  }

  for (const SyntheticBox& box : options.boxes) {
    const Eigen::Matrix3d rotation =
        Eigen::AngleAxisd(box.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    auto corner = [&](int i) {
      const Eigen::Vector3d local((i & 1) ? box.half_size.x() : -box.half_size.x(),
                                  (i & 2) ? box.half_size.y() : -box.half_size.y(),
                                  (i & 4) ? box.half_size.z() : -box.half_size.z());
      return view.cam_from_lidar * (box.center + rotation * local);
    };
    for (int i = 0; i < 8; ++i) {
      for (int bit : {1, 2, 4}) {
        if (!(i & bit)) {
          view.edges_in_cam.emplace_back(corner(i), corner(i | bit));
        }
      }
    }
  }
  return view;
}

double DistanceToSegment3D(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const Eigen::Vector3d& p) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

double DistanceToNearestEdge(const SyntheticView& view,
                             const Eigen::Vector3d& point_in_cam) {
  double best = std::numeric_limits<double>::max();
  for (const auto& edge : view.edges_in_cam) {
    best = std::min(best,
                    DistanceToSegment3D(edge.first, edge.second, point_in_cam));
  }
  return best;
}

}  // namespace colmap_lidar
