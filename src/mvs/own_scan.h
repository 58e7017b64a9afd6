// Precedence of a view's own LIDAR scan in its depth initialisation (not in
// the paper). The scan taken with the frame sits in the camera's frame
// through the calibration alone (cam_from_lidar): the pose error that the
// fused cloud carries for every other frame's scan cancels out, and its range
// noise lies along rays close to the camera's. Other scans see a far wall
// at an angle, where a centimetre across the wall becomes decimetres along
// the camera's ray: on the corridor VLP-16 (synthetic, true poses) the own
// scans' points lie within 5 cm of the truth along the camera's ray on 99.8
// / 98.0 % at 10-20 m / beyond, the other frames' on 69.7 / 41.3 %
// (scripts/depth_coverage_report.py --lidar), and with the refined poses on
// 56.8 / 22.7 %.
//
// A voxel belongs to the view's own scan when the fused cloud's .vis list
// names the view (lidar_fused.ply.vis: at most max_num_visible_images frames
// per voxel, those with the most points first, so a far voxel hit by many
// nearer frames may lose the mark: on the matrix's cells at most 0.004 % of
// the voxels reach the cap of 16; a cloud without .vis marks none).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/mvs/fused_vis.h"
#include "src/lidar/lidar_fusion.h"
#include "src/mvs/depth_init.h"
#include "src/mvs/mvs_view.h"
#include "src/mvs/patch_match_options.h"
#include "src/mvs/plane_map.h"

namespace colmap_lidar {

// 1 for the voxels whose visibility list holds `image_idx`, else 0; the
// visibility's size (empty when it is).
std::vector<uint8_t> OwnScanVoxels(const FusedVisibility& visibility,
                                   uint32_t image_idx);

// The samples of the view's own scan: ProjectLidarSamples over the voxels
// of `cloud` that OwnScanVoxels marks, with the features over them as over
// the fused cloud's (MergeFeatureSamples).
std::vector<DepthSample> OwnScanSamples(
    const MvsView& view, const FusedLidarCloud& cloud, uint32_t image_idx,
    const std::vector<Eigen::Vector3f>& features_in_world,
    const LidarPatchMatchOptions& options);

// The own scan's planes where they decide: in `map` (the interpolation of
// every scan's samples) and `across_depth_edge` (its flags, see
// InterpolateSamples; both not null, of the view's size), each pixel that both the map and the interpolation
// of `own_samples` alone cover, the latter not across a depth edge and seen
// at more than options.lidar_own_scan_min_incidence_deg from its normal,
// takes the own interpolation's plane (and loses its flag). Nothing changes
// at 90 deg.
//
// Only at grazing incidence: there the fused cloud's error across the
// surface (pose error, another scanner's range noise) grows by 1 / cos of
// the angle along the camera's ray, while the own scan's range noise lies
// along it; where the surface faces the camera, the fused cloud's denser
// sampling holds what lies between the own rings.
// Measured on the LIDAR prior alone (its pixels within 5 cm of the true
// depth, on run 1's fused clouds and poses of the benchmark matrix): the own
// scan everywhere, corridor VLP-16 89.7 -> 90.1 %, street_bent 90.8 -> 88.2 %
// (10-20 m: 79.5 -> 72.3 %); beyond 70 deg, 90.6 % and 91.0 %. On KITTI
// (real HDL-64E) the same 70 deg cost 5 % of the geometric pixels, mostly
// the road at 5-10 m, and 81.1 -> 77.2 % of the in-view LIDAR within 0.1 m
// of the mesh (79.5 % with the own planes as starting hypotheses only):
// hence off by default (options.lidar_own_scan_min_incidence_deg 90).
//
// The own interpolation never extends the map: its edge test measures the
// own scan's sparser sampling (on street_bent a seventeenth of the voxels a
// view sees at 10-20 m), which lets it bridge space that the denser cloud
// shows open: replacing the fused cloud's samples where the own
// interpolation covered the view put a lid over the corridor VLP-16's far
// end (mesh precision at 0.5 m 1.000 -> 0.990). Returns the number of
// pixels replaced.
size_t PreferOwnScan(const MvsView& view,
                     const std::vector<DepthSample>& own_samples,
                     const LidarPatchMatchOptions& options, PlaneMap* map,
                     std::vector<uint8_t>* across_depth_edge);

}  // namespace colmap_lidar
