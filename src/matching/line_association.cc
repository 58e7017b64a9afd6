#include "src/matching/line_association.h"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <map>
#include <numeric>
#include <sstream>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

double SecondsSince(const std::chrono::steady_clock::time_point& start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

// Without CLEAR: connected components, dropping those that hold two
// observations of one view (no way to tell which is right).
ClearResult ConnectedComponents(const std::vector<int>& view_ids,
                                const std::vector<ClearEdge>& edges) {
  const int n = static_cast<int>(view_ids.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const ClearEdge& edge : edges) {
    parent[find(edge.observation1)] = find(edge.observation2);
  }
  std::map<int, std::vector<int>> components;
  for (int i = 0; i < n; ++i) components[find(i)].push_back(i);
  ClearResult result;
  result.cluster_ids.assign(n, -1);
  result.num_input_edges = edges.size();
  for (const auto& [root, members] : components) {
    ++result.num_components;
    result.largest_component_size =
        std::max(result.largest_component_size, static_cast<int>(members.size()));
    std::vector<int> views;
    for (const int i : members) views.push_back(view_ids[i]);
    std::sort(views.begin(), views.end());
    if (std::adjacent_find(views.begin(), views.end()) != views.end()) continue;
    for (const int i : members) result.cluster_ids[i] = result.num_clusters;
    ++result.num_clusters;
  }
  for (const ClearEdge& edge : edges) {
    const int a = result.cluster_ids[edge.observation1];
    if (a < 0 || a != result.cluster_ids[edge.observation2]) {
      ++result.num_removed_edges;
    }
  }
  return result;
}

}  // namespace

std::string LineAssociationSummary::Format() const {
  std::ostringstream out;
  out << std::fixed << std::setprecision(2);
  out << "Line association: " << num_views << " views, "
      << pairwise.num_segments << " segments, " << pairwise.num_candidate_views
      << " (segment, candidate view) tests\n";
  if (pairwise.num_overlapping_pairs > 0) {
    out << "  Pair registration: " << pairwise.num_registered_pairs << " of "
        << pairwise.num_overlapping_pairs << " overlapping view pairs, "
        << pairwise.num_consistent_pairs << " consistent, in "
        << pairwise.registration_seconds << " s\n";
  }
  out << "  Pairwise matches (Algorithm 1): " << pairwise.num_matches << " ("
      << pairwise.num_mutual_matches << " mutual, "
      << pairwise.num_directed_matches << " directed) in " << pairwise.seconds
      << " s\n";
  out << "  Consistency: " << num_components << " components (largest "
      << largest_component_size << ", " << num_split_components
      << " split), " << num_matches_removed << " matches removed in "
      << clear_seconds << " s\n";
  out << "  Tracks: " << num_tracks << " with " << num_track_observations
      << " observations; observations per track mean " << mean_track_length
      << ", median " << median_track_length << ", max " << max_track_length
      << "\n";
  out << "  Time: load " << load_seconds << " s, total " << total_seconds
      << " s";
  return out.str();
}

