// A small synthetic camera + LIDAR view for the tests and the benchmark of
// the line module: yawed boxes on a ground plane, rendered (shaded by face,
// 2x2 supersampled) into a pinhole image and scanned by an OS1-64-like
// spinning LIDAR (uniform rings and columns, organised, ring channel set).
// The ground-truth box edges come with it, in the camera frame.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {

// A box in the LIDAR frame (x forward, y left, z up): centre, half sizes,
// yaw about z (radians), grey level of its faces (0..1, faces are shaded).
struct SyntheticBox {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d half_size = Eigen::Vector3d::Ones();
  double yaw = 0.0;
  double albedo = 0.7;
};

struct SyntheticViewOptions {
  int width = 848;
  int height = 480;
  double focal_length = 420.0;
  int num_rings = 64;
  int num_columns = 1024;
  double min_elevation_deg = -16.6;
  double max_elevation_deg = 16.6;
  double max_range = 100.0;
  // Gaussian range noise, metres.
  double range_noise = 0.0;
  // The ground plane z = ground_z, LIDAR frame, within |x|, |y| < 40 m.
  double ground_z = -1.6;
  // A painted stripe on the ground (texture only): x in [x0, x1] at all y.
  bool paint_stripe = false;
  double stripe_x0 = 5.0;
  double stripe_x1 = 5.4;
  std::vector<SyntheticBox> boxes;
  uint32_t seed = 1;
};

struct SyntheticView {
  cv::Mat image;  // 8-bit grey
  LidarScan scan;
  Camera camera;  // PINHOLE
  Rigid3d cam_from_lidar;
  // The boxes' 12 edges each, camera frame.
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> edges_in_cam;
};

// Three boxes at 6 .. 14 m in front (the default test scene).
std::vector<SyntheticBox> DefaultSyntheticBoxes();

SyntheticView MakeSyntheticView(const SyntheticViewOptions& options);

// Distance from p to the segment [a, b].
double DistanceToSegment3D(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const Eigen::Vector3d& p);

// Distance from a camera-frame point to the nearest box edge of the view.
double DistanceToNearestEdge(const SyntheticView& view,
                             const Eigen::Vector3d& point_in_cam);

}  // namespace colmap_lidar
