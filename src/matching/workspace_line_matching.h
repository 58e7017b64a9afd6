// The line_matcher command as a library function: a COLMAP database with
// ext_line_segments and a sparse model in, the association of
// line_association.h run, its tables written to the database, and on
// request a copy of the model with the tracks as lines3D.bin and the track
// JSON of track_export.h.
#pragma once

#include <string>

#include "src/matching/line_association.h"
#include "src/matching/line_matching_options.h"

namespace colmap_lidar {

struct WorkspaceLineMatchingPaths {
  // COLMAP database with ext_line_segments (from line_extractor); receives
  // ext_line_matches and ext_line_tracks.
  std::string database_path;
  // Sparse model whose poses place the segments in the world.
  std::string input_path;
  // Folder for a copy of the model with the tracks as lines3D.bin; empty:
  // none.
  std::string output_path;
  // JSON file with every track's observations (track_export.h); empty:
  // none.
  std::string tracks_json_path;
};

struct WorkspaceLineMatchingSummary {
  // Empty on success; otherwise why nothing was done (a missing database or
  // model), for the caller to report.
  std::string error;
  LineAssociationSummary association;
  // lines3D of the model written to output_path (0 when none was written).
  size_t num_model_lines3D = 0;
  // Tracks written to tracks_json_path (0 when none was written).
  size_t num_exported_tracks = 0;
};

// Refuses (error set, nothing read or written) when database_path does not
// exist or input_path holds no sparse model. Throws colmap_lidar::Error
// naming the file when reading or writing fails.
WorkspaceLineMatchingSummary RunWorkspaceLineMatching(
    const WorkspaceLineMatchingPaths& paths,
    const LineMatchingOptions& options);

}  // namespace colmap_lidar
