// The line_bundle_adjuster command as a library function (paper section
// III-D on its own): the line tracks of a COLMAP database (line_matcher)
// and a sparse model in, the point + line + LIDAR adjustment of
// src/optim/line_bundle_adjustment.h run, the refined model (with
// lines3D.bin) and a PLY of its 3D segments out.
#pragma once

#include <string>

#include "src/optim/line_bundle_adjustment.h"
#include "src/sfm/ba_input.h"

namespace colmap_lidar {

struct WorkspaceLineAdjustmentPaths {
  // COLMAP database with ext_line_tracks (line_matcher) and
  // ext_line_segments; with prior poses when the options use them.
  std::string database_path;
  // Sparse model with the poses (and points3D).
  std::string input_path;
  // Folder of the refined model (binary, with lines3D.bin).
  std::string output_path;
  // PLY line set of the refined 3D segments; empty:
  // <output_path>/lines3D.ply.
  std::string lines_ply_path;
};

struct WorkspaceLineAdjustmentSummary {
  // Empty on success; otherwise why nothing was written (a missing database
  // or model, no line tracks, an unusable solution), for the caller to
  // report.
  std::string error;
  // The adjustment ran; `adjustment` holds its summary (also when the
  // solution was unusable).
  bool solved = false;
  LineTrackLoadSummary load;
  // Images with a prior pose, when the options use pose priors
  // (prior_position_sigma_m > 0); else -1.
  int num_prior_images = -1;
  LineBundleAdjustmentSummary adjustment;
  // The written model and PLY (when error is empty).
  size_t num_images = 0;
  size_t num_points3D = 0;
  size_t num_lines3D = 0;
  std::string lines_ply_path;
};

// Refuses (error set, nothing written) when database_path does not exist,
// input_path holds no sparse model, the database has no line tracks, or
// the adjustment's solution is not usable (Ceres' IsSolutionUsable, false
// also when there is nothing to solve). Pose priors are read from the
// database when options.prior_position_sigma_m > 0. Throws
// colmap_lidar::Error naming the file when reading or writing fails.
WorkspaceLineAdjustmentSummary RunWorkspaceLineAdjustment(
    const WorkspaceLineAdjustmentPaths& paths,
    const LineBundleAdjustmentOptions& options);

}  // namespace colmap_lidar
