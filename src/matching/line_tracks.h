// Line tracks from the consistent association (paper section III-C, end):
// the observations of each CLEAR cluster form a track, and its infinite
// line is initialised from the observations' 3D data: the direction is the
// principal axis (PCA) of the observations' 3D endpoints in the world frame
// (current poses), through their centroid, as Plucker coordinates (d, m =
// c x d). The finite extent spans the endpoints projected on the line.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/database/line_tracks_table.h"
#include "src/matching/matching_view.h"

namespace colmap_lidar {

// An observation of a track being built: (view index, segment index). Not
// the bundle adjustment's LineObservation (src/optim/line_track.h), which
// carries the measurement.
using TrackObservation = std::pair<int, int>;

// Fits the line to points (>= 2, not all equal; else throws). Returns the
// Plucker vector (unit d, m = centroid x d); start/end (optional) receive
// the extreme projections of the points on the line, ordered along d.
Eigen::Matrix<double, 6, 1> FitPluckerLine(
    const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d* start,
    Eigen::Vector3d* end);

// Tracks from cluster ids (one per observation; negative ids are ignored):
// clusters with at least min_track_length observations, ids 1, 2, ... in
// order of their first observation; elements sorted by image id. Throws
// when a cluster holds two observations of one view.
std::vector<LineTrackRecord> BuildLineTracks(
    const std::vector<MatchingView>& views,
    const std::vector<TrackObservation>& observations,
    const std::vector<int>& cluster_ids, int min_track_length);

}  // namespace colmap_lidar
