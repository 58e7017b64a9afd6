// fused.ply.vis, written by stereo_fusion next to fused.ply
// (colmap-formats.md 4.8): uint64 num_points, then per point in PLY order
// uint32 n and n uint32 image indices. An image index is the 0-based
// position of the image in the workspace sparse model's image file order
// (Reconstruction::images), not its image_id.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace colmap_lidar {

// visibility[point_idx] = image indices that saw the fused point.
using FusedVisibility = std::vector<std::vector<uint32_t>>;

// Throws colmap_lidar::Error naming the path on a missing, truncated or
// over-long file.
FusedVisibility ReadFusedVis(const std::string& path);
// Also throws unless the file holds exactly `expected_num_points` entries
// (the vertex count of the matching PLY).
FusedVisibility ReadFusedVis(const std::string& path,
                             size_t expected_num_points);
// Atomic.
void WriteFusedVis(const std::string& path, const FusedVisibility& visibility);
// Throws naming `path_for_errors` and the point when an index is not below
// `num_images`.
void CheckFusedVisIndices(const FusedVisibility& visibility, size_t num_images,
                          const std::string& path_for_errors);

}  // namespace colmap_lidar
