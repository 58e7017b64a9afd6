#include "src/matching/workspace_line_matching.h"

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "src/matching/track_export.h"

namespace colmap_lidar {

WorkspaceLineMatchingSummary RunWorkspaceLineMatching(
    const WorkspaceLineMatchingPaths& paths,
    const LineMatchingOptions& options) {
  WorkspaceLineMatchingSummary summary;
  if (!ExistsFile(paths.database_path)) {
    summary.error =
        "--database_path " + paths.database_path + " does not exist";
    return summary;
  }
  if (!ExistsModel(paths.input_path)) {
    summary.error =
        "--input_path " + paths.input_path + " holds no sparse model";
    return summary;
  }
  Reconstruction model = ReadReconstruction(paths.input_path);
  Database database(paths.database_path);
  const LineAssociation association =
      MatchWorkspaceLines(&database, model, options);
  summary.association = association.summary;
  if (!paths.output_path.empty()) {
    SetModelLines3D(association.tracks, &model);
    WriteReconstruction(paths.output_path, model, ModelFormat::kBinary);
    summary.num_model_lines3D = model.lines3D.size();
  }
  if (!paths.tracks_json_path.empty()) {
    WriteLineTracksJson(paths.tracks_json_path, database, association.tracks);
    summary.num_exported_tracks = association.tracks.size();
  }
  return summary;
}

}  // namespace colmap_lidar
