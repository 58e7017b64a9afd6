#include "src/mvs/ncc_cost.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Windows whose grey-value standard deviation is below 0.005 (1.3 grey
// levels of 255) are textureless: their NCC is quantisation noise, which
// PatchMatch would otherwise follow away from a correct LIDAR plane (on the
// synthetic scene most pixels it lost had a window std of 0.0033-0.004).
constexpr float kMinVariance = 2.5e-5f;

// A source plane seen at more than acos(0.1) = 84 deg from its pixel's ray is
// nearly edge-on: its depth at a neighbouring sub-pixel position is
// ill-conditioned, so the pixel's own depth is used there.
constexpr float kMinPlaneRayCosine = 0.1f;

// The z-depth of the source map's surface along the ray through sub-pixel
// (x, y), whose nearest pixel (r, c) holds a valid depth: with `plane`, the
// plane of that pixel (its point at the pixel centre, its normal, both in the
// source camera frame) cut by the ray; else, or where the plane is seen
// nearly edge-on, the pixel's depth.
float SourceDepthAt(const PlaneMap& map, const MvsView& view, float x, float y,
                    int r, int c, bool plane) {
  const size_t index = map.Index(r, c);
  const float depth = map.depth[index];
  if (!plane) return depth;
  const Eigen::Vector3f& normal = map.normal[index];
  const Eigen::Vector3f ray = view.Ray(y, x);
  const float normal_dot_ray = normal.dot(ray);
  if (!(std::abs(normal_dot_ray) >=
        kMinPlaneRayCosine * normal.norm() * ray.norm())) {
    return depth;
  }
  const float plane_depth =
      depth * normal.dot(view.Ray(static_cast<float>(r),
                                  static_cast<float>(c))) /
      normal_dot_ray;
  return plane_depth > 0 ? plane_depth : depth;
}

}  // namespace

PatchCostComputer::PatchCostComputer(const MvsView& ref,
                                     std::vector<const MvsView*> srcs,
                                     const LidarPatchMatchOptions& options)
    : ref_(ref),
      inv_two_sigma_color_sq_(
          static_cast<float>(1.0 / (2.0 * options.sigma_color *
                                    options.sigma_color))),
      geom_regularizer_(static_cast<float>(options.geom_consistency_regularizer)),
      geom_max_cost_(static_cast<float>(options.geom_consistency_max_cost)),
      best_views_fraction_(options.best_views_fraction),
      visible_sources_only_(options.visible_sources_only),
      source_plane_depth_(options.source_plane_depth) {
  THROW_CHECK(!srcs.empty(), "view " << ref.name << " has no source views");
  const Eigen::Matrix3f R_ref_t = ref.R.transpose();
  for (const MvsView* src : srcs) {
    SourceGeometry geometry;
    geometry.view = src;
    // src_from_ref = src_from_world * world_from_ref.
    geometry.R = src->R * R_ref_t;
    geometry.t = src->t - geometry.R * ref.t;
    geometry.A = src->K * geometry.R * ref.K_inv;
    geometry.b = src->K * geometry.t;
    srcs_.push_back(geometry);
  }
  const int radius = options.window_radius;
  const int step = options.window_step;
  const double sigma_spatial =
      options.sigma_spatial > 0 ? options.sigma_spatial : radius;
  // Symmetric offsets: -radius, -radius + step, ... up to +radius.
  for (int dy = -radius; dy <= radius; dy += step) {
    for (int dx = -radius; dx <= radius; dx += step) {
      offset_dx_.push_back(static_cast<float>(dx));
      offset_dy_.push_back(static_cast<float>(dy));
      spatial_weight_.push_back(static_cast<float>(
          std::exp(-(dx * dx + dy * dy) / (2.0 * sigma_spatial * sigma_spatial))));
    }
  }
  num_best_ = std::max(
      1, static_cast<int>(std::ceil(options.best_views_fraction * srcs_.size())));
}

void PatchCostComputer::SetSourceMaps(std::vector<const PlaneMap*> src_maps) {
  THROW_CHECK(src_maps.size() == srcs_.size(),
              "view " << ref_.name << ": " << src_maps.size()
                      << " source maps for " << srcs_.size() << " sources");
  for (size_t i = 0; i < src_maps.size(); ++i) {
    THROW_CHECK(src_maps[i] == nullptr ||
                    (src_maps[i]->width == srcs_[i].view->width &&
                     src_maps[i]->height == srcs_[i].view->height),
                "source map of " << srcs_[i].view->name
                                 << " differs in size from its image");
  }
  src_maps_ = std::move(src_maps);
}

