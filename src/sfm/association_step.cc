#include "src/sfm/association_step.h"

#include "src/matching/line_association.h"

namespace colmap_lidar {

AssociationStepSummary AssociateWorkspaceLines(
    Database* database, const Reconstruction& model,
    const LineMatchingOptions& options) {
  const LineAssociation association =
      MatchWorkspaceLines(database, model, options);
  AssociationStepSummary summary;
  summary.num_tracks = association.summary.num_tracks;
  summary.mean_track_length = association.summary.mean_track_length;
  summary.text = association.summary.Format();
  return summary;
}

}  // namespace colmap_lidar
