// Deterministic SIFT matching and geometric verification into COLMAP's
// matches and two_view_geometries tables, in place of stock
// exhaustive_matcher / sequential_matcher.
//
// Why: stock COLMAP 3.8's CPU matchers give other raw matches and other
// inliers run after run on the same database, also with one thread
// (measured: 6 images, two runs of exhaustive_matcher, matches and
// two_view_geometries both differ); the mapper then returns other models
// (issue 16: the same recording must give the same poses). Here:
//  - matching is exact: every descriptor against every other of the pair
//    (dot products of COLMAP's uint8 SIFT descriptors, whose L2 norm is
//    512), distance = acos(dot / 512^2) as COLMAP's matcher, kept when the
//    best is below max_distance and below max_ratio times the second best,
//    and, with cross_check, when the two descriptors are each other's best;
//  - verification: an essential matrix by RANSAC (OpenCV, whose generator
//    has a fixed seed) on the keypoints undistorted by their camera, with
//    max_error_px over the mean focal length as the threshold; the pair is
//    kept (config CALIBRATED, E and F = K2^-T E K1^-1) when it has at least
//    min_num_inliers inliers and min_inlier_ratio of the matches.
// Pairs are independent and written in a fixed order, so the tables do not
// depend on the number of threads.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "colmap_ext/database/database.h"

namespace colmap_lidar {

struct ExactMatchingOptions {
  // COLMAP's SiftMatching defaults: ratio test, largest descriptor
  // distance (radians of the unit descriptors), mutual best.
  double max_ratio = 0.8;    // (0, 1]
  double max_distance = 0.7;  // (0, pi]
  bool cross_check = true;
  // Verification: RANSAC threshold, pixels, > 0; confidence in (0, 1);
  // iterations >= 1; inliers needed, absolute (>= 5) and as a share of the
  // matches ([0, 1]).
  double max_error_px = 4.0;
  double confidence = 0.999;
  int max_num_trials = 10000;
  int min_num_inliers = 15;
  double min_inlier_ratio = 0.25;
  // Threads over the pairs; <= 0: all cores.
  int num_threads = -1;

  bool Check() const;
};

// Descriptor distance as COLMAP's matcher: the angle (radians) between the
// unit descriptors whose uint8 dot product is `dot`.
float DotToDistance(float dot);

// RANSAC trials of the verification: max_num_trials, or fewer where more
// could change no verdict but by chance. A pair is kept only when at least
// min_inlier_ratio of its matches are inliers, and ln(1 - confidence) /
// ln(1 - min_inlier_ratio^5) trials (Fischler and Bolles' count, to which
// OpenCV's RANSAC lowers its budget for the ratio of its best model so far)
// find a model of that ratio with probability `confidence`. So a pair that
// passes stops within them anyway (its best model's ratio is above the
// minimum, so its count is below), and a pair that has no such model after
// them would find one later with probability below 1 - confidence. 7,071
// instead of 10,000 trials with the defaults; the 30 of 545 pairs that fail
// on 60 corridor frames spent 30 s of CPU in them.
int VerificationTrials(const ExactMatchingOptions& options);

// The best match of each row descriptor of `descriptors1` among those of
// `descriptors2` under the rules above; rows x 2 (index in 1, index in 2),
// sorted by the first index.
FeatureMatchesBlob MatchDescriptors(const FeatureDescriptorsBlob& descriptors1,
                                    const FeatureDescriptorsBlob& descriptors2,
                                    const ExactMatchingOptions& options);

struct ExactMatchingSummary {
  int num_pairs = 0;           // Pairs matched.
  int num_pairs_skipped = 0;   // Pairs that had matches already.
  int num_verified_pairs = 0;  // Pairs with a two-view geometry written.
  size_t num_matches = 0;
  size_t num_inlier_matches = 0;
};

// Image pairs by image id (first < second): every pair when the database
// has at most `exhaustive_max_num_images` images, else each image with the
// `sequential_overlap` next ones in name order (and, with
// `quadratic_overlap`, the ones 2^k further for k < sequential_overlap), as
// stock sequential_matcher.
std::vector<std::pair<image_t, image_t>> MatchingPairs(
    const std::vector<DatabaseImage>& images, int exhaustive_max_num_images,
    int sequential_overlap, bool quadratic_overlap);

// Matches and verifies `pairs` of the database at `database_path`; pairs
// that already have matches are left as they are (as stock matchers do).
// Progress in the log at least every 20 s. Throws naming the database on a
// missing camera or keypoints of an unexpected shape.
ExactMatchingSummary RunExactMatching(
    const std::string& database_path,
    const std::vector<std::pair<image_t, image_t>>& pairs,
    const ExactMatchingOptions& options);

}  // namespace colmap_lidar
