#include "src/mvs/textureless_fill.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Dense>
#include <glog/logging.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Inverse z-depth as an affine function of the pixel: w = a col + b row + c.
using Affine = Eigen::Vector3d;

Eigen::Vector3d PixelVector(int index, int width) {
  return Eigen::Vector3d(index % width, index / width, 1.0);
}

// The pixel indices of each 4-connected component of `mask`.
std::vector<std::vector<int>> Components(const std::vector<uint8_t>& mask,
                                         int width, int height) {
  std::vector<std::vector<int>> components;
  std::vector<uint8_t> seen(mask.size(), 0);
  std::vector<int> stack;
  for (int start = 0; start < static_cast<int>(mask.size()); ++start) {
    if (!mask[start] || seen[start]) continue;
    std::vector<int> component;
    seen[start] = 1;
    stack.push_back(start);
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      component.push_back(i);
      const int row = i / width;
      const int col = i % width;
      const int neighbours[4][2] = {
          {row, col - 1}, {row, col + 1}, {row - 1, col}, {row + 1, col}};
      for (const auto& n : neighbours) {
        if (n[0] < 0 || n[0] >= height || n[1] < 0 || n[1] >= width) continue;
        const int j = n[0] * width + n[1];
        if (mask[j] && !seen[j]) {
          seen[j] = 1;
          stack.push_back(j);
        }
      }
    }
    components.push_back(std::move(component));
  }
  return components;
}

bool IsInlier(const Affine& affine, int index, int width, float depth,
              double max_relative_depth_error) {
  const double w = affine.dot(PixelVector(index, width));
  return w > 0 && std::abs(1.0 / w - depth) <= max_relative_depth_error * depth;
}

// Least-squares affine fit of the inverse depths of `pixels`.
Affine FitAffine(const std::vector<int>& pixels, const PlaneMap& map) {
  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const int i : pixels) {
    const Eigen::Vector3d x = PixelVector(i, map.width);
    normal_matrix += x * x.transpose();
    rhs += x / map.depth[i];
  }
  return normal_matrix.ldlt().solve(rhs);
}

// The plane of one region, if its measured pixels fit one (see the header).
bool FitRegionPlane(const std::vector<int>& measured, const PlaneMap& map,
                    const Eigen::Matrix3f& K,
                    const TexturelessFillOptions& options, Affine* affine,
                    Eigen::Vector3f* normal, float* max_inlier_depth) {
  const int width = map.width;
  if (static_cast<int>(measured.size()) < options.min_support_pixels) {
    return false;
  }
  // Spread of the support in the image.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const int i : measured) mean += PixelVector(i, width).head<2>();
  mean /= measured.size();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const int i : measured) {
    const Eigen::Vector2d d = PixelVector(i, width).head<2>() - mean;
    covariance += d * d.transpose();
  }
  covariance /= measured.size();
  const double min_std = std::sqrt(
      std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(covariance)
                        .eigenvalues()(0)));
  if (min_std < options.min_support_spread_px) return false;

  // RANSAC over minimal samples of 3 pixels; the seed is the region's first
  // pixel, so the result does not depend on the order of regions.
  std::mt19937 rng(static_cast<uint32_t>(measured.front()));
  std::uniform_int_distribution<size_t> pick(0, measured.size() - 1);
  size_t best_inliers = 0;
  Affine best = Affine::Zero();
  for (int it = 0; it < options.num_ransac_iterations; ++it) {
    Eigen::Matrix3d A;
    Eigen::Vector3d b;
    for (int k = 0; k < 3; ++k) {
      const int i = measured[pick(rng)];
      A.row(k) = PixelVector(i, width).transpose();
      b(k) = 1.0 / map.depth[i];
    }
    if (std::abs(A.determinant()) < 1e-6) continue;
    const Affine candidate = A.partialPivLu().solve(b);
    size_t inliers = 0;
    for (const int i : measured) {
      inliers += IsInlier(candidate, i, width, map.depth[i],
                          options.max_relative_depth_error);
    }
    if (inliers > best_inliers) {
      best_inliers = inliers;
      best = candidate;
    }
  }
  if (best_inliers < options.min_inlier_ratio * measured.size()) return false;
  std::vector<int> inliers;
  for (const int i : measured) {
    if (IsInlier(best, i, width, map.depth[i],
                 options.max_relative_depth_error)) {
      inliers.push_back(i);
    }
  }
  *affine = FitAffine(inliers, map);
  // On a plane n . X = e (camera frame), 1 / z = (n^T K^-1 / e) [col, row,
  // 1]^T, so n is parallel to K^T (a, b, c).
  *normal = (K.transpose() * affine->cast<float>()).normalized();
  if (!normal->allFinite()) return false;
  // The inliers again, now with the refitted plane and their own normals:
  // a curved surface (a tanker's tank) fits one plane's depths within the
  // tolerance over a small region, but not its normals.
  const float min_cos =
      static_cast<float>(std::cos(options.max_normal_angle_deg * M_PI / 180.0));
  size_t num_agreeing = 0;
  *max_inlier_depth = 0.0f;
  for (const int i : inliers) {
    if (!IsInlier(*affine, i, width, map.depth[i],
                  options.max_relative_depth_error) ||
        !(std::abs(map.normal[i].dot(*normal)) >=
          min_cos * map.normal[i].norm())) {
      continue;
    }
    ++num_agreeing;
    *max_inlier_depth = std::max(*max_inlier_depth, map.depth[i]);
  }
  return num_agreeing >= options.min_inlier_ratio * measured.size();
}

}  // namespace

