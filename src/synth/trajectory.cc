#include "src/synth/trajectory.h"

#include <algorithm>
#include <cmath>

#include "colmap_ext/util/logging.h"
#include "src/synth/random.h"

namespace colmap_lidar {
namespace {

double DegToRad(double deg) { return deg * M_PI / 180.0; }

// Point at arc length s along the polyline (wrapping when closed).
Eigen::Vector2d PointAt(const std::vector<Eigen::Vector2d>& points,
                        const std::vector<double>& cumulative, bool closed,
                        double s) {
  const double length = cumulative.back();
  if (closed) {
    s = std::fmod(s, length);
    if (s < 0) s += length;
  } else {
    s = std::clamp(s, 0.0, length);
  }
  const size_t num_segments = cumulative.size() - 1;
  size_t k = 0;
  while (k + 1 < num_segments && cumulative[k + 1] < s) ++k;
  const Eigen::Vector2d& a = points[k];
  const Eigen::Vector2d& b = points[(k + 1) % points.size()];
  const double segment = cumulative[k + 1] - cumulative[k];
  const double t = segment > 0 ? (s - cumulative[k]) / segment : 0.0;
  return a + t * (b - a);
}

}  // namespace

Rigid3d CameraPoseFromYawPitchRoll(const Eigen::Vector3d& position,
                                   double yaw, double pitch, double roll) {
  const Eigen::Vector3d forward(std::cos(pitch) * std::cos(yaw),
                                std::cos(pitch) * std::sin(yaw),
                                std::sin(pitch));
  const Eigen::Vector3d right0 =
      forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down0 = forward.cross(right0);
  const Eigen::Vector3d right =
      std::cos(roll) * right0 + std::sin(roll) * down0;
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d world_from_cam_rotation;
  world_from_cam_rotation << right, down, forward;
  return Rigid3d(Eigen::Quaterniond(world_from_cam_rotation).normalized(),
                 position);
}

std::vector<Rigid3d> GenerateTrajectory(const WalkPath& path, int num_frames,
                                        uint64_t seed,
                                        const double path_fraction) {
  THROW_CHECK(path.waypoints.size() >= 2,
              "A walk path needs at least two waypoints");
  THROW_CHECK(num_frames >= 1, "num_frames must be >= 1");
  std::vector<Eigen::Vector2d> points = path.waypoints;
  std::vector<double> cumulative = {0.0};
  const size_t num_segments =
      path.closed ? points.size() : points.size() - 1;
  for (size_t k = 0; k < num_segments; ++k) {
    cumulative.push_back(cumulative.back() +
                         (points[(k + 1) % points.size()] - points[k]).norm());
  }
  THROW_CHECK(path_fraction > 0.0 && path_fraction <= 1.0,
              "path_fraction must be in (0, 1], got " << path_fraction);
  THROW_CHECK(cumulative.back() > 0.0, "The walk path has zero length");
  // A part of a closed path is walked like an open one, end included.
  const bool closed = path.closed && path_fraction == 1.0;
  const double length = cumulative.back() * path_fraction;

  const CounterRng rng(seed, StreamId(RandomStream::kTrajectory));
  std::vector<Rigid3d> poses;
  poses.reserve(num_frames);
  for (int i = 0; i < num_frames; ++i) {
    const double s =
        closed ? length * i / num_frames
               : (num_frames > 1 ? length * i / (num_frames - 1) : 0.0);
    const Eigen::Vector2d xy = PointAt(points, cumulative, path.closed, s);
    // Walking direction from a central difference over +-0.5 m, so that
    // the heading turns smoothly along a polygonal path.
    const Eigen::Vector2d ahead =
        PointAt(points, cumulative, path.closed, s + 0.5);
    const Eigen::Vector2d behind =
        PointAt(points, cumulative, path.closed, s - 0.5);
    const Eigen::Vector2d direction = (ahead - behind).normalized();
    const double heading = std::atan2(direction.y(), direction.x());
    const uint64_t base = 8 * static_cast<uint64_t>(i);
    const double yaw =
        heading + DegToRad(path.look_yaw_offset_deg) +
        DegToRad(path.yaw_amplitude_deg) *
            std::sin(2.0 * M_PI * i / path.yaw_period_frames);
    const double pitch =
        DegToRad(path.pitch_deg + path.jitter_deg * rng.Normal(base));
    const double roll = DegToRad(path.jitter_deg * rng.Normal(base + 1));
    const Eigen::Vector3d position(xy.x() + 0.03 * rng.Normal(base + 2),
                                   xy.y() + 0.03 * rng.Normal(base + 3),
                                   path.height_m + 0.02 * rng.Normal(base + 4));
    poses.push_back(CameraPoseFromYawPitchRoll(position, yaw, pitch, roll));
  }
  return poses;
}

std::vector<Rigid3d> PerturbPoses(const std::vector<Rigid3d>& world_from_cams,
                                  double sigma_t, double sigma_r_deg,
                                  uint64_t seed) {
  const CounterRng rng(seed, StreamId(RandomStream::kPriorNoise));
  std::vector<Rigid3d> noisy;
  noisy.reserve(world_from_cams.size());
  for (size_t i = 0; i < world_from_cams.size(); ++i) {
    const uint64_t base = 8 * static_cast<uint64_t>(i);
    const Eigen::Vector3d translation_noise(rng.Normal(base),
                                            rng.Normal(base + 1),
                                            rng.Normal(base + 2));
    // A uniformly distributed axis: a normalised isotropic Gaussian vector.
    Eigen::Vector3d axis(rng.Normal(base + 3), rng.Normal(base + 4),
                         rng.Normal(base + 5));
    if (axis.norm() < 1e-12) axis = Eigen::Vector3d::UnitZ();
    axis.normalize();
    const double angle = DegToRad(sigma_r_deg) * rng.Normal(base + 6);
    const Eigen::Quaterniond rotation_noise(Eigen::AngleAxisd(angle, axis));
    const Rigid3d& gt = world_from_cams[i];
    noisy.emplace_back((rotation_noise * gt.rotation).normalized(),
                       gt.translation + sigma_t * translation_noise);
  }
  return noisy;
}

}  // namespace colmap_lidar
