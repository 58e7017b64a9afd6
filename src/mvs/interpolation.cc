#include "src/mvs/interpolation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <opencv2/imgproc.hpp>

namespace colmap_lidar {
namespace {

// The z-depth at which `ray` (z = 1) meets the plane through `point` (the
// point of a pixel at `point_depth`) with `normal`; 0 where the plane is
// seen nearly edge-on or the depth leaves [0.5, 2] x point_depth.
float PlaneDepthAlongRay(const Eigen::Vector3f& normal,
                         const Eigen::Vector3f& point, float point_depth,
                         const Eigen::Vector3f& ray) {
  const float denominator = normal.dot(ray);
  if (!(denominator < -1e-3f)) return 0.0f;
  const float depth = normal.dot(point) / denominator;
  return depth >= 0.5f * point_depth && depth <= 2.0f * point_depth ? depth
                                                                    : 0.0f;
}

}  // namespace

PlaneMap InterpolateSamples(const MvsView& view,
                            const std::vector<DepthSample>& samples,
                            const LidarPatchMatchOptions& options,
                            std::vector<uint8_t>* across_depth_edge) {
  PlaneMap map(view.width, view.height);
  if (across_depth_edge != nullptr) {
    across_depth_edge->assign(map.depth.size(), 0);
  }
  if (samples.empty()) {
    return map;
  }
  std::unordered_map<int64_t, int> pixel_to_sample;
  cv::Subdiv2D subdiv(cv::Rect(0, 0, view.width, view.height));
  for (size_t k = 0; k < samples.size(); ++k) {
    const int64_t key =
        static_cast<int64_t>(samples[k].row) * view.width + samples[k].col;
    if (pixel_to_sample.emplace(key, static_cast<int>(k)).second) {
      subdiv.insert(cv::Point2f(static_cast<float>(samples[k].col),
                                static_cast<float>(samples[k].row)));
    }
  }
  std::vector<cv::Vec6f> triangles;
  if (pixel_to_sample.size() >= 3) {
    subdiv.getTriangleList(triangles);
  }
  const float max_ratio = static_cast<float>(options.interpolation_max_depth_ratio);
  auto sample_at = [&](float x, float y) -> const DepthSample* {
    if (x < 0 || y < 0 || x > view.width - 1 || y > view.height - 1) {
      return nullptr;  // A virtual outer vertex of Subdiv2D.
    }
    const int64_t key = static_cast<int64_t>(std::lround(y)) * view.width +
                        std::lround(x);
    const auto it = pixel_to_sample.find(key);
    return it == pixel_to_sample.end() ? nullptr : &samples[it->second];
  };
  // The angle a triangle of LIDAR samples subtends: its longest 3D edge over
  // its mean depth; -1 when a vertex is a feature or missing.
  auto lidar_extent = [&](const DepthSample* const* v) -> float {
    if (!v[0] || !v[1] || !v[2]) return -1.0f;
    Eigen::Vector3f p[3];
    for (int k = 0; k < 3; ++k) {
      if (v[k]->from_feature) return -1.0f;
      p[k] = v[k]->depth * view.Ray(static_cast<float>(v[k]->row),
                                    static_cast<float>(v[k]->col));
    }
    const float longest = std::max({(p[0] - p[1]).norm(),
                                    (p[1] - p[2]).norm(),
                                    (p[2] - p[0]).norm()});
    return 3.0f * longest / (v[0]->depth + v[1]->depth + v[2]->depth);
  };
  float max_extent = std::numeric_limits<float>::infinity();
  if (options.interpolation_max_edge_factor > 0) {
    std::vector<float> extents;
    extents.reserve(triangles.size());
    for (const cv::Vec6f& triangle : triangles) {
      const DepthSample* v[3] = {sample_at(triangle[0], triangle[1]),
                                 sample_at(triangle[2], triangle[3]),
                                 sample_at(triangle[4], triangle[5])};
      const float extent = lidar_extent(v);
      if (extent >= 0) extents.push_back(extent);
    }
    if (!extents.empty()) {
      auto middle = extents.begin() + extents.size() / 2;
      std::nth_element(extents.begin(), middle, extents.end());
      max_extent = static_cast<float>(options.interpolation_max_edge_factor) *
                   *middle;
    }
  }
  for (const cv::Vec6f& triangle : triangles) {
    const DepthSample* v[3] = {sample_at(triangle[0], triangle[1]),
                               sample_at(triangle[2], triangle[3]),
                               sample_at(triangle[4], triangle[5])};
    if (!v[0] || !v[1] || !v[2]) continue;
    if (lidar_extent(v) > max_extent) continue;  // Not a sampled surface.
    const float x0 = v[0]->col, y0 = v[0]->row;
    const float x1 = v[1]->col, y1 = v[1]->row;
    const float x2 = v[2]->col, y2 = v[2]->row;
    const float area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    if (std::abs(area) < 1e-6f) continue;
    const float min_depth = std::min({v[0]->depth, v[1]->depth, v[2]->depth});
    const float max_depth = std::max({v[0]->depth, v[1]->depth, v[2]->depth});
    const bool smooth = max_depth <= max_ratio * min_depth;
    const int col_begin = std::max(0, static_cast<int>(std::floor(std::min({x0, x1, x2}))));
    const int col_end = std::min(view.width - 1, static_cast<int>(std::ceil(std::max({x0, x1, x2}))));
    const int row_begin = std::max(0, static_cast<int>(std::floor(std::min({y0, y1, y2}))));
    const int row_end = std::min(view.height - 1, static_cast<int>(std::ceil(std::max({y0, y1, y2}))));
    constexpr float kEps = -1e-4f;
    for (int row = row_begin; row <= row_end; ++row) {
      for (int col = col_begin; col <= col_end; ++col) {
        const float x = static_cast<float>(col);
        const float y = static_cast<float>(row);
        const float b1 = ((x - x0) * (y2 - y0) - (x2 - x0) * (y - y0)) / area;
        const float b2 = ((x1 - x0) * (y - y0) - (x - x0) * (y1 - y0)) / area;
        const float b0 = 1.0f - b1 - b2;
        if (b0 < kEps || b1 < kEps || b2 < kEps) continue;
        const size_t i = map.Index(row, col);
        if (map.depth[i] > 0) continue;  // Shared edge, already set.
        const Eigen::Vector3f ray = view.Ray(y, x);
        if (smooth) {
          const float inv = b0 / v[0]->depth + b1 / v[1]->depth + b2 / v[2]->depth;
          Eigen::Vector3f normal =
              b0 * v[0]->normal + b1 * v[1]->normal + b2 * v[2]->normal;
          if (normal.squaredNorm() < 1e-6f || normal.dot(ray) >= 0) {
            normal = -ray.normalized();
          }
          map.depth[i] = 1.0f / inv;
          map.normal[i] = normal.normalized();
        } else {
          const float b[3] = {b0, b1, b2};
          const DepthSample& nearest = *v[std::max_element(b, b + 3) - b];
          const Eigen::Vector3f point =
              nearest.depth * view.Ray(static_cast<float>(nearest.row),
                                       static_cast<float>(nearest.col));
          const float depth =
              PlaneDepthAlongRay(nearest.normal, point, nearest.depth, ray);
          map.depth[i] = depth > 0 ? depth : nearest.depth;
          map.normal[i] = nearest.normal;
          if (across_depth_edge != nullptr) (*across_depth_edge)[i] = 1;
        }
      }
    }
  }
  // Samples keep their exact values.
  for (const DepthSample& sample : samples) {
    const size_t i = map.Index(sample.row, sample.col);
    map.depth[i] = sample.depth;
    map.normal[i] = sample.normal;
    if (across_depth_edge != nullptr) (*across_depth_edge)[i] = 0;
  }
  return map;
}

size_t ExtrapolateToEmptyPixels(const MvsView& view, PlaneMap* map) {
  cv::Mat empty(map->height, map->width, CV_8U);
  size_t num_empty = 0;
  for (int row = 0; row < map->height; ++row) {
    for (int col = 0; col < map->width; ++col) {
      const bool is_empty = !(map->depth[map->Index(row, col)] > 0);
      empty.at<uint8_t>(row, col) = is_empty ? 255 : 0;
      num_empty += is_empty;
    }
  }
  if (num_empty == 0 || num_empty == map->depth.size()) return 0;
  // Labels of the nearest non-empty pixel (one label per such pixel).
  cv::Mat distance;
  cv::Mat labels;
  cv::distanceTransform(empty, distance, labels, cv::DIST_L2, cv::DIST_MASK_5,
                        cv::DIST_LABEL_PIXEL);
  std::unordered_map<int, size_t> label_to_index;
  for (int row = 0; row < map->height; ++row) {
    for (int col = 0; col < map->width; ++col) {
      if (empty.at<uint8_t>(row, col) == 0) {
        label_to_index[labels.at<int>(row, col)] = map->Index(row, col);
      }
    }
  }
  // Reads only the pixels that had a plane; writes only the empty ones.
  size_t num_filled = 0;
  for (int row = 0; row < map->height; ++row) {
    for (int col = 0; col < map->width; ++col) {
      if (empty.at<uint8_t>(row, col) == 0) continue;
      const auto it = label_to_index.find(labels.at<int>(row, col));
      if (it == label_to_index.end()) continue;
      const size_t j = it->second;
      const int nearest_row = static_cast<int>(j / map->width);
      const int nearest_col = static_cast<int>(j % map->width);
      const Eigen::Vector3f point =
          map->depth[j] * view.Ray(static_cast<float>(nearest_row),
                                   static_cast<float>(nearest_col));
      const float depth = PlaneDepthAlongRay(
          map->normal[j], point, map->depth[j],
          view.Ray(static_cast<float>(row), static_cast<float>(col)));
      if (!(depth > 0)) continue;
      const size_t i = map->Index(row, col);
      map->depth[i] = depth;
      map->normal[i] = map->normal[j];
      ++num_filled;
    }
  }
  return num_filled;
}

}  // namespace colmap_lidar
