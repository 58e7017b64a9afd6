// Pose-guided matching (issue 16; not in the paper): more SIFT matches
// between images whose poses are known to about a centimetre, found where
// the LIDAR puts each keypoint's match, for the triangulation of the next
// mapper iteration (src/sfm/mapper_iterations.h).
//
// Why: exact matching (src/sfm/exact_feature_matcher.h) keeps a match only
// when it is distinctly the best in the whole other image (ratio test).
// Frames of a forward walk 3.4 m apart see the side walls at grazing angles
// and repeated textures (brick, stone): on the corridor OS1-64 cell 1,400-
// 3,000 keypoints per image gave 50-100 verified matches per consecutive
// pair and 407 points for 20 images, and the steps along the corridor,
// which the LIDAR registrations hardly see, rest on them. Once the first
// adjustment has placed the cameras, a keypoint's match can only lie near
// a short stretch of its epipolar line: the projection of its ray between
// the depths that the image's own scan gives around it. The ratio test
// among the few keypoints there keeps many more matches. Stock COLMAP's
// guided matching, which knows only the fundamental matrix, searches the
// whole epipolar line and on a forward walk (all lines through the epipole)
// added wrong matches: 3 times the points and 1.00 cm instead of 1.44 cm on
// the corridor VLP-16 cell, but 0.061 instead of 0.029 deg.
//
// Per pair (image 1, image 2) of trusted images, each image with its
// nearest ones, in both directions
// (source s, target t):
// - depth: each keypoint of s takes the z-depths of the num_depth_neighbors
//   scan points of s nearest to it in the image, all within
//   max_depth_neighbor_angle_deg of its pixel (else it has no depth and no
//   guided match from this side); its interval [min, max] is widened by
//   depth_margin (relative);
// - candidates: the keypoints of t within a tolerance of the projection of
//   the ray of s between those depths; the tolerance is max_error_px plus
//   num_pose_sigmas times what the pose uncertainty (pose_sigma_m at the
//   interval's near end, pose_sigma_deg) moves a projection by. A candidate
//   with a depth interval of its own must hold the two rays' meeting point
//   in it (not a surface in front of or behind it), and its feature scale
//   must be within max_scale_ratio of the one the depths predict (a patch
//   at depth z appears at a scale proportional to f / z; as ORB-SLAM's
//   search by projection checks the scale level);
// - a match: the candidate with the smallest descriptor distance (the
//   angle, as COLMAP's matcher), below max_distance and below max_ratio
//   times the second candidate's (or times max_distance when it is the only
//   one), that is also the keypoint of s with the smallest distance among
//   those that took it as a candidate (mutual).
// The matches of both directions are united (one per keypoint, the
// verified matches of exact matching first).
//
// Measured on the benchmark matrix's 10 cells (docs/benchmarks/
// lidar_mapper.md): without the target's depth and the scales the added
// matches lay a median 3.0 px from where the true poses and surface put
// them on the HDL-32E street (exact matching's 1.2 px) and moved its poses
// by +0.03 cm; with them 1.8 px, and the worst cell went from 1.74 to
// 1.29 cm after sim3 (with the 2 nearest images).
//
// A pair whose verified matches (min_num_matches or more) do not fit the
// poses' epipolar geometry (fewer than min_agreement of them within the
// tolerance) keeps its matches as they are: the pose of one of its images
// may be wrong as well as the matches (dropping their matches instead, with
// every pair guided: corridor OS1-64 1.31 -> 1.50 cm).
// A pair gains its guided matches only when they number at
// least min_num_matches; one without a two-view geometry gets E and F from
// the poses (config CALIBRATED). The workspace's database is not changed:
// the result is a copy of the tables the triangulator reads (cameras,
// images, keypoints, two_view_geometries) in a database of its own.
#pragma once

#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/database/database.h"
#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/reconstruction.h"