void PatchCostComputer::PrepareRefPatch(int row, int col,
                                        RefPatch* patch) const {
  const size_t n = offset_dx_.size();
  patch->row = row;
  patch->col = col;
  patch->dx.resize(n);
  patch->dy.resize(n);
  patch->value.resize(n);
  patch->weight.resize(n);
  const float center = ref_.At(row, col);
  int num = 0;
  float weight_sum = 0.0f;
  for (size_t i = 0; i < n; ++i) {
    const int r = row + static_cast<int>(offset_dy_[i]);
    const int c = col + static_cast<int>(offset_dx_[i]);
    if (r < 0 || c < 0 || r >= ref_.height || c >= ref_.width) {
      continue;
    }
    const float value = ref_.At(r, c);
    const float diff = value - center;
    const float weight =
        spatial_weight_[i] * std::exp(-diff * diff * inv_two_sigma_color_sq_);
    patch->dx[num] = offset_dx_[i];
    patch->dy[num] = offset_dy_[i];
    patch->value[num] = value;
    patch->weight[num] = weight;
    weight_sum += weight;
    ++num;
  }
  patch->num = num;
  float mean = 0.0f;
  float second = 0.0f;
  for (int i = 0; i < num; ++i) {
    patch->weight[i] /= weight_sum;
    mean += patch->weight[i] * patch->value[i];
    second += patch->weight[i] * patch->value[i] * patch->value[i];
  }
  patch->mean = mean;
  patch->variance = second - mean * mean;
}

bool PatchCostComputer::Textureless(int row, int col) const {
  RefPatch patch;
  PrepareRefPatch(row, col, &patch);
  return patch.variance < kMinVariance;
}

float PatchCostComputer::PhotometricCost(const RefPatch& patch, int src,
                                         float depth,
                                         const Eigen::Vector3f& normal) const {
  if (patch.variance < kMinVariance || !(depth > 0)) {
    return kMaxCost;
  }
  const SourceGeometry& geometry = srcs_[src];
  const Eigen::Vector3f ray = ref_.Ray(patch.row, patch.col);
  const float n_dot_x = depth * normal.dot(ray);
  if (std::abs(n_dot_x) < 1e-6f) {
    return kMaxCost;
  }
  // H = A + b c^T with c^T = n^T K_r^-1 / (n . X).
  const Eigen::RowVector3f c = (normal.transpose() * ref_.K_inv) / n_dot_x;
  const Eigen::Matrix3f H = geometry.A + geometry.b * c;
  const Eigen::Vector3f q0 =
      H * Eigen::Vector3f(static_cast<float>(patch.col),
                          static_cast<float>(patch.row), 1.0f);
  const Eigen::Vector3f hx = H.col(0);
  const Eigen::Vector3f hy = H.col(1);
  const MvsView& view = *geometry.view;
  const float max_x = static_cast<float>(view.width - 1);
  const float max_y = static_cast<float>(view.height - 1);
  float sum_s = 0.0f;
  float sum_ss = 0.0f;
  float sum_rs = 0.0f;
  for (int i = 0; i < patch.num; ++i) {
    const Eigen::Vector3f q = q0 + patch.dx[i] * hx + patch.dy[i] * hy;
    if (q.z() <= 0) {
      return kMaxCost;
    }
    const float inv_z = 1.0f / q.z();
    const float x = q.x() * inv_z;
    const float y = q.y() * inv_z;
    if (!(x >= 0 && y >= 0 && x <= max_x && y <= max_y)) {
      return kMaxCost;
    }
    const float s = view.Sample(x, y);
    const float w = patch.weight[i];
    sum_s += w * s;
    sum_ss += w * s * s;
    sum_rs += w * patch.value[i] * s;
  }
  const float var_s = sum_ss - sum_s * sum_s;
  if (var_s < kMinVariance) {
    return kMaxCost;
  }
  const float cov = sum_rs - patch.mean * sum_s;
  const float ncc = cov / std::sqrt(patch.variance * var_s);
  return std::clamp(1.0f - ncc, 0.0f, kMaxCost);
}

bool PatchCostComputer::SourceSees(int src, int row, int col,
                                   float depth) const {
  const SourceGeometry& geometry = srcs_[src];
  const Eigen::Vector3f point_in_src =
      geometry.R * (depth * ref_.Ray(row, col)) + geometry.t;
  if (!(point_in_src.z() > 0)) {
    return false;
  }
  const MvsView& view = *geometry.view;
  const Eigen::Vector3f projection = view.K * point_in_src;
  const float x = projection.x() / projection.z();
  const float y = projection.y() / projection.z();
  return x >= -0.5f && y >= -0.5f && x < view.width - 0.5f &&
         y < view.height - 0.5f;
}

