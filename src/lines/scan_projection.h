// A LIDAR scan seen from the camera: every point in the camera frame, its
// pixel, and whether the camera can see it. Visibility uses a coarse
// z-buffer so that points the LIDAR sees but the camera does not (hidden
// behind a nearer surface, e.g. through the LIDAR-camera parallax) are not
// associated with image lines (section III-B asks for points that
// *effectively* correspond to the observed line).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {

struct ScanProjectionOptions {
  // Points nearer / farther than this along the optical axis are ignored,
  // metres.
  double min_depth = 0.5;
  double max_depth = 120.0;
  // Z-buffer cell size, pixels. A point is hidden when its depth exceeds
  // the minimum depth in its cell by more than the tolerance below.
  int zbuffer_cell_px = 5;
  // Visible when depth <= min_cell_depth * (1 + relative) + absolute.
  double zbuffer_relative_tolerance = 0.1;
  double zbuffer_absolute_tolerance = 0.1;

  bool Check() const;
};

// Points bucketed by pixel cell, for neighbourhood queries in the image.
class PixelGrid {
 public:
  PixelGrid() = default;
  PixelGrid(int width, int height, int cell_px);
  void Insert(int idx, const Eigen::Vector2d& pixel);
  // Calls visit(idx) for every inserted index whose cell meets the box
  // [min, max] (pixels).
  template <typename Visit>
  void VisitBox(const Eigen::Vector2d& min, const Eigen::Vector2d& max,
                Visit&& visit) const {
    const int x0 = std::max(0, static_cast<int>(min.x()) / cell_px_);
    const int y0 = std::max(0, static_cast<int>(min.y()) / cell_px_);
    const int x1 =
        std::min(num_x_ - 1, static_cast<int>(std::max(0.0, max.x())) / cell_px_);
    const int y1 =
        std::min(num_y_ - 1, static_cast<int>(std::max(0.0, max.y())) / cell_px_);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        for (const int idx : cells_[y * num_x_ + x]) {
          visit(idx);
        }
      }
    }
  }

 private:
  int cell_px_ = 1;
  int num_x_ = 0;
  int num_y_ = 0;
  std::vector<std::vector<int>> cells_;
};

struct ProjectedScan {
  // One entry per scan point (same indices as the scan).
  std::vector<Eigen::Vector3d> points_in_cam;
  std::vector<Eigen::Vector2d> pixels;
  std::vector<bool> visible;
  // Visible points, bucketed in 16-pixel cells.
  PixelGrid visible_grid;
  int num_visible = 0;
  // The LIDAR's field of view as the scan shows it: the rotation of
  // directions from the camera into the LIDAR frame and the smallest and
  // largest elevation of the scan's points (radians; 0 / 0 for an empty
  // scan). A direction within it that holds no point saw no surface within
  // the LIDAR's range (sky, or a surface that returned nothing).
  Eigen::Matrix3d lidar_from_cam_rotation = Eigen::Matrix3d::Identity();
  double min_elevation_rad = 0.0;
  double max_elevation_rad = 0.0;
};

// Whether the LIDAR scanned the direction of the camera ray `ray_in_cam`,
// with a margin (radians) inside its elevation limits.
bool WithinLidarElevation(const ProjectedScan& projected,
                          const Eigen::Vector3d& ray_in_cam, double margin_rad);

ProjectedScan ProjectScan(const LidarScan& scan, const Camera& camera,
                          const Rigid3d& cam_from_lidar,
                          const ScanProjectionOptions& options);

}  // namespace colmap_lidar
