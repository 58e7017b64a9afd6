// Which part of a 3D line each image of its track observed.
//
// A 3D line track is the union of per-view segments (ext_line_segments,
// colmap_ext/database/line_segments_table.h): an image in the track usually
// saw only part of it (a facade edge leaves the frame, an occluder cuts it).
// A line sample must only carve free space along the rays of images that saw
// that sample (Amblard et al., Sec. III-E: the samples are vertices with the
// visibility of the lines); a ray from an image that did not see it may cross
// whatever hid it and open a hole there. Measured on the benchmark matrix
// (docs/benchmarks/matrix.md): with rays from every image of the track, the
// line samples cost 0.001-0.005 of mesh precision within 0.2 m of the creases
// on every cell.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/scene/reconstruction.h"

namespace colmap_lidar {

struct LineObservedInterval {
  image_t image_id = kInvalidImageId;
  // The observed interval of the line, as the parameter t of
  // start_in_world + t * (end_in_world - start_in_world): t_begin <= t_end,
  // not clamped to [0, 1].
  double t_begin = 0;
  double t_end = 0;
};

// The interval of `line3D` spanned by the orthogonal projections onto it of
// the endpoints of `segment` (its per-view 3D segment, camera frame),
// carried into the world by `image`'s cam_from_world. Throws on a degenerate
// line (coincident endpoints).
LineObservedInterval ObservedLineInterval(const Line3D& line3D, const Image& image,
                                     const LineSegmentRecord& segment);

// The observations of every track element of every line of `lines_model`
// whose image is in the model and whose segment is in `database`, keyed by
// line id. Throws naming the database when a track element refers to a
// segment index the database does not have (a model and a database of
// different runs).
std::map<line3D_t, std::vector<LineObservedInterval>> ReadLineObservations(
    const Reconstruction& lines_model, const Database& database);

// The observations as bytes for the other ranks of an MPI job (the same
// binary), and back. Throws colmap_lidar::Error on truncated or trailing
// bytes.
std::string SerializeLineObservations(
    const std::map<line3D_t, std::vector<LineObservedInterval>>& observations);
std::map<line3D_t, std::vector<LineObservedInterval>>
DeserializeLineObservations(const std::string& bytes);

}  // namespace colmap_lidar
