#include "src/sfm/workspace_line_adjustment.h"

#include <vector>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_tracks_table.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/optim/line_track.h"
#include "src/sfm/lidar_mapper.h"

namespace colmap_lidar {

WorkspaceLineAdjustmentSummary RunWorkspaceLineAdjustment(
    const WorkspaceLineAdjustmentPaths& paths,
    const LineBundleAdjustmentOptions& options) {
  WorkspaceLineAdjustmentSummary summary;
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
  const Database database(paths.database_path);
  if (NumLineTracks(database) == 0) {
    summary.error = "--database_path " + paths.database_path +
                    " holds no line tracks (ext_line_tracks is empty): run "
                    "line_matcher first";
    return summary;
  }
  std::vector<LineTrack> tracks = LoadLineTracks(
      database, model, /*min_track_length=*/2, &summary.load);
  LOG(INFO) << "line_bundle_adjuster: " << summary.load.num_tracks << " of "
            << summary.load.num_tracks_in_database << " line tracks, "
            << summary.load.num_observations << " observations ("
            << summary.load.num_observations_without_image
            << " of images not in the model dropped)";
  LineBundleAdjuster adjuster(options);
  if (options.prior_position_sigma_m > 0.0) {
    const auto priors = ReadPosePriors(database, model);
    LOG(INFO) << "line_bundle_adjuster: " << priors.size()
              << " images with a prior pose";
    summary.num_prior_images = static_cast<int>(priors.size());
    adjuster.SetPosePriors(priors);
  }
  summary.adjustment = adjuster.Solve(&model, &tracks);
  summary.solved = true;
  if (!summary.adjustment.usable) {
    summary.error = "line_bundle_adjuster: the solution is not usable (" +
                    summary.adjustment.termination_message +
                    "); nothing written";
    return summary;
  }
  SetReconstructionLines(tracks, &model);
  WriteReconstruction(paths.output_path, model, ModelFormat::kBinary);
  summary.lines_ply_path = paths.lines_ply_path.empty()
                               ? JoinPaths(paths.output_path, "lines3D.ply")
                               : paths.lines_ply_path;
  WriteLines3DPly(summary.lines_ply_path, model);
  summary.num_images = model.images.size();
  summary.num_points3D = model.points3D.size();
  summary.num_lines3D = model.lines3D.size();
  return summary;
}

}  // namespace colmap_lidar
