// Depth and normal initialisation of PatchMatch from visual features and
// the fused LIDAR cloud (paper section III-E): "we initialize each depth
// map's pixel using the depth of a visual feature, if available. Otherwise,
// we initialize with the range provided by the LIDAR ... we extend the
// [occlusion] verification to a neighborhood. We check the consistency of
// the pixel's depth with respect to the average depth in the neighborhood.
// We keep the LIDAR measurement only if the depth is consistent with the
// local average."
//
// LIDAR voxels are projected into the view with a per-pixel z-buffer (the
// nearest wins, Li et al.'s pixel-scale rule; with
// lidar_samples_at_pixel_centres each voxel's depth is first carried along
// its plane to its pixel's centre, and the pixel takes the median of its
// front surface's depths: within occlusion_relative_tolerance of the
// nearest, up to the first gap of 1 % of depth); then a sample is kept only
// if its depth is at most (1 + occlusion_relative_tolerance) times the mean
// depth of the z-buffer samples within occlusion_window_radius pixels. A
// LIDAR point seen through a gap of a foreground surface, or from the
// scanner's different viewpoint behind an edge, lands among nearer
// foreground samples and is dropped. Features (sparse 3D points observed by
// the view) override LIDAR samples in their pixel and are not checked.
// Normals come from the LIDAR local planes (the fused cloud's normals),
// rotated into the camera and turned to face it; a feature takes the normal
// of the nearest LIDAR sample in the window, else faces the camera.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "src/mvs/mvs_view.h"
#include "src/mvs/patch_match_options.h"

namespace colmap_lidar {

struct DepthSample {
  int row = 0;
  int col = 0;
  // z-depth, reference camera frame.
  float depth = 0.0f;
  // Unit, camera frame, facing the camera.
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  bool from_feature = false;
};

struct DepthInitStats {
  size_t num_lidar_in_view = 0;   // Projected inside the image, in front.
  size_t num_lidar_zbuffer = 0;   // Nearest in their pixel.
  size_t num_lidar_occluded = 0;  // Dropped by the neighbourhood check.
  size_t num_features = 0;
  // Pixels whose initial plane the view's own scan decided
  // (lidar_own_scan_min_incidence_deg; set by InitializeReference).
  size_t num_own_scan_pixels = 0;
};

// LIDAR points and normals in the world (normals may be zero: "unknown").
// Returns the kept samples, one per pixel at most, in row-major order.
std::vector<DepthSample> ProjectLidarSamples(
    const MvsView& view, const std::vector<Eigen::Vector3f>& points_in_world,
    const std::vector<Eigen::Vector3f>& normals_in_world,
    const LidarPatchMatchOptions& options, DepthInitStats* stats = nullptr);

// Features (world points observed by the view) over the LIDAR samples:
// a feature replaces the LIDAR sample of its pixel.
std::vector<DepthSample> MergeFeatureSamples(
    const MvsView& view, const std::vector<Eigen::Vector3f>& features_in_world,
    const std::vector<DepthSample>& lidar_samples,
    const LidarPatchMatchOptions& options, DepthInitStats* stats = nullptr);

// Per-pixel depth of the samples (0 elsewhere), row-major: the soft prior.
std::vector<float> SamplesToPriorDepth(const std::vector<DepthSample>& samples,
                                       int width, int height);

}  // namespace colmap_lidar
