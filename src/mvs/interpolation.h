// Densification of the depth samples to every pixel (paper section III-E,
// initialisation): a 2D Delaunay triangulation of the sample pixels
// (OpenCV Subdiv2D); inside a triangle, inverse depth is interpolated
// linearly (exact for a plane seen in perspective) and the normals
// barycentrically, unless the vertex depths differ by more than
// interpolation_max_depth_ratio, in which case each pixel takes the plane of
// its nearest vertex so that depth edges are not smeared. Pixels outside
// the convex hull stay invalid (depth 0): PatchMatch starts them randomly,
// or ExtrapolateToEmptyPixels gives them the nearest interpolated plane.
// So do the pixels of a triangle of three LIDAR samples that spans space the
// LIDAR did not sample: its longest 3D edge over its mean depth (the angle
// it subtends) exceeds interpolation_max_edge_factor times the median of
// that ratio over the view's LIDAR triangles (the scanner's sampling as this
// view sees it). Without this test the hull bridges, e.g., the tops of a
// corridor's two walls across the sky, and the LIDAR prior then keeps sky
// pixels at that invented depth (a lid in the mesh).
#pragma once

#include <cstdint>
#include <vector>

#include "src/mvs/depth_init.h"
#include "src/mvs/mvs_view.h"
#include "src/mvs/patch_match_options.h"
#include "src/mvs/plane_map.h"

namespace colmap_lidar {

// Returns a map of the view's size; cost is 0. `across_depth_edge`
// (optional) receives per pixel 1 where the depth is the nearest vertex's
// plane of a triangle across a depth edge (a guess: where the edge lies
// between the vertices is unknown), else 0.
PlaneMap InterpolateSamples(const MvsView& view,
                            const std::vector<DepthSample>& samples,
                            const LidarPatchMatchOptions& options,
                            std::vector<uint8_t>* across_depth_edge = nullptr);

// Gives every pixel without a hypothesis the plane of the nearest pixel that
// has one (Euclidean distance in the image), intersected with its ray: a
// wall the LIDAR sampled only up to the top of its vertical field starts
// PatchMatch on that wall's plane above it, instead of on random planes
// that propagation reaches only a few strips per iteration. Where the
// intersection is behind the camera or beyond [0.5, 2] times the nearest
// pixel's depth (the plane seen nearly edge-on), the pixel stays empty
// (random). These are starting hypotheses only: the caller keeps them out
// of the soft LIDAR prior, so the photometric cost alone accepts or
// replaces them. Returns the number of pixels filled.
size_t ExtrapolateToEmptyPixels(const MvsView& view, PlaneMap* map);

}  // namespace colmap_lidar