LineAssociation AssociateLines(const std::vector<MatchingView>& views,
                               const LineMatchingOptions& options) {
  THROW_CHECK(options.Check(), "Invalid LineMatchingOptions");
  const auto start_time = std::chrono::steady_clock::now();
  LineAssociation association;
  LineAssociationSummary& summary = association.summary;
  summary.num_views = static_cast<int>(views.size());
  association.pairwise_matches =
      MatchLinesPairwise(views, options, &summary.pairwise);
  LOG(INFO) << "Algorithm 1: " << association.pairwise_matches.size()
            << " pairwise line matches over " << views.size() << " views in "
            << summary.pairwise.seconds << " s";

  // The observation graph: every segment is a node.
  const auto clear_start = std::chrono::steady_clock::now();
  std::vector<TrackObservation> observations;
  std::vector<int> view_ids;
  std::vector<int> first_observation(views.size() + 1, 0);
  for (size_t v = 0; v < views.size(); ++v) {
    first_observation[v] = static_cast<int>(observations.size());
    for (size_t s = 0; s < views[v].segments.size(); ++s) {
      observations.emplace_back(static_cast<int>(v), static_cast<int>(s));
      view_ids.push_back(static_cast<int>(v));
    }
  }
  std::vector<ClearEdge> edges;
  edges.reserve(association.pairwise_matches.size());
  for (const PairwiseLineMatch& match : association.pairwise_matches) {
    // Mutual matches are worth more; a weak score less.
    const double quality = std::clamp(1.0 - match.score / 4.0, 0.05, 1.0);
    edges.push_back({first_observation[match.view1] + match.segment1,
                     first_observation[match.view2] + match.segment2,
                     (match.mutual ? 1.0 : 0.5) * quality});
  }
  const ClearResult clear = options.use_clear
                                ? RunClear(view_ids, edges, options.clear)
                                : ConnectedComponents(view_ids, edges);
  summary.num_components = clear.num_components;
  summary.num_split_components = clear.num_split_components;
  summary.largest_component_size = clear.largest_component_size;
  summary.num_matches_removed = clear.num_removed_edges;
  association.tracks = BuildLineTracks(views, observations, clear.cluster_ids,
                                       options.min_track_length);
  summary.clear_seconds = SecondsSince(clear_start);

  std::vector<int> lengths;
  for (const LineTrackRecord& track : association.tracks) {
    lengths.push_back(static_cast<int>(track.elements.size()));
  }
  summary.num_tracks = lengths.size();
  if (!lengths.empty()) {
    summary.num_track_observations =
        std::accumulate(lengths.begin(), lengths.end(), size_t{0});
    summary.mean_track_length =
        static_cast<double>(summary.num_track_observations) / lengths.size();
    std::sort(lengths.begin(), lengths.end());
    summary.median_track_length = lengths[lengths.size() / 2];
    summary.max_track_length = lengths.back();
  } else {
    LOG(WARNING) << "Line association produced no track";
  }
  LOG(INFO) << (options.use_clear ? "CLEAR" : "Connected components") << ": "
            << summary.num_tracks << " tracks, " << summary.num_matches_removed
            << " matches removed in " << summary.clear_seconds << " s";
  summary.total_seconds = SecondsSince(start_time);
  return association;
}

void WriteLineAssociation(Database* database,
                          const std::vector<MatchingView>& views,
                          const LineAssociation& association) {
  std::map<std::pair<int, int>, std::vector<std::pair<uint32_t, uint32_t>>>
      per_pair;
  for (const PairwiseLineMatch& match : association.pairwise_matches) {
    per_pair[{match.view1, match.view2}].emplace_back(match.segment1,
                                                       match.segment2);
  }
  DatabaseTransaction transaction(database);
  ClearLineMatches(database);
  for (const auto& [pair, rows] : per_pair) {
    LineMatchesBlob blob(rows.size(), 2);
    for (size_t r = 0; r < rows.size(); ++r) {
      blob(r, 0) = rows[r].first;
      blob(r, 1) = rows[r].second;
    }
    WriteLineMatches(database, views.at(pair.first).image_id,
                     views.at(pair.second).image_id, blob);
  }
  WriteLineTracks(database, association.tracks);
  transaction.Commit();
}

void SetModelLines3D(const std::vector<LineTrackRecord>& tracks,
                     Reconstruction* model) {
  model->lines3D.clear();
  for (const LineTrackRecord& track : tracks) {
    Line3D line;
    line.start_in_world = track.start_in_world;
    line.end_in_world = track.end_in_world;
    line.error = -1.0;
    line.track = track.elements;
    model->lines3D.emplace(track.line3D_id, std::move(line));
  }
}

LineAssociation MatchWorkspaceLines(Database* database, const Reconstruction& model,
                               const LineMatchingOptions& options) {
  THROW_CHECK(options.Check(), "Invalid LineMatchingOptions");
  const auto start_time = std::chrono::steady_clock::now();
  const std::vector<MatchingView> views =
      LoadMatchingViews(*database, model, options);
  const double load_seconds = SecondsSince(start_time);
  LOG(INFO) << "Loaded " << views.size() << " views with line segments in "
            << load_seconds << " s";
  LineAssociation association = AssociateLines(views, options);
  WriteLineAssociation(database, views, association);
  association.summary.load_seconds = load_seconds;
  association.summary.total_seconds = SecondsSince(start_time);
  return association;
}

}  // namespace colmap_lidar
