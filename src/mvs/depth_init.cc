#include "src/mvs/depth_init.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace colmap_lidar {
namespace {

Eigen::Vector3f FacingNormal(const Eigen::Vector3f& normal,
                             const Eigen::Vector3f& ray) {
  if (normal.squaredNorm() < 0.25f) {
    return -ray.normalized();
  }
  return normal.dot(ray) > 0 ? Eigen::Vector3f(-normal) : normal;
}

// Samples of one pixel's front surface lie at most this share of its depth
// apart in depth order (ProjectLidarSamples).
constexpr float kMaxFrontGap = 0.01f;

// The depth at the centre of pixel (row, col) of the plane through
// `point_in_cam` (which projects into that pixel) with `normal_in_cam`: the
// point's own depth carried along its plane by the sub-pixel offset of its
// projection. A surface seen at grazing incidence far away changes depth by
// several centimetres per pixel (a facade 20 m ahead along a street), so
// the rounding alone put the LIDAR samples that far off along the ray. The
// point's own depth where the normal is unknown (zero), the plane is seen
// nearly edge-on (cosine below 0.1) or the correction leaves [0.5, 2]
// times that depth.
float DepthAtPixelCentre(const MvsView& view, int row, int col,
                         const Eigen::Vector3f& point_in_cam,
                         const Eigen::Vector3f& normal_in_cam) {
  const float depth = point_in_cam.z();
  if (normal_in_cam.squaredNorm() < 0.25f) return depth;
  const Eigen::Vector3f ray =
      view.Ray(static_cast<float>(row), static_cast<float>(col));
  const float normal_dot_ray = normal_in_cam.dot(ray);
  if (!(std::abs(normal_dot_ray) >= 0.1f * normal_in_cam.norm() * ray.norm())) {
    return depth;
  }
  const float centre_depth = normal_in_cam.dot(point_in_cam) / normal_dot_ray;
  return centre_depth >= 0.5f * depth && centre_depth <= 2.0f * depth
             ? centre_depth
             : depth;
}

}  // namespace

std::vector<DepthSample> ProjectLidarSamples(
    const MvsView& view, const std::vector<Eigen::Vector3f>& points_in_world,
    const std::vector<Eigen::Vector3f>& normals_in_world,
    const LidarPatchMatchOptions& options, DepthInitStats* stats) {
  const int width = view.width;
  const int height = view.height;
  const float min_depth = static_cast<float>(options.min_depth);
  const bool at_centres = options.lidar_samples_at_pixel_centres;
  const float front_band =
      1.0f + static_cast<float>(options.occlusion_relative_tolerance);
  // Every point in view: its pixel and its depth there.
  struct Candidate {
    size_t pixel;
    float depth;
    int point;
  };
  std::vector<Candidate> candidates;
  DepthInitStats local;
  for (size_t k = 0; k < points_in_world.size(); ++k) {
    const Eigen::Vector3f point = view.CamFromWorld(points_in_world[k]);
    if (point.z() < min_depth) continue;
    const Eigen::Vector3f projection = view.K * point;
    const int col = static_cast<int>(std::lround(projection.x() / point.z()));
    const int row = static_cast<int>(std::lround(projection.y() / point.z()));
    if (col < 0 || row < 0 || col >= width || row >= height) continue;
    ++local.num_lidar_in_view;
    float depth = point.z();
    if (at_centres && k < normals_in_world.size()) {
      depth = DepthAtPixelCentre(view, row, col, point,
                                 view.R * normals_in_world[k]);
    }
    candidates.push_back(
        {static_cast<size_t>(row) * width + col, depth, static_cast<int>(k)});
  }
  // Group the candidates by pixel (counting sort), then pick one per pixel.
  std::vector<size_t> begin(static_cast<size_t>(width) * height + 1, 0);
  for (const Candidate& candidate : candidates) ++begin[candidate.pixel + 1];
  for (size_t i = 1; i < begin.size(); ++i) begin[i] += begin[i - 1];
  std::vector<Candidate> grouped(candidates.size());
  {
    std::vector<size_t> next(begin.begin(), begin.end() - 1);
    for (const Candidate& candidate : candidates) {
      grouped[next[candidate.pixel]++] = candidate;
    }
  }
  std::vector<float> zbuffer(static_cast<size_t>(width) * height,
                             std::numeric_limits<float>::infinity());
  std::vector<int> winner(zbuffer.size(), -1);
  for (size_t i = 0; i + 1 < begin.size(); ++i) {
    if (begin[i] == begin[i + 1]) continue;
    const auto first = grouped.begin() + static_cast<std::ptrdiff_t>(begin[i]);
    const auto last =
        grouped.begin() + static_cast<std::ptrdiff_t>(begin[i + 1]);
    // Ties broken by point index: the result does not depend on the order
    // of the cloud's points within a pixel.
    std::sort(first, last, [](const Candidate& a, const Candidate& b) {
      return a.depth < b.depth || (a.depth == b.depth && a.point < b.point);
    });
    auto chosen = first;
    if (at_centres) {
      // The median of the front surface's samples: the nearest of several
      // noisy samples of one surface is biased towards the camera. The
      // front surface ends at the first gap of more than kMaxFrontGap of
      // depth between consecutive samples (a car and the wall 1.5 m behind
      // it, seen by other scans past the car's edge, are two surfaces even
      // where both lie within the band), and within the band.
      auto front_end = first + 1;
      while (front_end != last &&
             front_end->depth <= front_band * first->depth &&
             front_end->depth - (front_end - 1)->depth <=
                 kMaxFrontGap * first->depth) {
        ++front_end;
      }
      chosen = first + (front_end - first) / 2;
    }
    zbuffer[i] = chosen->depth;
    winner[i] = chosen->point;
  }
  const int radius = options.occlusion_window_radius;
  const float tolerance = 1.0f + static_cast<float>(options.occlusion_relative_tolerance);
  std::vector<DepthSample> samples;
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      const size_t i = static_cast<size_t>(row) * width + col;
      if (winner[i] < 0) continue;
      ++local.num_lidar_zbuffer;
      const float depth = zbuffer[i];
      double sum = 0.0;
      int num = 0;
      for (int r = std::max(0, row - radius); r <= std::min(height - 1, row + radius); ++r) {
        for (int c = std::max(0, col - radius); c <= std::min(width - 1, col + radius); ++c) {
          const float z = zbuffer[static_cast<size_t>(r) * width + c];
          if (std::isfinite(z)) {
            sum += z;
            ++num;
          }
        }
      }
      if (depth > tolerance * static_cast<float>(sum / num)) {
        ++local.num_lidar_occluded;
        continue;
      }
      DepthSample sample;
      sample.row = row;
      sample.col = col;
      sample.depth = depth;
      const Eigen::Vector3f normal =
          winner[i] < static_cast<int>(normals_in_world.size())
              ? Eigen::Vector3f(view.R * normals_in_world[winner[i]])
              : Eigen::Vector3f::Zero();
      sample.normal = FacingNormal(normal, view.Ray(row, col));
      samples.push_back(sample);
    }
  }
  if (stats != nullptr) {
    stats->num_lidar_in_view = local.num_lidar_in_view;
    stats->num_lidar_zbuffer = local.num_lidar_zbuffer;
    stats->num_lidar_occluded = local.num_lidar_occluded;
  }
  return samples;
}