bool TexturelessFillOptions::Check() const {
  const auto fail = [](const char* message) {
    LOG(ERROR) << "TexturelessFill." << message;
    return false;
  };
  if (min_support_pixels < 3) return fail("min_support_pixels must be >= 3");
  if (!(min_support_spread_px >= 0)) {
    return fail("min_support_spread_px must be >= 0");
  }
  if (!(min_inlier_ratio > 0 && min_inlier_ratio <= 1)) {
    return fail("min_inlier_ratio must be in (0, 1]");
  }
  if (!(max_relative_depth_error > 0)) {
    return fail("max_relative_depth_error must be > 0");
  }
  if (!(max_normal_angle_deg > 0 && max_normal_angle_deg <= 90)) {
    return fail("max_normal_angle_deg must be in (0, 90]");
  }
  if (!(max_depth_factor >= 1)) return fail("max_depth_factor must be >= 1");
  if (num_ransac_iterations < 1) {
    return fail("num_ransac_iterations must be >= 1");
  }
  return true;
}

size_t FillTexturelessRegions(const Eigen::Matrix3f& K,
                              const std::vector<uint8_t>& textureless,
                              const TexturelessFillOptions& options,
                              float filled_cost, PlaneMap* map,
                              std::vector<uint8_t>* filled) {
  const int width = map->width;
  const size_t num_pixels = static_cast<size_t>(width) * map->height;
  THROW_CHECK(textureless.size() == num_pixels,
              "textureless mask of " << textureless.size()
                                     << " pixels for a map of " << num_pixels);
  THROW_CHECK(options.Check(), "invalid TexturelessFillOptions");
  if (filled != nullptr) filled->assign(num_pixels, 0);
  const Eigen::Matrix3f K_inv = K.inverse();
  size_t num_filled = 0;
  for (const std::vector<int>& region :
       Components(textureless, width, map->height)) {
    std::vector<int> measured;
    std::vector<int> empty;
    for (const int i : region) {
      (map->depth[i] > 0 ? measured : empty).push_back(i);
    }
    Affine affine;
    Eigen::Vector3f normal;
    float max_inlier_depth = 0.0f;
    if (empty.empty() || !FitRegionPlane(measured, *map, K, options, &affine,
                                         &normal, &max_inlier_depth)) {
      continue;
    }
    const double max_depth = options.max_depth_factor * max_inlier_depth;
    for (const int i : empty) {
      const double w = affine.dot(PixelVector(i, width));
      if (!(w > 0) || 1.0 / w > max_depth) continue;
      const Eigen::Vector3f ray = K_inv * PixelVector(i, width).cast<float>();
      map->depth[i] = static_cast<float>(1.0 / w);
      map->normal[i] = normal.dot(ray) > 0 ? Eigen::Vector3f(-normal) : normal;
      map->cost[i] = filled_cost;
      if (filled != nullptr) (*filled)[i] = 1;
      ++num_filled;
    }
  }
  return num_filled;
}

}  // namespace colmap_lidar
