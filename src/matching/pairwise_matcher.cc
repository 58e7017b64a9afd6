#include "src/matching/pairwise_matcher.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <tuple>

#include "colmap_ext/util/logging.h"
#include "src/matching/candidate_views.h"
#include "colmap_ext/util/parallel.h"
#include "src/matching/pose_graph.h"
#include "src/matching/relative_line_pose.h"
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

// Algorithm 1 for every segment of views[i]. With `component`, views of
// views[i]'s component are matched with `registered_options` (their poses
// agree) and the others with `options`.
std::vector<DirectedMatch> MatchView(
    const std::vector<MatchingView>& views, const int i,
    const LineMatchingOptions& options,
    const LineMatchingOptions& registered_options,
    const std::vector<int>* component, size_t* num_candidate_views) {
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
      const LineMatchingOptions& pair_options =
          component != nullptr && (*component)[j] == (*component)[i]
              ? registered_options
              : options;
      const SegmentInView in_view = ProjectSegmentIntoView(
          query.start_in_world, query.end_in_world, views[j], pair_options);
      if (!in_view.visible) continue;
      ++*num_candidate_views;
      const MatchingThresholds thresholds = EffectiveThresholds(
          pair_options, in_view.depth, views[j].camera.MeanFocalLength());
      const ViewMatch match = FindBestMatchInView(query, in_view, views[j],
                                                  thresholds, pair_options);
      if (match.segment_idx >= 0) {
        matches.push_back({i, static_cast<int>(a), static_cast<int>(j),
                           match.segment_idx, match.score});
      }
    }
  }
  return matches;
}

// Registers every pair of views that the prior poses make overlap
// (relative_line_pose.h): per view i, the segments the prior places in view
// j's field of view (with the uncertainty-grown tolerances); pairs i < j
// with at least min_inliers of them are registered on them.
std::vector<PoseGraphEdge> RegisterPairs(const std::vector<MatchingView>& views,
                                         const LineMatchingOptions& options,
                                         PairwiseMatchingStats* stats) {
  const int num_views = static_cast<int>(views.size());
  std::vector<std::vector<std::pair<int, std::vector<int>>>> visible(num_views);
  ParallelFor(0, num_views, options.num_threads, [&](int i) {
    for (int j = i + 1; j < num_views; ++j) {
      std::vector<int> segments;
      for (size_t a = 0; a < views[i].segments.size(); ++a) {
        const MatchingSegment& segment = views[i].segments[a];
        if (ProjectSegmentIntoView(segment.start_in_world,
                                   segment.end_in_world, views[j], options)
                .visible) {
          segments.push_back(static_cast<int>(a));
        }
      }
      if (static_cast<int>(segments.size()) >=
          options.relative_pose_min_inliers) {
        visible[i].emplace_back(j, std::move(segments));
      }
    }
  });
  std::vector<std::pair<int, int>> pairs;  // (i, position in visible[i])
  for (int i = 0; i < num_views; ++i) {
    for (size_t k = 0; k < visible[i].size(); ++k) {
      pairs.emplace_back(i, static_cast<int>(k));
    }
  }
  std::vector<RelativeLinePose> poses(pairs.size());
  ParallelFor(0, static_cast<int>(pairs.size()), options.num_threads,
              [&](int p) {
    const auto& [i, k] = pairs[p];
    const auto& [j, segments] = visible[i][k];
    poses[p] = EstimateRelativeLinePose(views[i], segments, views[j], options,
                                        /*seed=*/static_cast<uint32_t>(p + 1));
  });
  std::vector<PoseGraphEdge> edges;
  for (size_t p = 0; p < pairs.size(); ++p) {
    if (!poses[p].valid) continue;
    const int i = pairs[p].first;
    edges.push_back({i, visible[i][pairs[p].second].first,
                     poses[p].cam2_from_cam1, poses[p].information});
  }
  stats->num_overlapping_pairs = pairs.size();
  stats->num_registered_pairs = edges.size();
  return edges;
}

}  // namespace

std::vector<PairwiseLineMatch> MatchLinesPairwise(
    const std::vector<MatchingView>& views, const LineMatchingOptions& options,
    PairwiseMatchingStats* stats) {
  THROW_CHECK(options.Check(), "Invalid LineMatchingOptions");
  const auto start_time = std::chrono::steady_clock::now();
  const int num_views = static_cast<int>(views.size());
  PairwiseMatchingStats local_stats;
  // With registration, Algorithm 1 runs on the views moved to the pose
  // graph's poses, with the exact-pose thresholds within the components of
  // the consistent registrations, and the uncertainty-grown ones between
  // components (views that did not register keep their priors).
  std::vector<MatchingView> registered_views;
  std::vector<int> component;
  LineMatchingOptions registered_options = options;
  if (options.RegistersPairs()) {
    const std::vector<PoseGraphEdge> edges =
        RegisterPairs(views, options, &local_stats);
    PoseGraphOptions graph_options;
    graph_options.prior_sigma_t_m = std::max(options.pose_sigma_t_m, 1e-3);
    graph_options.prior_sigma_r_deg = std::max(options.pose_sigma_r_deg, 1e-3);
    std::vector<Rigid3d> priors;
    for (const MatchingView& view : views) priors.push_back(view.cam_from_world);
    const PoseGraphResult graph =
        OptimizePoseGraph(priors, edges, graph_options);
    local_stats.num_consistent_pairs = graph.num_inlier_edges;
    registered_views = views;
    for (int v = 0; v < num_views; ++v) {
      UpdateMatchingViewPose(graph.cam_from_world[v], &registered_views[v]);
    }
    component = graph.component;
    local_stats.registration_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                      start_time)
            .count();
    LOG(INFO) << "Registered " << local_stats.num_registered_pairs << " of "
              << local_stats.num_overlapping_pairs
              << " overlapping view pairs on their segments, "
              << local_stats.num_consistent_pairs
              << " consistent in the pose graph, in "
              << local_stats.registration_seconds << " s";
    registered_options.pose_sigma_t_m = 0.0;
    registered_options.pose_sigma_r_deg = 0.0;
  }
  const std::vector<MatchingView>& match_views =
      options.RegistersPairs() ? registered_views : views;
  std::vector<std::vector<DirectedMatch>> directed(num_views);
  std::vector<size_t> num_candidates(num_views, 0);
  ParallelFor(0, num_views, options.num_threads, [&](int i) {
    directed[i] = MatchView(match_views, i, options, registered_options,
                            options.RegistersPairs() ? &component : nullptr,
                            &num_candidates[i]);
  });

  // Merge both directions into undirected pairs.
  std::map<std::tuple<int, int, int, int>, PairwiseLineMatch> merged;
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