float PatchCostComputer::DepthErrorParallax(int src, int row, int col,
                                            float depth, float relative) const {
  const SourceGeometry& geometry = srcs_[src];
  const Eigen::Vector3f point_in_src =
      geometry.R * (depth * ref_.Ray(row, col)) + geometry.t;
  if (!(point_in_src.z() > 0)) {
    return 0.0f;
  }
  const Eigen::Vector3f moved_in_ref =
      geometry.R.transpose() * ((1.0f + relative) * point_in_src - geometry.t);
  if (!(moved_in_ref.z() > 0)) {
    return 0.0f;
  }
  const Eigen::Vector3f moved = ref_.K * moved_in_ref;
  const float du = moved.x() / moved.z() - col;
  const float dv = moved.y() / moved.z() - row;
  return std::sqrt(du * du + dv * dv);
}

std::optional<PatchCostComputer::SourceSurfacePoint>
PatchCostComputer::SourceSurface(int src, int row, int col, float depth) const {
  const PlaneMap* map = src_maps_.empty() ? nullptr : src_maps_[src];
  if (map == nullptr) {
    return std::nullopt;
  }
  const SourceGeometry& geometry = srcs_[src];
  SourceSurfacePoint hit;
  hit.point_in_src = geometry.R * (depth * ref_.Ray(row, col)) + geometry.t;
  if (hit.point_in_src.z() <= 0) {
    return std::nullopt;
  }
  const Eigen::Vector3f homogeneous = geometry.view->K * hit.point_in_src;
  hit.projection = homogeneous.head<2>() / homogeneous.z();
  const int c = static_cast<int>(std::lround(hit.projection.x()));
  const int r = static_cast<int>(std::lround(hit.projection.y()));
  if (c < 0 || r < 0 || c >= map->width || r >= map->height ||
      !(map->depth[map->Index(r, c)] > 0)) {
    return std::nullopt;
  }
  hit.src_depth = SourceDepthAt(*map, *geometry.view, hit.projection.x(),
                                hit.projection.y(), r, c, source_plane_depth_);
  return hit;
}

float PatchCostComputer::ReprojectionError(int src, int row, int col,
                                           float depth) const {
  const std::optional<SourceSurfacePoint> hit =
      SourceSurface(src, row, col, depth);
  if (!hit) return std::numeric_limits<float>::infinity();
  const SourceGeometry& geometry = srcs_[src];
  const Eigen::Vector3f back_in_src =
      hit->src_depth *
      geometry.view->Ray(hit->projection.y(), hit->projection.x());
  const Eigen::Vector3f back_in_ref =
      geometry.R.transpose() * (back_in_src - geometry.t);
  if (back_in_ref.z() <= 0) {
    return std::numeric_limits<float>::infinity();
  }
  const Eigen::Vector3f back = ref_.K * back_in_ref;
  const float du = back.x() / back.z() - col;
  const float dv = back.y() / back.z() - row;
  return std::sqrt(du * du + dv * dv);
}

float PatchCostComputer::SourceDepthError(int src, int row, int col,
                                          float depth) const {
  const std::optional<SourceSurfacePoint> hit =
      SourceSurface(src, row, col, depth);
  if (!hit) return std::numeric_limits<float>::infinity();
  return std::abs(hit->src_depth - hit->point_in_src.z()) /
         hit->point_in_src.z();
}

float PatchCostComputer::Cost(const RefPatch& patch, float depth,
                              const Eigen::Vector3f& normal) const {
  // Small fixed buffer: sources are few (max_num_src_images).
  float costs[64];
  const int n = std::min<int>(static_cast<int>(srcs_.size()), 64);
  for (int s = 0; s < n; ++s) {
    float cost = PhotometricCost(patch, s, depth, normal);
    if (!src_maps_.empty() && src_maps_[s] != nullptr) {
      const float error = ReprojectionError(s, patch.row, patch.col, depth);
      cost += geom_regularizer_ * std::min(error, geom_max_cost_);
    }
    costs[s] = cost;
  }
  int k = std::min(num_best_, n);
  if (visible_sources_only_) {
    int num_visible = 0;
    for (int s = 0; s < n; ++s) {
      if (SourceSees(s, patch.row, patch.col, depth)) ++num_visible;
    }
    k = std::min(n, std::max(1, static_cast<int>(std::ceil(
                                    best_views_fraction_ * num_visible))));
  }
  std::partial_sort(costs, costs + k, costs + n);
  float sum = 0.0f;
  for (int i = 0; i < k; ++i) {
    sum += costs[i];
  }
  return sum / k;
}

}  // namespace colmap_lidar
