// Which reference points the cameras could see: the "whole visible
// reference, occluded parts removed" of the paper's recall (Amblard et al.,
// Table II), as opposed to the part that the LIDAR covered
// (MeshEvaluationOptions::observed_cloud_path).
//
// A point is seen by a camera when it projects inside the image, lies in
// front of it (and within max_depth_m) and is not hidden by the reference's
// own surface. The surface is the reference cloud itself, splatted into a
// depth buffer per image: each point covers a square of about its spacing
// (the cloud's median nearest-neighbour distance, measured, unless
// point_spacing_m is given) at its depth, so that a surface sampled every
// 2 cm hides what lies behind it however close the camera is. A point is
// visible when its depth is within tolerance of the buffer at its own
// pixel: relative_tolerance of the depth, plus twice the spacing, plus the
// depth extent of the surface within the pixel (the largest change of the
// buffer to a neighbouring pixel: metres on ground seen at a grazing angle,
// whose far points share pixels with nearer ones; the slope of a wall that
// hides another). At a silhouette that extent is the depth step itself, so
// the points right behind an occluder's outline (one pixel wide) count as
// visible.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "colmap_ext/scene/reconstruction.h"

namespace colmap_lidar {

struct ReferenceVisibilityOptions {
  // Spacing of the reference's points, metres; <= 0 measures it (median
  // distance to the nearest other point of a sample of the cloud).
  double point_spacing_m = 0.0;
  // Depth tolerance relative to the depth, >= 0.
  double relative_tolerance = 0.01;
  // Points farther from a camera than this are not seen by it, metres; 0:
  // no limit.
  double max_depth_m = 0.0;
  // Largest half-size of a point's square in the depth buffer, pixels, >= 0
  // (bounds the cost of points very close to a camera).
  int max_splat_radius_px = 8;

  bool Check() const;
};

// For each point (in the model's world frame): seen by at least one image
// of `model`. Throws colmap_lidar::Error on invalid options, an image whose
// camera is missing, or non-finite points.
std::vector<bool> VisibleFromCameras(const std::vector<Eigen::Vector3d>& points,
                                     const Reconstruction& model,
                                     const ReferenceVisibilityOptions& options);

// The measured spacing used when options.point_spacing_m <= 0 (metres; 0 for
// fewer than 2 points).
double MedianPointSpacing(const std::vector<Eigen::Vector3d>& points);

}  // namespace colmap_lidar
