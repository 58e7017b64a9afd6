// Source-view selection for PatchMatch, from the sparse model and the LIDAR
// co-visibility (the fused cloud's .vis lists): the score of a candidate is
// the number of sparse points both images observe plus
// lidar_covisibility_weight x the number of LIDAR voxels both frames' scans
// hit. Candidates must see the reference's median-depth point (from its
// sparse points, else its LIDAR voxels) under at least
// min_triangulation_angle_deg; when they share at least 5 sparse points, the
// median triangulation angle of those points must reach it instead (the
// point ahead of a camera moving along its axis is seen under no angle). patch-match.cfg decides the candidates:
// "__auto__, N" and "__all__" rank all other images (at most
// min(N, max_num_src_images)); an explicit list is taken as given (names
// not in the model are skipped with a warning).
#pragma once

#include <vector>

#include "colmap_ext/mvs/fused_vis.h"
#include "colmap_ext/mvs/stereo_config.h"
#include "colmap_ext/scene/reconstruction.h"
#include "src/mvs/patch_match_options.h"

namespace colmap_lidar {

class SourceViewSelector {
 public:
  // `lidar_visibility` may be empty; image indices are positions in
  // model.images.
  SourceViewSelector(const Reconstruction& model,
                     const FusedVisibility& lidar_visibility,
                     const std::vector<Eigen::Vector3f>& lidar_points,
                     const LidarPatchMatchOptions& options);

  // Image indices of the sources, best first. Empty when none qualifies.
  std::vector<int> Select(int ref_idx, const PatchMatchEntry& entry) const;

  int NumSharedPoints(int a, int b) const { return shared_points_[a][b]; }
  int NumSharedVoxels(int a, int b) const { return shared_voxels_[a][b]; }
  // Median z-depth of the sparse points (else LIDAR voxels) seen by `idx`;
  // 0 when it has none.
  double MedianDepth(int idx) const { return median_depth_[idx]; }

 private:
  const Reconstruction& model_;
  LidarPatchMatchOptions options_;
  std::vector<std::vector<int>> shared_points_;
  std::vector<std::vector<int>> shared_voxels_;
  std::vector<double> median_depth_;
  // Sparse points seen by each image and at least one other (pointers into
  // model_.points3D).
  std::vector<std::vector<const Point3D*>> points_of_image_;
};

}  // namespace colmap_lidar
