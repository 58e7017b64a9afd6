// The per-view line detection pipeline of section III-B: LSD segments in the
// image, LeGO-LOAM edge points in the LIDAR scan, association of the two
// (z-buffered projection, RANSAC, reprojection check, endpoint
// back-projection, texture rejection), fusion of duplicates, and an LBD
// descriptor per resulting segment.
#pragma once

#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/lidar_scan.h"
#include "src/lines/edge_association.h"
#include "src/lines/lidar_edges.h"
#include "src/lines/line_types.h"
#include "src/lines/lsd_detector.h"
#include "src/lines/plane_lifting.h"
#include "src/lines/scan_projection.h"
#include "src/lines/segment_fusion.h"

namespace colmap_lidar {

struct LineExtractionOptions {
  LsdOptions lsd;
  LidarEdgeOptions edges;
  ScanProjectionOptions projection;
  EdgeAssociationOptions association;
  PlaneLiftingOptions planes;
  SegmentFusionOptions fusion;
  // Compute the LBD descriptor of every output segment.
  bool compute_descriptors = true;
  // Worker threads of the workspace extractor (-1: all cores).
  int num_threads = -1;

  bool Check() const;
};

struct LineExtractionTimings {
  double lsd_ms = 0.0;
  double edges_ms = 0.0;
  double projection_ms = 0.0;
  // The scan's range noise (EstimateRangeNoise), when estimated.
  double noise_ms = 0.0;
  double association_ms = 0.0;
  double planes_ms = 0.0;
  double fusion_ms = 0.0;
  double descriptor_ms = 0.0;
  double TotalMs() const {
    return lsd_ms + edges_ms + projection_ms + noise_ms + association_ms +
           planes_ms + fusion_ms + descriptor_ms;
  }
};

// What became of one LSD segment, before the fusion of duplicates (the
// debug overlay and lifting report of --debug_path).
struct SegmentOutcome {
  LineSegment2D segment;
  LiftResult edge_result = LiftResult::kTooFewPoints;
  PlaneLiftResult plane_result = PlaneLiftResult::kNotTried;
  // The surface test's verdict (texture_rejection.h) when the edge-point
  // lifting reached it: why a kTexture segment was refused, what a lifted
  // one is (crease or occluding contour).
  std::optional<LineSurfaceType> edge_surface;
  // When lifted (by edge points or planes): the 2D segment as clipped to
  // its support and its 3D endpoints, camera frame.
  LineSegment2D lifted2D;
  Eigen::Vector3d start3D_in_cam = Eigen::Vector3d::Zero();
  Eigen::Vector3d end3D_in_cam = Eigen::Vector3d::Zero();

  bool Lifted() const {
    return edge_result == LiftResult::kLifted ||
           plane_result == PlaneLiftResult::kCrease ||
           plane_result == PlaneLiftResult::kOcclusion;
  }
};

struct ViewLines {
  // Lifted, fused segments with descriptors, longest 2D segment first.
  std::vector<ViewLineSegment> segments;
  // LSD segments (after the minimum length) and how many were lifted
  // before fusion.
  int num_lsd_segments = 0;
  int num_lifted_segments = 0;
  // Why the others were not lifted by edge points, indexed by LiftResult.
  std::vector<int> lift_result_counts;
  // Of those, lifted by the surfaces on their sides (plane_lifting.h).
  int num_plane_lifted_segments = 0;
  // Every LSD segment (after the minimum length), in detection order.
  std::vector<SegmentOutcome> outcomes;
  // The scan's range noise sigma that the texture test and the plane
  // lifting used, metres (0: neither needed it).
  double range_noise_m = 0.0;
  // Edge points of the scan and those the camera sees (for the overlay:
  // indices into the scan and their pixels).
  int num_edge_points = 0;
  std::vector<int> visible_edge_point_idxs;
  std::vector<Eigen::Vector2d> visible_edge_pixels;
  LineExtractionTimings timings;
};

// `image` is the view's image (8-bit grey or BGR, the size of the camera);
// the scan is in the LIDAR frame; p_cam = cam_from_lidar * p_lidar. An image
// whose size differs from the camera's throws. Options must pass Check().
ViewLines ExtractViewLines(const cv::Mat& image, const LidarScan& scan,
                           const Camera& camera, const Rigid3d& cam_from_lidar,
                           const LineExtractionOptions& options);

}  // namespace colmap_lidar
