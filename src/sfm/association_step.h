// The line association step of lidar_mapper (paper section III-C) behind a
// narrow interface: src/matching/line_tracks.h and src/optim/line_track.h
// both declare a colmap_lidar::LineObservation (an index pair there, a
// bundle adjustment observation here), so no translation unit may include
// both; this one includes the matching side only.
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
