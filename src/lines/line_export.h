// line_exporter: the 3D segments of ext_line_segments in the world frame of
// a sparse model (each image's cam_from_world; images are matched by name),
// as PLY (vertex x y z red green blue + edge vertex1 vertex2; CloudCompare
// and MeshLab show the edges) or Wavefront OBJ ("v x y z r g b" and
// "l i j"). One colour per image.
#pragma once

#include <string>

#include "colmap_ext/database/database.h"
#include "colmap_ext/scene/reconstruction.h"

namespace colmap_lidar {

struct LineExportSummary {
  int num_images = 0;        // model images with segments
  int num_images_missing = 0;  // database images with segments, not in model
  int num_segments = 0;
};

// output_path ends in .ply or .obj (case-insensitive), else throws. The file
// is written atomically.
LineExportSummary ExportWorldLineSegments(const Database& database,
                                          const Reconstruction& model,
                                          const std::string& output_path);

}  // namespace colmap_lidar
