// Inputs of the point + line bundle adjustment (paper section III-D) read
// from a COLMAP workspace: the line tracks of the association stage
// (ext_line_tracks / ext_line_track_elements, section III-C) joined with
// the segments they reference (ext_line_segments, section III-B), and the
// prior poses the importer stored in the database's prior columns.
//
// The points of the adjustment are the model's own points3D / points2D (a
// model written by stock `point_triangulator` or `mapper` has them); they
// need no conversion.
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "colmap_ext/database/database.h"
#include "colmap_ext/scene/reconstruction.h"
#include "src/optim/line_track.h"

namespace colmap_lidar {

struct LineTrackLoadSummary {
  int num_tracks_in_database = 0;
  // Tracks returned (at least min_track_length observations in the model).
  int num_tracks = 0;
  int num_observations = 0;
  int num_lidar_observations = 0;
  // Observations dropped because their image is not in the model.
  int num_observations_without_image = 0;
};

// One LineTrack per database track: each element becomes a LineObservation
// with the 2D endpoints and the LIDAR 3D endpoints (camera frame) of its
// ext_line_segments row (every stored segment was lifted to 3D, so
// has_lidar is true). The track's Plucker line and segment are copied from
// ext_line_tracks (world frame of the poses used by the association).
// Elements whose image is not in `model` are dropped; tracks left with
// fewer than `min_track_length` observations are dropped. Throws
// colmap_lidar::Error naming the track when an element references a
// segment index that does not exist.
std::vector<LineTrack> LoadLineTracks(const Database& database,
                                      const Reconstruction& model,
                                      int min_track_length = 2,
                                      LineTrackLoadSummary* summary = nullptr);

// Prior cam_from_world per model image, from the database's prior columns
// (prior_q = cam_from_world rotation, prior_t = camera centre in the world,
// see src/dataset/importer.h). Images are matched by name; images without a
// complete prior are absent from the result.
std::unordered_map<image_t, Rigid3d> ReadPosePriors(
    const Database& database, const Reconstruction& model);

}  // namespace colmap_lidar
