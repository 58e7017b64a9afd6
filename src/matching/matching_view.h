// One view as the 3D/3D line association (paper section III-C) sees it:
// its camera, its current pose, its 3D line segments (ext_line_segments)
// taken to the world frame, and optionally a coarse LIDAR depth image for
// the occlusion test of the candidate views.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/reconstruction.h"
#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"
#include "src/matching/line_matching_options.h"

namespace colmap_lidar {

// The nearest LIDAR depth per image cell: a sample farther than the
// surface the LIDAR saw in its cell is hidden.
class LidarDepthGrid {
 public:
  LidarDepthGrid() = default;
  // Points in the camera frame, metres; those nearer than min_depth or
  // outside the image are ignored.
  LidarDepthGrid(const std::vector<Eigen::Vector3d>& points_in_cam,
                 const Camera& camera, int cell_px, double min_depth);

  bool empty() const { return depths_.empty(); }
  // Nearest LIDAR depth of the cell of `pixel`; +infinity when the cell saw
  // nothing or the grid is empty.
  double NearestDepth(const Eigen::Vector2d& pixel) const;

 private:
  int cell_px_ = 1;
  int num_x_ = 0;
  int num_y_ = 0;
  std::vector<float> depths_;
};

// A segment of a view, with what Algorithm 1 needs precomputed.
struct MatchingSegment {
  // Detected 2D segment, pixels (COLMAP convention).
  Eigen::Vector2d start2D = Eigen::Vector2d::Zero();
  Eigen::Vector2d end2D = Eigen::Vector2d::Zero();
  // Unit 2D direction and the 2D line (a, b, c), a^2 + b^2 = 1.
  Eigen::Vector2d direction2D = Eigen::Vector2d::UnitX();
  Eigen::Vector3d line2D = Eigen::Vector3d::Zero();
  // Orientation of the 2D segment in [0, 180) degrees.
  double angle_deg = 0.0;
  // 3D endpoints, camera frame and world frame (current pose).
  Eigen::Vector3d start_in_cam = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_in_cam = Eigen::Vector3d::Zero();
  Eigen::Vector3d start_in_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_in_world = Eigen::Vector3d::Zero();
  std::array<uint8_t, 32> descriptor{};
};

struct MatchingView {
  image_t image_id = kInvalidImageId;
  std::string name;
  Camera camera;
  Rigid3d cam_from_world;
  std::vector<MatchingSegment> segments;
  LidarDepthGrid lidar_depth;
  // Segment indices bucketed by 2D orientation (kAngleBucketDeg wide).
  std::vector<std::vector<int>> angle_buckets;

  static constexpr double kAngleBucketDeg = 5.0;
};

// Builds a view from its segments (idx = position) and pose. The depth grid
// stays empty; set it with LidarDepthGrid when a scan is available.
MatchingView MakeMatchingView(image_t image_id, const std::string& name,
                              const Camera& camera,
                              const Rigid3d& cam_from_world,
                              const std::vector<LineSegmentRecord>& segments);

// Re-derives the world endpoints after the pose changed.
void UpdateMatchingViewPose(const Rigid3d& cam_from_world, MatchingView* view);

// The views of every model image that has line segments in the database
// (model image ids are database ids; a name mismatch throws). With
// options.use_lidar_visibility, each view's LIDAR scan (ext_lidar_scans,
// relative paths against the database's folder) fills its depth grid; a
// missing scan leaves the grid empty with a warning. Loads in parallel.
std::vector<MatchingView> LoadMatchingViews(const Database& database,
                                            const Reconstruction& model,
                                            const LineMatchingOptions& options);

}  // namespace colmap_lidar