namespace colmap_lidar {

struct PoseGuidedMatchingOptions {
  // On/off, 0/1 (lidar_mapper: after the first iteration, when the
  // initialisation is the LIDAR pose graph).
  bool enabled = true;
  // Pairs: each image with its num_nearest_images nearest images (by the
  // distance of the camera centres at the given poses), >= 0; 0: every pair
  // given. The nearest views share the most surface at the smallest change
  // of viewpoint; matching every pair of a dense walk added thousands of
  // matches to pairs that had hundreds and cost accuracy (the 60-frame
  // corridor VLP-16: 0.508 -> 0.675 cm after sim3; 2 nearest: 0.477 cm).
  int num_nearest_images = 2;
  // Scan points per keypoint for its depth interval, >= 1.
  int num_depth_neighbors = 4;
  // They lie within this angle of the keypoint's pixel (3 deg reaches the
  // next ring of a 16-ring LIDAR, 2 deg apart), degrees, > 0.
  double max_depth_neighbor_angle_deg = 3.0;
  // Relative widening of the depth interval on each side, >= 0.
  double depth_margin = 0.05;
  // Image noise of the tolerance, pixels, > 0 (exact matching's
  // verification threshold).
  double max_error_px = 4.0;
  // Relative pose uncertainty of the tolerance: lidar_mapper sets them to
  // its refined_pose_sigma_t_m / refined_pose_sigma_r_deg; >= 0.
  double pose_sigma_m = 0.01;
  double pose_sigma_deg = 0.05;
  double num_pose_sigmas = 2.0;  // > 0
  // Largest ratio between a candidate's feature scale and the scale the
  // depths predict (f / z of each side), >= 1; 0: no scale test (also when
  // the keypoints have no scale).
  double max_scale_ratio = 1.5;
  // Descriptor tests among the candidates (exact matching's), (0, 1] and
  // (0, pi].
  double max_ratio = 0.8;
  double max_distance = 0.7;
  // Guided matches a pair needs to gain them, and verified matches it needs
  // for the agreement test, >= 1.
  int min_num_matches = 15;
  // Share of a pair's verified matches the poses must explain, [0, 1].
  double min_agreement = 0.5;
  // Threads over the pairs; <= 0: all cores.
  int num_threads = -1;

  bool Check() const;
};

// A keypoint's depth interval; valid when max > 0.
struct KeypointDepth {
  float min_depth = 0.0f;
  float max_depth = 0.0f;
};

// Depth intervals of `keypoints` (pixels, rows x >= 2) from the points of
// the image's own scan in the camera frame (`points_in_cam`), see the file
// comment.
std::vector<KeypointDepth> KeypointDepthIntervals(
    const Camera& camera, const FeatureKeypointsBlob& keypoints,
    const std::vector<Eigen::Vector3f>& points_in_cam,
    const PoseGuidedMatchingOptions& options);

// One image as the matcher sees it.
struct GuidedMatchingImage {
  Camera camera;
  Rigid3d cam_from_world;
  FeatureKeypointsBlob keypoints;
  FeatureDescriptorsBlob descriptors;
  std::vector<KeypointDepth> depths;  // one per keypoint
};

// The guided matches of keypoints of `source` in `target` (rows: index in
// source, index in target), sorted by source index; see the file comment.
FeatureMatchesBlob GuidedMatchesOneWay(const GuidedMatchingImage& source,
                                       const GuidedMatchingImage& target,
                                       const PoseGuidedMatchingOptions& options);

// Share of `matches` (image1 index, image2 index) that lie within the
// tolerance of the poses' epipolar geometry, whatever their depth; 0 for
// none.
double EpipolarAgreement(const GuidedMatchingImage& image1,
                         const GuidedMatchingImage& image2,
                         const FeatureMatchesBlob& matches,
                         const PoseGuidedMatchingOptions& options);

struct PoseGuidedMatchingSummary {
  int num_pairs = 0;             // Pairs tried.
  int num_pairs_gained = 0;      // Pairs that gained matches.
  int num_pairs_disagreeing = 0;  // Left as they were (agreement test).
  size_t num_verified_before = 0;  // Inliers of the tried pairs before.
  size_t num_added = 0;            // Guided matches added.
  double seconds = 0.0;

  std::string ToString() const;
};

// The pairs of `pairs` that join an image with one of its
// num_nearest_images nearest images of `model` (camera centres; ties by
// id), in their order; all of them for num_nearest_images <= 0.
std::vector<std::pair<image_t, image_t>> NearestImagePairs(
    const Reconstruction& model,
    const std::vector<std::pair<image_t, image_t>>& pairs,
    int num_nearest_images);

// Guided matches for the NearestImagePairs of `pairs` (ids of `model`'s
// images, first < second) of
// the images in `trusted` at their poses in `model`, their scans read as
// lidar_mapper does (ext_lidar_scans; LidarScanFilePath).
// Writes the triangulation database `output_database_path` (replaced): the
// workspace database's cameras, images and keypoints, and every two-view
// geometry, merged with the guided matches. Throws colmap_lidar::Error
// naming the file on a missing image, camera or unreadable scan.
PoseGuidedMatchingSummary RunPoseGuidedMatching(
    const std::string& database_path,
    const Reconstruction& model, const std::unordered_set<image_t>& trusted,
    const std::vector<std::pair<image_t, image_t>>& pairs,
    const PoseGuidedMatchingOptions& options,
    const std::string& output_database_path);

}  // namespace colmap_lidar
