#include "src/eval/reference_visibility.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "colmap_ext/util/logging.h"
#include "src/eval/nearest_neighbor.h"

namespace colmap_lidar {

bool ReferenceVisibilityOptions::Check() const {
  bool ok = true;
  if (!std::isfinite(point_spacing_m)) {
    LOG(ERROR) << "ReferenceVisibility.point_spacing_m must be finite";
    ok = false;
  }
  if (!(relative_tolerance >= 0.0) || !std::isfinite(relative_tolerance)) {
    LOG(ERROR) << "ReferenceVisibility.relative_tolerance must be >= 0, got "
               << relative_tolerance;
    ok = false;
  }
  if (!(max_depth_m >= 0.0) || !std::isfinite(max_depth_m)) {
    LOG(ERROR) << "ReferenceVisibility.max_depth_m must be >= 0, got "
               << max_depth_m;
    ok = false;
  }
  if (max_splat_radius_px < 0) {
    LOG(ERROR) << "ReferenceVisibility.max_splat_radius_px must be >= 0, got "
               << max_splat_radius_px;
    ok = false;
  }
  return ok;
}

double MedianPointSpacing(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 2) {
    return 0.0;
  }
  // Every step-th point queries the index of all the others.
  const size_t step = std::max<size_t>(2, points.size() / 20000);
  std::vector<Eigen::Vector3d> queries;
  std::vector<Eigen::Vector3d> others;
  for (size_t i = 0; i < points.size(); ++i) {
    (i % step == 0 ? queries : others).push_back(points[i]);
  }
  std::vector<double> distances =
      PointCloudIndex(others).NearestDistances(queries);
  std::nth_element(distances.begin(), distances.begin() + distances.size() / 2,
                   distances.end());
  return distances[distances.size() / 2];
}

std::vector<bool> VisibleFromCameras(
    const std::vector<Eigen::Vector3d>& points, const Reconstruction& model,
    const ReferenceVisibilityOptions& options) {
  THROW_CHECK(options.Check(), "Invalid ReferenceVisibility options");
  for (const Eigen::Vector3d& point : points) {
    THROW_CHECK(point.allFinite(),
                "The reference cloud has a non-finite point");
  }
  const double spacing = options.point_spacing_m > 0.0
                             ? options.point_spacing_m
                             : MedianPointSpacing(points);
  const double max_depth = options.max_depth_m > 0.0
                               ? options.max_depth_m
                               : std::numeric_limits<double>::infinity();
  std::vector<bool> visible(points.size(), false);
  std::vector<double> depths(points.size());
  std::vector<Eigen::Vector2d> pixels(points.size());
  std::vector<float> buffer;
  size_t num_images = 0;
  // Thousands of images over millions of points take minutes: progress
  // once a minute.
  auto last_log = std::chrono::steady_clock::now();
  for (const Image& image : model.images) {
    if (std::chrono::steady_clock::now() - last_log > std::chrono::minutes(1)) {
      last_log = std::chrono::steady_clock::now();
      LOG(INFO) << "Reference visibility: " << num_images << " of "
                << model.images.size() << " images";
    }
    const auto camera_it = model.cameras.find(image.camera_id);
    THROW_CHECK(camera_it != model.cameras.end(),
                "image " << image.name << " has no camera " << image.camera_id);
    const Camera& camera = camera_it->second;
    const int width = static_cast<int>(camera.width);
    const int height = static_cast<int>(camera.height);
    const double focal = camera.MeanFocalLength();
    buffer.assign(static_cast<size_t>(width) * height,
                  std::numeric_limits<float>::infinity());
    // Pass 1: project and splat.
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d in_cam = image.cam_from_world * points[i];
      depths[i] = in_cam.z();
      if (!(in_cam.z() > 0.0) || in_cam.z() > max_depth) {
        continue;
      }
      pixels[i] = camera.ImgFromCam(in_cam);
      // Bounds in double first: a point just in front of the camera
      // projects far outside the int range.
      const double radius_px = std::min<double>(
          options.max_splat_radius_px, 0.5 * focal * spacing / in_cam.z());
      if (!(pixels[i].x() + radius_px >= 0.0 &&
            pixels[i].x() - radius_px < width &&
            pixels[i].y() + radius_px >= 0.0 &&
            pixels[i].y() - radius_px < height)) {
        // Also keeps pass 2 off this point (its pixel is outside).
        pixels[i] = Eigen::Vector2d(-1.0, -1.0);
        continue;
      }
      const int u = static_cast<int>(std::floor(pixels[i].x()));
      const int v = static_cast<int>(std::floor(pixels[i].y()));
      const int radius = static_cast<int>(std::lround(radius_px));
      const float depth = static_cast<float>(in_cam.z());
      for (int y = std::max(0, v - radius);
           y <= std::min(height - 1, v + radius); ++y) {
        float* row = buffer.data() + static_cast<size_t>(y) * width;
        for (int x = std::max(0, u - radius);
             x <= std::min(width - 1, u + radius); ++x) {
          row[x] = std::min(row[x], depth);
        }
      }
    }
    // Pass 2: a point at its own pixel within tolerance of the buffer.
    for (size_t i = 0; i < points.size(); ++i) {
      if (visible[i] || !(depths[i] > 0.0) || depths[i] > max_depth) {
        continue;
      }
      const int u = static_cast<int>(std::floor(pixels[i].x()));
      const int v = static_cast<int>(std::floor(pixels[i].y()));
      if (u < 0 || u >= width || v < 0 || v >= height) {
        continue;
      }
      const size_t pixel = static_cast<size_t>(v) * width + u;
      const double nearest = buffer[pixel];
      // The depth extent of the surface within this pixel: how much the
      // nearest depth changes to the next pixel. On ground seen at a
      // grazing angle one pixel spans metres of depth, all of it visible;
      // inside a wall that hides another it is the wall's own slope.
      double extent = 0.0;
      const int neighbours[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
      for (const auto& offset : neighbours) {
        const int x = u + offset[0];
        const int y = v + offset[1];
        if (x < 0 || x >= width || y < 0 || y >= height) {
          continue;
        }
        const double depth = buffer[static_cast<size_t>(y) * width + x];
        if (std::isfinite(depth)) {
          extent = std::max(extent, std::abs(depth - nearest));
        }
      }
      visible[i] = depths[i] <= nearest * (1.0 + options.relative_tolerance) +
                                    2.0 * spacing + extent;
    }
    ++num_images;
  }
  const size_t num_visible = std::count(visible.begin(), visible.end(), true);
  LOG(INFO) << "Reference visibility: " << num_visible << " of "
            << points.size() << " points seen by " << num_images
            << " images (point spacing " << spacing << " m)";
  return visible;
}

}  // namespace colmap_lidar
