// 3D line tracks as the line bundle adjustment (paper section III-D) sees
// them: an infinite line in Pluecker coordinates plus its per-view
// observations (2D segment endpoints and, where the LIDAR saw the edge, the
// 3D segment endpoints in that camera's frame). The association stage
// (section III-C) produces these; after the adjustment they are stored in a
// Reconstruction as Line3D (colmap_ext/scene/line3d.h, lines3D.bin).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/line3d.h"
#include "colmap_ext/scene/reconstruction.h"
#include "colmap_ext/util/types.h"

namespace colmap_lidar {

struct LineObservation {
  image_t image_id = kInvalidImageId;
  // Index of the 2D segment among that image's line segments.
  uint32_t line2D_idx = 0;
  // Observed 2D segment endpoints in pixels (SfM convention, centre of the
  // upper-left pixel at (0.5, 0.5)), distorted as detected in the image.
  Eigen::Vector2d start2D = Eigen::Vector2d::Zero();
  Eigen::Vector2d end2D = Eigen::Vector2d::Zero();
  // True when start_in_cam / end_in_cam hold the LIDAR 3D segment of this
  // view (section III-A), in the camera frame, metres.
  bool has_lidar = false;
  Eigen::Vector3d start_in_cam = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_in_cam = Eigen::Vector3d::Zero();
};

struct LineTrack {
  line3D_t line3D_id = kInvalidLine3DId;
  // Infinite line (direction d, moment m = p x d) with |d| = 1, world frame.
  // All zeros means "not initialised yet" (see InitializeLineFromLidar).
  Eigen::Matrix<double, 6, 1> plucker_in_world =
      Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<LineObservation> observations;
  // Finite extent on the infinite line (ComputeLineSegment), world frame.
  Eigen::Vector3d start_in_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_in_world = Eigen::Vector3d::Zero();
  // Mean line reprojection error over the observations in pixels (distance
  // of the observed endpoints to the projected line); -1 when unknown.
  double error = -1.0;
};

// True when plucker_in_world is set (|d| > 0).
bool IsLineInitialized(const LineTrack& track);

// Initial infinite line from the observations' LIDAR 3D segments taken to
// the world with the current poses: the principal axis (PCA) of all LIDAR
// endpoints in the world frame. Returns false (track unchanged) when no
// observation has LIDAR data, an observation's image is missing, or the
// endpoints do not span a line (all within 1 mm).
bool InitializeLineFromLidar(const Reconstruction& reconstruction,
                             LineTrack* track);

// Initial infinite line from 2D observations only: intersection of the two
// viewing planes (camera centre + observed segment) that are the furthest
// from parallel. Returns false (track unchanged) when fewer than two views
// exist or all viewing planes are within min_angle_deg of each other.
bool InitializeLineFromViews(const Reconstruction& reconstruction,
                             LineTrack* track, double min_angle_deg = 1.0);

// Sets start_in_world / end_in_world from the infinite line: the observed
// 2D endpoints' viewing rays and the LIDAR endpoints (taken to the world)
// are projected onto the line and the extent over all views is kept.
// Returns false (endpoints unchanged) when the line is not initialised or
// no endpoint could be projected.
bool ComputeLineSegment(const Reconstruction& reconstruction,
                        LineTrack* track);

// Stored form of a track (lines3D.bin): the segment, error and the
// (image_id, line2D_idx) track elements.
Line3D LineTrackToLine3D(const LineTrack& track);

// Replaces reconstruction->lines3D with the tracks, keyed by line3D_id
// (throws colmap_lidar::Error on a duplicate or invalid id).
void SetReconstructionLines(const std::vector<LineTrack>& tracks,
                            Reconstruction* reconstruction);

}  // namespace colmap_lidar
