#include "src/matching/synthetic_line_views.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

namespace colmap_lidar {
namespace {

void AddRectangle(double x0, double x1, double z0, double z1, double y,
                  SyntheticLineScene* scene) {
  const Eigen::Vector3d a(x0, y, z0), b(x1, y, z0), c(x1, y, z1), d(x0, y, z1);
  scene->edges.emplace_back(a, b);
  scene->edges.emplace_back(b, c);
  scene->edges.emplace_back(c, d);
  scene->edges.emplace_back(d, a);
}

// The camera looks along +y (world), x right, z up: camera axes x = world
// x, y = world -z, z = world y; then a yaw about the world z axis.
Rigid3d CameraPose(const Eigen::Vector3d& center, double yaw_rad) {
  Eigen::Matrix3d cam_from_level;
  cam_from_level << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  const Eigen::Matrix3d world_from_level =
      Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d cam_from_world =
      cam_from_level * world_from_level.transpose();
  return Rigid3d(Eigen::Quaterniond(cam_from_world),
                 -cam_from_world * center);
}

}  // namespace

SyntheticLineScene MakeSyntheticLineScene(
    const SyntheticLineSceneOptions& options) {
  SyntheticLineScene scene;
  std::mt19937 rng(options.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);

  // Facade at y = 10 with recessed windows, plus its outline.
  const double facade_y = 10.0;
  const double width = 2.5 * options.num_window_columns;
  AddRectangle(-width / 2, width / 2, 0.0, 1.0 + 2.5 * options.num_window_rows,
               facade_y, &scene);
  for (int c = 0; c < options.num_window_columns; ++c) {
    for (int r = 0; r < options.num_window_rows; ++r) {
      const double x0 = -width / 2 + 2.5 * c + 0.65;
      const double z0 = 1.0 + 2.5 * r;
      AddRectangle(x0, x0 + 1.2, z0, z0 + 1.5, facade_y, &scene);
      AddRectangle(x0, x0 + 1.2, z0, z0 + 1.5,
                   facade_y + options.recess_depth_m, &scene);
    }
  }
  // Edge descriptors: random bits per edge.
  std::vector<std::array<uint8_t, 32>> edge_descriptors(scene.edges.size());
  for (auto& descriptor : edge_descriptors) {
    for (auto& byte : descriptor) byte = static_cast<uint8_t>(rng() & 0xff);
  }

  scene.camera = Camera::FromModelName("PINHOLE", 848, 480,
                                       {424.0, 424.0, 424.0, 240.0});
  for (int v = 0; v < options.num_views; ++v) {
    const double s =
        options.num_views > 1 ? static_cast<double>(v) / (options.num_views - 1)
                              : 0.5;
    const Eigen::Vector3d center(-0.35 * width + 0.7 * width * s,
                                 0.5 * std::sin(3.0 * s), 1.6);
    const double yaw = 0.25 * std::sin(5.0 * s + 1.0);
    scene.cam_from_world.push_back(CameraPose(center, yaw));
  }

  const double w = static_cast<double>(scene.camera.width);
  const double h = static_cast<double>(scene.camera.height);
  scene.segments.resize(options.num_views);
  scene.edge_of_segment.resize(options.num_views);
  for (int v = 0; v < options.num_views; ++v) {
    const Rigid3d& cam_from_world = scene.cam_from_world[v];
    for (size_t e = 0; e < scene.edges.size(); ++e) {
      const Eigen::Vector3d a = cam_from_world * scene.edges[e].first;
      const Eigen::Vector3d b = cam_from_world * scene.edges[e].second;
      // The part of the edge in front and inside the image, by sampling.
      double t_first = -1.0, t_last = -1.0;
      constexpr int kSamples = 200;
      for (int k = 0; k <= kSamples; ++k) {
        const double t = static_cast<double>(k) / kSamples;
        const Eigen::Vector3d p = (1.0 - t) * a + t * b;
        if (p.z() < 0.5) continue;
        const Eigen::Vector2d pixel = scene.camera.ImgFromCam(p);
        if (pixel.x() < 1.0 || pixel.y() < 1.0 || pixel.x() > w - 1.0 ||
            pixel.y() > h - 1.0) {
          continue;
        }
        if (t_first < 0.0) t_first = t;
        t_last = t;
      }
      if (t_first < 0.0) continue;
      // Partial detection: up to 20% lost at each end.
      const double span = t_last - t_first;
      const double t0 = t_first + 0.2 * span * uniform(rng);
      const double t1 = t_last - 0.2 * span * uniform(rng);
      const Eigen::Vector3d p0 = (1.0 - t0) * a + t0 * b;
      const Eigen::Vector3d p1 = (1.0 - t1) * a + t1 * b;
      LineSegmentRecord record;
      record.start2D = scene.camera.ImgFromCam(p0) +
                       options.pixel_noise_px *
                           Eigen::Vector2d(normal(rng), normal(rng));
      record.end2D = scene.camera.ImgFromCam(p1) +
                     options.pixel_noise_px *
                         Eigen::Vector2d(normal(rng), normal(rng));
      if ((record.end2D - record.start2D).norm() < options.min_length_px) {
        continue;
      }
      record.start3D_in_cam =
          p0 * (1.0 + options.depth_noise_m * normal(rng) / p0.norm());
      record.end3D_in_cam =
          p1 * (1.0 + options.depth_noise_m * normal(rng) / p1.norm());
      record.num_inliers = 10;
      record.descriptor = edge_descriptors[e];
      for (int f = 0; f < options.descriptor_bit_flips; ++f) {
        const int bit = static_cast<int>(rng() % 256);
        record.descriptor[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
      }
      scene.segments[v].push_back(record);
      scene.edge_of_segment[v].push_back(static_cast<int>(e));
    }
  }
  return scene;
}

std::vector<MatchingView> MakeSyntheticViews(
    const SyntheticLineScene& scene,
    const std::vector<Rigid3d>& cam_from_world) {
  std::vector<MatchingView> views;
  for (size_t v = 0; v < scene.segments.size(); ++v) {
    views.push_back(MakeMatchingView(static_cast<image_t>(v + 1),
                                     "view" + std::to_string(v) + ".png",
                                     scene.camera, cam_from_world.at(v),
                                     scene.segments[v]));
  }
  return views;
}

std::vector<Rigid3d> PerturbPoses(const std::vector<Rigid3d>& cam_from_world,
                                  const double sigma_t_m,
                                  const double sigma_r_deg,
                                  const uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Rigid3d> perturbed;
  for (const Rigid3d& pose : cam_from_world) {
    const Rigid3d world_from_cam = pose.Inverse();
    const Eigen::Vector3d center =
        world_from_cam.translation +
        sigma_t_m * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    const Eigen::Vector3d axis =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const double angle = sigma_r_deg * M_PI / 180.0 * normal(rng);
    const Eigen::Quaterniond rotation =
        (pose.rotation * Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis)))
            .normalized();
    perturbed.emplace_back(rotation, -(rotation * center));
  }
  return perturbed;
}