std::vector<DepthSample> MergeFeatureSamples(
    const MvsView& view, const std::vector<Eigen::Vector3f>& features_in_world,
    const std::vector<DepthSample>& lidar_samples,
    const LidarPatchMatchOptions& options, DepthInitStats* stats) {
  const int width = view.width;
  const int height = view.height;
  std::vector<int> lidar_index(static_cast<size_t>(width) * height, -1);
  for (size_t k = 0; k < lidar_samples.size(); ++k) {
    lidar_index[static_cast<size_t>(lidar_samples[k].row) * width +
                lidar_samples[k].col] = static_cast<int>(k);
  }
  std::vector<int> feature_index(lidar_index.size(), -1);
  std::vector<DepthSample> features;
  const int radius = options.occlusion_window_radius;
  for (const Eigen::Vector3f& feature : features_in_world) {
    const Eigen::Vector3f point = view.CamFromWorld(feature);
    if (point.z() < options.min_depth) continue;
    const Eigen::Vector3f projection = view.K * point;
    const int col = static_cast<int>(std::lround(projection.x() / point.z()));
    const int row = static_cast<int>(std::lround(projection.y() / point.z()));
    if (col < 0 || row < 0 || col >= width || row >= height) continue;
    const size_t i = static_cast<size_t>(row) * width + col;
    if (feature_index[i] >= 0 && features[feature_index[i]].depth <= point.z()) {
      continue;
    }
    DepthSample sample;
    sample.row = row;
    sample.col = col;
    sample.depth = point.z();
    sample.from_feature = true;
    // Normal of the nearest LIDAR sample in the window.
    int best = -1;
    int best_distance = std::numeric_limits<int>::max();
    for (int r = std::max(0, row - radius); r <= std::min(height - 1, row + radius); ++r) {
      for (int c = std::max(0, col - radius); c <= std::min(width - 1, col + radius); ++c) {
        const int k = lidar_index[static_cast<size_t>(r) * width + c];
        const int distance = (r - row) * (r - row) + (c - col) * (c - col);
        if (k >= 0 && distance < best_distance) {
          best = k;
          best_distance = distance;
        }
      }
    }
    sample.normal = FacingNormal(
        best >= 0 ? lidar_samples[best].normal : Eigen::Vector3f::Zero(),
        view.Ray(row, col));
    if (feature_index[i] >= 0) {
      features[feature_index[i]] = sample;
    } else {
      feature_index[i] = static_cast<int>(features.size());
      features.push_back(sample);
    }
  }
  std::vector<DepthSample> merged;
  merged.reserve(lidar_samples.size() + features.size());
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      const size_t i = static_cast<size_t>(row) * width + col;
      if (feature_index[i] >= 0) {
        merged.push_back(features[feature_index[i]]);
      } else if (lidar_index[i] >= 0) {
        merged.push_back(lidar_samples[lidar_index[i]]);
      }
    }
  }
  if (stats != nullptr) stats->num_features = features.size();
  return merged;
}

std::vector<float> SamplesToPriorDepth(const std::vector<DepthSample>& samples,
                                       int width, int height) {
  std::vector<float> prior(static_cast<size_t>(width) * height, 0.0f);
  for (const DepthSample& sample : samples) {
    prior[static_cast<size_t>(sample.row) * width + sample.col] = sample.depth;
  }
  return prior;
}

}  // namespace colmap_lidar
