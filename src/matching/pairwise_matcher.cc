#include "src/matching/pairwise_matcher.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <tuple>

#include "colmap_ext/util/logging.h"
#include "src/matching/candidate_views.h"
#include "colmap_ext/util/parallel.h"
#include "src/matching/segment_similarity.h"

namespace colmap_lidar {
namespace {

struct DirectedMatch {
  int view_from;
  int segment_from;
  int view_to;
  int segment_to;
  double score;
};

// Algorithm 1 for every segment of views[i].
std::vector<DirectedMatch> MatchView(const std::vector<MatchingView>& views,
                                     const int i,
                                     const LineMatchingOptions& options,
                                     size_t* num_candidate_views) {
  std::vector<DirectedMatch> matches;
  const MatchingView& view = views[i];
  for (size_t a = 0; a < view.segments.size(); ++a) {
    const MatchingSegment& segment = view.segments[a];
    QuerySegment query;
    query.start_in_world = segment.start_in_world;
    query.end_in_world = segment.end_in_world;
    query.descriptor = segment.descriptor;
    for (size_t j = 0; j < views.size(); ++j) {
      if (static_cast<int>(j) == i || views[j].segments.empty()) continue;
      const SegmentInView in_view = ProjectSegmentIntoView(
          query.start_in_world, query.end_in_world, views[j], options);
      if (!in_view.visible) continue;
      ++*num_candidate_views;
      const MatchingThresholds thresholds = EffectiveThresholds(
          options, in_view.depth, views[j].camera.MeanFocalLength());
      const ViewMatch match =
          FindBestMatchInView(query, in_view, views[j], thresholds, options);
      if (match.segment_idx >= 0) {
        matches.push_back({i, static_cast<int>(a), static_cast<int>(j),
                           match.segment_idx, match.score});
      }
    }
  }
  return matches;
}

}  // namespace

std::vector<PairwiseLineMatch> MatchLinesPairwise(
    const std::vector<MatchingView>& views, const LineMatchingOptions& options,
    PairwiseMatchingStats* stats) {
  THROW_CHECK(options.Check(), "Invalid LineMatchingOptions");
  const auto start_time = std::chrono::steady_clock::now();
  const int num_views = static_cast<int>(views.size());
  std::vector<std::vector<DirectedMatch>> directed(num_views);
  std::vector<size_t> num_candidates(num_views, 0);
  ParallelFor(0, num_views, options.num_threads, [&](int i) {
    directed[i] = MatchView(views, i, options, &num_candidates[i]);
  });

  // Merge both directions into undirected pairs.
  std::map<std::tuple<int, int, int, int>, PairwiseLineMatch> merged;
  PairwiseMatchingStats local_stats;
  for (int i = 0; i < num_views; ++i) {
    local_stats.num_segments += views[i].segments.size();
    local_stats.num_candidate_views += num_candidates[i];
    local_stats.num_directed_matches += directed[i].size();
    for (const DirectedMatch& match : directed[i]) {
      PairwiseLineMatch pair;
      if (match.view_from < match.view_to) {
        pair = {match.view_from, match.segment_from, match.view_to,
                match.segment_to, match.score, false};
      } else {
        pair = {match.view_to, match.segment_to, match.view_from,
                match.segment_from, match.score, false};
      }
      const auto key =
          std::make_tuple(pair.view1, pair.segment1, pair.view2, pair.segment2);
      const auto [it, inserted] = merged.emplace(key, pair);
      if (!inserted) {
        it->second.mutual = true;
        it->second.score = std::min(it->second.score, pair.score);
      }
    }
  }
  std::vector<PairwiseLineMatch> matches;
  matches.reserve(merged.size());
  for (const auto& [key, match] : merged) {
    local_stats.num_mutual_matches += match.mutual ? 1 : 0;
    if (options.cross_check && !match.mutual) continue;
    matches.push_back(match);
  }
  local_stats.num_matches = matches.size();
  local_stats.seconds = std::chrono::duration<double>(
                            std::chrono::steady_clock::now() - start_time)
                            .count();
  if (stats != nullptr) *stats = local_stats;
  return matches;
}

}  // namespace colmap_lidar
