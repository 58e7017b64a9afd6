// The line tracks as JSON, so that anyone can check the association with
// their own tools:
//   {"num_tracks": N,
//    "tracks": [{"line3D_id": 1,
//                "plucker": [dx, dy, dz, mx, my, mz],       (world)
//                "start_in_world": [x, y, z], "end_in_world": [x, y, z],
//                "observations": [{"image_id": 3, "image_name": "000002.png",
//                                  "segment_idx": 17,
//                                  "start2D": [x, y], "end2D": [x, y],
//                                  "start3D_in_cam": [x, y, z],
//                                  "end3D_in_cam": [x, y, z]}, ...]}, ...]}
// 2D endpoints in pixels (COLMAP convention, centre of the upper-left pixel
// at (0.5, 0.5)); 3D endpoints in metres in that image's camera frame, as
// ext_line_segments stores them. Numbers with the shortest text that reads
// back to the same double (colmap_ext/util/json.h).
#pragma once

#include <string>
#include <vector>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_tracks_table.h"

namespace colmap_lidar {

// Reads each observation's segment from `database` (ext_line_segments) and
// image names from its images table; throws naming the track when a
// segment or image is missing. Written atomically.
void WriteLineTracksJson(const std::string& path, const Database& database,
                         const std::vector<LineTrackRecord>& tracks);

}  // namespace colmap_lidar
