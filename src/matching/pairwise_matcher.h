// Pairwise 3D/3D line matches over all views (paper section III-C,
// Algorithm 1 for every segment of every view): each segment, taken to the
// world with its view's current pose, is reprojected into every other view
// where it is a candidate (candidate_views.h) and matched to at most one
// segment there (segment_similarity.h). Matches found from either side are
// merged into undirected pairs.
//
// With uncertain poses (LineMatchingOptions::RegistersPairs), the poses are
// corrected first: every pair of views the priors make overlap is
// registered on its 3D segments (relative_line_pose.h), a robust pose graph
// keeps the consistent registrations (pose_graph.h), and Algorithm 1 runs
// on its poses with the exact-pose thresholds between views of one
// component of the consistent registrations (with the uncertainty-grown
// ones between components, e.g. views with too few segments to register).
#pragma once

#include <cstddef>
#include <vector>

#include "src/matching/line_matching_options.h"
#include "src/matching/matching_view.h"

namespace colmap_lidar {

// An undirected match between segment segment1 of views[view1] and segment
// segment2 of views[view2], with view1 < view2 (indices into the views).
struct PairwiseLineMatch {
  int view1 = -1;
  int segment1 = -1;
  int view2 = -1;
  int segment2 = -1;
  // Smallest Algorithm 1 score over the directions that found it, [0, 4).
  double score = 0.0;
  // Found from both sides (each is the other's best in its view).
  bool mutual = false;
};

struct PairwiseMatchingStats {
  size_t num_segments = 0;
  // (segment, view) candidate tests that passed the visibility test.
  size_t num_candidate_views = 0;
  // Directed matches (Algorithm 1 results), then undirected pairs.
  size_t num_directed_matches = 0;
  size_t num_matches = 0;
  size_t num_mutual_matches = 0;
  // With registration (LineMatchingOptions::RegistersPairs): view pairs the
  // prior makes overlap, those registered on their segments, and the time
  // it took (included in seconds).
  size_t num_overlapping_pairs = 0;
  size_t num_registered_pairs = 0;
  // Registrations the pose graph kept (pose_graph.h).
  size_t num_consistent_pairs = 0;
  double registration_seconds = 0.0;
  double seconds = 0.0;
};

// Sorted by (view1, segment1, view2, segment2). With options.cross_check
// only mutual matches are returned. Runs views in parallel
// (options.num_threads).
std::vector<PairwiseLineMatch> MatchLinesPairwise(
    const std::vector<MatchingView>& views, const LineMatchingOptions& options,
    PairwiseMatchingStats* stats = nullptr);

}  // namespace colmap_lidar
