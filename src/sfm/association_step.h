// The line association step of lidar_mapper (paper section III-C) behind a
// narrow interface: the mapper sees a summary, not the association's
// internals (src/matching/line_association.h).
#pragma once

#include <string>

#include "colmap_ext/database/database.h"
#include "colmap_ext/scene/reconstruction.h"
#include "src/matching/line_matching_options.h"

namespace colmap_lidar {

struct AssociationStepSummary {
  size_t num_tracks = 0;
  double mean_track_length = 0.0;
  // LineAssociationSummary::Format().
  std::string text;
};

// MatchWorkspaceLines: associates the segments of `model`'s images with
// its poses and replaces ext_line_matches / ext_line_tracks.
AssociationStepSummary AssociateWorkspaceLines(
    Database* database, const Reconstruction& model,
    const LineMatchingOptions& options);

}  // namespace colmap_lidar