TrackQuality EvaluateTracks(const SyntheticLineScene& scene,
                            const std::vector<LineTrackRecord>& tracks) {
  TrackQuality quality;
  quality.num_tracks = tracks.size();
  size_t num_observations = 0;
  for (const LineTrackRecord& track : tracks) {
    std::set<int> edges;
    for (const LineTrackElement& element : track.elements) {
      edges.insert(scene.edge_of_segment.at(element.image_id - 1)
                       .at(element.line2D_idx));
    }
    num_observations += track.elements.size();
    quality.num_pure_tracks += edges.size() == 1 ? 1 : 0;
  }
  if (!tracks.empty()) {
    quality.precision =
        static_cast<double>(quality.num_pure_tracks) / tracks.size();
    quality.mean_track_length =
        static_cast<double>(num_observations) / tracks.size();
  }
  std::map<int, int> views_per_edge;
  for (const auto& edges : scene.edge_of_segment) {
    for (const int e : edges) ++views_per_edge[e];
  }
  size_t num_matchable = 0;
  for (const auto& [edge, count] : views_per_edge) {
    if (count >= 2) num_matchable += count;
  }
  quality.recall = num_matchable > 0 ? static_cast<double>(num_observations) /
                                           num_matchable
                                     : 0.0;
  return quality;
}

}  // namespace colmap_lidar
