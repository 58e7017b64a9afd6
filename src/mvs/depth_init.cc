#include "src/mvs/depth_init.h"

#include <algorithm>
#include <cmath>
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

}  // namespace

std::vector<DepthSample> ProjectLidarSamples(
    const MvsView& view, const std::vector<Eigen::Vector3f>& points_in_world,
    const std::vector<Eigen::Vector3f>& normals_in_world,
    const LidarPatchMatchOptions& options, DepthInitStats* stats) {
  const int width = view.width;
  const int height = view.height;
  const float min_depth = static_cast<float>(options.min_depth);
  std::vector<float> zbuffer(static_cast<size_t>(width) * height,
                             std::numeric_limits<float>::infinity());
  std::vector<int> winner(zbuffer.size(), -1);
  DepthInitStats local;
  for (size_t k = 0; k < points_in_world.size(); ++k) {
    const Eigen::Vector3f point = view.CamFromWorld(points_in_world[k]);
    if (point.z() < min_depth) continue;
    const Eigen::Vector3f projection = view.K * point;
    const int col = static_cast<int>(std::lround(projection.x() / point.z()));
    const int row = static_cast<int>(std::lround(projection.y() / point.z()));
    if (col < 0 || row < 0 || col >= width || row >= height) continue;
    ++local.num_lidar_in_view;
    const size_t i = static_cast<size_t>(row) * width + col;
    if (point.z() < zbuffer[i]) {
      zbuffer[i] = point.z();
      winner[i] = static_cast<int>(k);
    }
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
