#include "src/lines/scan_projection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

bool ScanProjectionOptions::Check() const {
  if (!(min_depth > 0.0 && max_depth > min_depth)) {
    LOG(ERROR) << "LineExtraction.min_depth / max_depth: need 0 < min < max";
    return false;
  }
  if (zbuffer_cell_px < 1) {
    LOG(ERROR) << "LineExtraction.zbuffer_cell_px must be >= 1";
    return false;
  }
  if (!(zbuffer_relative_tolerance >= 0.0) ||
      !(zbuffer_absolute_tolerance >= 0.0)) {
    LOG(ERROR) << "LineExtraction.zbuffer_*_tolerance must be >= 0";
    return false;
  }
  return true;
}

PixelGrid::PixelGrid(const int width, const int height, const int cell_px)
    : cell_px_(cell_px),
      num_x_((width + cell_px - 1) / cell_px),
      num_y_((height + cell_px - 1) / cell_px),
      cells_(static_cast<size_t>(num_x_) * num_y_) {}

void PixelGrid::Insert(const int idx, const Eigen::Vector2d& pixel) {
  const int x = std::clamp(static_cast<int>(pixel.x()) / cell_px_, 0, num_x_ - 1);
  const int y = std::clamp(static_cast<int>(pixel.y()) / cell_px_, 0, num_y_ - 1);
  cells_[y * num_x_ + x].push_back(idx);
}

ProjectedScan ProjectScan(const LidarScan& scan, const Camera& camera,
                          const Rigid3d& cam_from_lidar,
                          const ScanProjectionOptions& options) {
  const int width = static_cast<int>(camera.width);
  const int height = static_cast<int>(camera.height);
  THROW_CHECK(width > 0 && height > 0, "ProjectScan: camera without size");
  const size_t n = scan.points.size();
  ProjectedScan projected;
  projected.points_in_cam.resize(n);
  projected.pixels.assign(n, Eigen::Vector2d::Constant(-1.0));
  projected.visible.assign(n, false);

  const Eigen::Matrix3d rotation = cam_from_lidar.rotation.toRotationMatrix();
  projected.lidar_from_cam_rotation = rotation.transpose();
  double min_elevation = 0.0;
  double max_elevation = 0.0;
  bool any_elevation = false;
  const int cell = options.zbuffer_cell_px;
  const int zb_width = (width + cell - 1) / cell;
  const int zb_height = (height + cell - 1) / cell;
  std::vector<float> zbuffer(static_cast<size_t>(zb_width) * zb_height,
                             std::numeric_limits<float>::max());
  std::vector<int> zbuffer_cell(n, -1);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d point_in_cam =
        rotation * scan.points[i].cast<double>() + cam_from_lidar.translation;
    projected.points_in_cam[i] = point_in_cam;
    const Eigen::Vector3f& point = scan.points[i];
    const double elevation =
        std::atan2(static_cast<double>(point.z()),
                   std::hypot(static_cast<double>(point.x()),
                              static_cast<double>(point.y())));
    if (std::isfinite(elevation)) {
      min_elevation = any_elevation ? std::min(min_elevation, elevation)
                                    : elevation;
      max_elevation = any_elevation ? std::max(max_elevation, elevation)
                                    : elevation;
      any_elevation = true;
    }
    if (point_in_cam.z() < options.min_depth ||
        point_in_cam.z() > options.max_depth) {
      continue;
    }
    const Eigen::Vector2d pixel = camera.ImgFromCam(point_in_cam);
    if (!(pixel.x() >= 0.0 && pixel.y() >= 0.0 && pixel.x() < width &&
          pixel.y() < height)) {
      continue;
    }
    projected.pixels[i] = pixel;
    const int cell_idx = (static_cast<int>(pixel.y()) / cell) * zb_width +
                         static_cast<int>(pixel.x()) / cell;
    zbuffer_cell[i] = cell_idx;
    zbuffer[cell_idx] =
        std::min(zbuffer[cell_idx], static_cast<float>(point_in_cam.z()));
  }
  projected.min_elevation_rad = min_elevation;
  projected.max_elevation_rad = max_elevation;
  projected.visible_grid = PixelGrid(width, height, 16);
  for (size_t i = 0; i < n; ++i) {
    if (zbuffer_cell[i] < 0) {
      continue;
    }
    const double min_depth = zbuffer[zbuffer_cell[i]];
    if (projected.points_in_cam[i].z() <=
        min_depth * (1.0 + options.zbuffer_relative_tolerance) +
            options.zbuffer_absolute_tolerance) {
      projected.visible[i] = true;
      projected.visible_grid.Insert(static_cast<int>(i), projected.pixels[i]);
      ++projected.num_visible;
    }
  }
  return projected;
}

bool WithinLidarElevation(const ProjectedScan& projected,
                          const Eigen::Vector3d& ray_in_cam,
                          const double margin_rad) {
  const Eigen::Vector3d ray = projected.lidar_from_cam_rotation * ray_in_cam;
  const double elevation = std::atan2(ray.z(), std::hypot(ray.x(), ray.y()));
  return elevation >= projected.min_elevation_rad + margin_rad &&
         elevation <= projected.max_elevation_rad - margin_rad;
}

}  // namespace colmap_lidar
