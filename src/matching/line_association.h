// The 3D/3D line association of the paper (section III-C, Fig. 6) end to
// end: pairwise matches by Algorithm 1 (pairwise_matcher.h), multi-view
// consistency by CLEAR (clear.h), tracks with Plucker lines (line_tracks.h),
// and the workspace glue: views from database.db + a sparse model, results
// into our tables (line_tracks_table.h) and the model's lines3D.
#pragma once

#include <string>
#include <vector>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_tracks_table.h"
#include "colmap_ext/scene/reconstruction.h"
#include "src/matching/clear.h"
#include "src/matching/line_matching_options.h"
#include "src/matching/line_tracks.h"
#include "src/matching/matching_view.h"
#include "src/matching/pairwise_matcher.h"

namespace colmap_lidar {

struct LineAssociationSummary {
  int num_views = 0;
  PairwiseMatchingStats pairwise;
  // CLEAR (or the connected components when CLEAR is off).
  int num_components = 0;
  int num_split_components = 0;
  int largest_component_size = 0;
  // Pairwise matches whose observations ended in different tracks.
  size_t num_matches_removed = 0;
  size_t num_tracks = 0;
  size_t num_track_observations = 0;
  double mean_track_length = 0.0;
  int median_track_length = 0;
  int max_track_length = 0;
  double load_seconds = 0.0;
  double clear_seconds = 0.0;
  double total_seconds = 0.0;

  // A few human-readable lines.
  std::string Format() const;
};

struct LineAssociation {
  std::vector<PairwiseLineMatch> pairwise_matches;
  std::vector<LineTrackRecord> tracks;
  LineAssociationSummary summary;
};

// Associates the segments of `views` (their current poses).
LineAssociation AssociateLines(const std::vector<MatchingView>& views,
                               const LineMatchingOptions& options);

// Replaces ext_line_matches (the pairwise matches of Algorithm 1, before
// CLEAR, per image pair) and ext_line_tracks in one transaction.
void WriteLineAssociation(Database* database,
                          const std::vector<MatchingView>& views,
                          const LineAssociation& association);

// Replaces model->lines3D by the tracks (same ids; error -1).
void SetModelLines3D(const std::vector<LineTrackRecord>& tracks,
                     Reconstruction* model);

// The line_matcher command: views of `model` from `database` (segments and,
// for the visibility test, LIDAR scans), association, tables written.
// Re-running after the poses were refined (a refined model) replaces the
// previous matches and tracks.
LineAssociation MatchWorkspaceLines(Database* database, const Reconstruction& model,
                               const LineMatchingOptions& options);

}  // namespace colmap_lidar
