// Algorithm 1 of the paper (section III-C): the similarity of a 3D segment
// l of view i, reprojected into a candidate view j, to each segment l'
// detected in view j, and the choice of the best one.
//
// The four criteria, computed in view j with the current poses:
//   a  angle(l, l', j): angle between the reprojected segment pi_j(l) and
//      the detected 2D segment of l', degrees in [0, 90];
//   b  distPixel(l, l', j): the pixel distance between the projected
//      endpoints, taken as the mean distance of the four endpoints (those of
//      pi_j(l) and of l') to the other segment's 2D line, so that two
//      observations of one edge with different extents score 0;
//   c  distOrtho(l, l', j): the norm of the midpoint difference
//      (s_l + e_l)/2 - (s_l' + e_l')/2 projected perpendicularly to l's 3D
//      direction, world frame, metres;
//   d  distFeat(l, l', j): the Hamming distance of the LBD descriptors.
// A candidate passes when a < t_theta, b < t_dP, c < t_dO, d < t_LBD (and,
// optionally, the overlap along the line reaches min_overlap); its score is
// s = a/t_theta + b/t_dP + c/t_dO + d/t_LBD; the match in view j is the
// passing candidate with the smallest s.
#pragma once

#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "src/matching/candidate_views.h"
#include "src/matching/line_matching_options.h"
#include "src/matching/matching_view.h"

namespace colmap_lidar {

// The segment l being matched: its world endpoints and descriptor.
struct QuerySegment {
  Eigen::Vector3d start_in_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_in_world = Eigen::Vector3d::Zero();
  std::array<uint8_t, 32> descriptor{};
};

struct SegmentComparison {
  double angle_deg = 0.0;
  double pixel_distance_px = 0.0;
  double orthogonal_distance_m = 0.0;
  double descriptor_distance = 0.0;
  // Overlap along pi_j(l) as a fraction of the shorter segment, [0, 1].
  double overlap = 0.0;
};

int HammingDistance(const std::array<uint8_t, 32>& a,
                    const std::array<uint8_t, 32>& b);

SegmentComparison CompareSegments(const QuerySegment& query,
                                  const SegmentInView& query_in_view,
                                  const MatchingSegment& candidate);

// True when every criterion is strictly below its threshold (and the overlap
// reaches min_overlap).
bool PassesThresholds(const SegmentComparison& comparison,
                      const MatchingThresholds& thresholds,
                      double min_overlap);

// a/t_theta + b/t_dP + c/t_dO + d/t_LBD.
double MatchingScore(const SegmentComparison& comparison,
                     const MatchingThresholds& thresholds);

struct ViewMatch {
  // Segment index in the view; -1 when no candidate passed.
  int segment_idx = -1;
  double score = 0.0;
};

// The overlap of b with a along a's 2D line, as a fraction of the shorter
// of the two, [0, 1]: 1 for two segments side by side.
double SideBySideOverlap(const MatchingSegment& a, const MatchingSegment& b);

// The inner loop of Algorithm 1 for one candidate view: only segments whose
// 2D orientation is within the angle threshold are scored (orientation
// buckets of the view). With options.max_rival_score_ratio < 1, the match
// is dropped when the runner-up lies side by side with it
// (SideBySideOverlap >= kMinRivalOverlap) and scores within that ratio:
// two parallel edges a few centimetres apart that the criteria cannot tell
// apart.
constexpr double kMinRivalOverlap = 0.5;
ViewMatch FindBestMatchInView(const QuerySegment& query,
                              const SegmentInView& query_in_view,
                              const MatchingView& view,
                              const MatchingThresholds& thresholds,
                              const LineMatchingOptions& options);

}  // namespace colmap_lidar
