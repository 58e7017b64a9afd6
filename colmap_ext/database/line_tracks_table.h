// Our tables of the 3D/3D line association (paper section III-C;
// src/matching): the pairwise line matches per image pair and the
// multi-view line tracks after CLEAR.
//
// ext_line_matches, one row per image pair, laid out like COLMAP's matches:
//   pair_id  INTEGER PRIMARY KEY  Database::ImagePairToPairId (smaller id
//                                 first, as COLMAP computes it)
//   rows     INTEGER              number of matches
//   cols     INTEGER              2
//   data     BLOB                 rows x 2 uint32, row-major: segment idx
//                                 (ext_line_segments.idx) in the image with
//                                 the smaller id, then in the larger one
//
// ext_line_tracks, one row per track (a 3D line):
//   line3D_id  INTEGER PRIMARY KEY
//   plucker    BLOB  6 float64: unit direction d, then moment m = p x d
//                    (world frame, metres), the infinite line
//   segment3D  BLOB  6 float64: start xyz, end xyz in the world: the extent
//                    of the observations along the line
//
// ext_line_track_elements, one row per observation:
//   line3D_id  INTEGER  references ext_line_tracks ON DELETE CASCADE
//   image_id   INTEGER  references images ON DELETE CASCADE
//   idx        INTEGER  the segment (ext_line_segments.idx)
//   PRIMARY KEY (line3D_id, image_id): a track holds at most one
//   observation per image (the association is multi-view consistent);
//   UNIQUE (image_id, idx): a segment belongs to at most one track.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/schema.h"
#include "colmap_ext/scene/line3d.h"
#include "colmap_ext/util/types.h"

namespace colmap_lidar {

// Rows x 2: segment idx in the first image, in the second.
using LineMatchesBlob =
    Eigen::Matrix<uint32_t, Eigen::Dynamic, 2, Eigen::RowMajor>;

struct LineTrackRecord {
  line3D_t line3D_id = kInvalidLine3DId;
  // (d, m): unit direction and moment p x d of the infinite line, world.
  Eigen::Matrix<double, 6, 1> plucker = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Vector3d start_in_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_in_world = Eigen::Vector3d::Zero();
  // At most one element per image.
  std::vector<LineTrackElement> elements;
};

// The schema entries (listed in ExtTableSchemas(), schema.cc).
const TableSchema& LineMatchesTableSchema();
const TableSchema& LineTracksTableSchema();
const TableSchema& LineTrackElementsTableSchema();

// ---- ext_line_matches. Column 0 of `matches` indexes the segments of
// image_id1; rows are stored with the columns swapped when image_id1 >
// image_id2, as COLMAP stores matches. Replaces an existing row of the pair.
void WriteLineMatches(Database* database, image_t image_id1, image_t image_id2,
                      const LineMatchesBlob& matches);
// In the (image_id1, image_id2) orientation; empty when none.
LineMatchesBlob ReadLineMatches(const Database& database, image_t image_id1,
                                image_t image_id2);
// Every stored pair in stored orientation, by increasing pair id.
std::vector<std::pair<image_pair_t, LineMatchesBlob>> ReadAllLineMatches(
    const Database& database);
void ClearLineMatches(Database* database);
// Sum of rows over all pairs.
size_t NumLineMatches(const Database& database);

// ---- ext_line_tracks + ext_line_track_elements. Replaces all tracks by
// `tracks` in one transaction. Throws (naming the track) on an invalid id,
// an image with two elements in one track, a segment in two tracks or an
// image that does not exist.
void WriteLineTracks(Database* database,
                     const std::vector<LineTrackRecord>& tracks);
// By increasing line3D_id; elements by increasing image id.
std::vector<LineTrackRecord> ReadLineTracks(const Database& database);
void ClearLineTracks(Database* database);
size_t NumLineTracks(const Database& database);

}  // namespace colmap_lidar
