// The driver of `colmap-lidar lidar_patch_match_stereo` (paper section
// III-E): reads a dense workspace made by stock `colmap image_undistorter`
// (plus lidar_fused.ply from lidar_fuser for the LIDAR initialisation),
// computes depth and normal maps for every reference image of
// stereo/patch-match.cfg, and writes them as COLMAP does:
//   stereo/depth_maps/<name>.photometric.bin, stereo/normal_maps/<name>.
//   photometric.bin (cost-filtered), and with geom_consistency the
//   .geometric.bin pair (geometric pass + consistency filter),
// so that stock `colmap stereo_fusion` fuses them (input_type photometric
// or geometric). Maps that exist already are skipped unless overwrite is
// set (resumable); every file is written atomically. Under mpirun / srun
// (colmap_ext/util/process_group.h) each rank computes every Size()-th
// reference of each pass, the ranks meet between the passes, and the maps
// are byte for byte those of one process.
//
// With filter_lidar_as_view, a geometric map also keeps the pixels that one
// source view and the LIDAR confirm (rather than two source views), and with
// filter_reproj_parallax those that the views confirm only within the
// parallax tolerance; stereo/fusion_masks/<name>.png marks both 0 (the others
// 255): those depths are right (within 5 cm as often as the rest) but add
// nothing to a mesh that has the LIDAR points themselves and measurably
// roughen it (quad HDL-64E: precision at 2 cm 0.977 -> 0.970 for the LIDAR's
// vote; quad VLP-16: 0.855 -> 0.851 for the parallax). Fusing with
// `stereo_fusion --StereoFusion.mask_path <workspace>/stereo/fusion_masks`,
// as the pipeline does, gives exactly the cloud of the strict two-view
// filter.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "src/lidar/lidar_fusion.h"
#include "src/mvs/depth_init.h"
#include "src/mvs/map_filter.h"
#include "src/mvs/mvs_view.h"
#include "src/mvs/patch_match_options.h"
#include "src/mvs/plane_map.h"

namespace colmap_lidar {

struct ReferenceInit {
  PlaneMap state;
  // Depth samples per pixel (0: none), for the soft prior.
  std::vector<float> prior_depth;
  float depth_min = 0.0f;
  float depth_max = 0.0f;
  DepthInitStats stats;
};

// Initial planes of a reference view: with init "lidar", LIDAR samples
// (occlusion-checked) and features merged and interpolated; with "random",
// an empty state (PatchMatch randomises it). The depth range spans the 1st
// to 99th percentile of the feature (and, with "lidar" or without features,
// LIDAR) depths, widened by 1/1.5 and 1.5. `lidar` may be nullptr.
// `ref_image_idx` is the view's position in the model's images (the .vis
// index) for lidar_own_scan_min_incidence_deg, -1 when unknown (then the
// own scan has no precedence).
// Throws naming the view when no depth is known to set the range.
ReferenceInit InitializeReference(
    const MvsView& ref, const std::vector<Eigen::Vector3f>& features_in_world,
    const FusedLidarCloud* lidar, int ref_image_idx,
    const LidarPatchMatchOptions& options);

// The soft prior of a LIDAR-initialised view: the interpolated depth at
// every pixel inside the samples' hull (0 elsewhere), so that textureless
// surfaces, where NCC does not decide, keep their LIDAR plane.
// InitializeReference then clears it, unless lidar_prior_across_depth_edges,
// at the pixels of the triangles across a depth edge, which take a vertex's
// plane by guess (mostly triangles with a sparse feature as a vertex: the
// LIDAR's own steps fail the edge test). (An earlier variant that masked
// every pixel within a few pixels of an interpolated depth edge, including
// the interpolated ones, was measured worse on the quad: 96.1 % vs 96.7 %
// within 5 cm.)
std::vector<float> DensePriorDepth(const PlaneMap& interpolated);

// Under MPI the counts are every rank's, on every rank.
struct LidarPatchMatchSummary {
  int num_references = 0;
  int num_photometric_computed = 0;
  int num_photometric_skipped = 0;
  int num_geometric_computed = 0;
  int num_geometric_skipped = 0;
  int num_without_sources = 0;
  // Geometric pixels kept by the LIDAR's vote or the parallax tolerance
  // only (masked out of fusion).
  size_t num_not_fused = 0;
  // Empty textureless geometric pixels given the plane of the measured
  // pixels enclosing them (fill_enclosed_textureless).
  size_t num_filled = 0;
  // Geometric pixels by what confirmed them (maps computed in this run).
  DepthSupportCounts support;
  double seconds = 0.0;
};

LidarPatchMatchSummary RunLidarPatchMatchStereo(
    const std::string& workspace_path, const LidarPatchMatchOptions& options);

// <workspace_path>/stereo/fusion_masks: stereo_fusion's --StereoFusion.
// mask_path for the maps of RunLidarPatchMatchStereo.
std::string FusionMaskDir(const std::string& workspace_path);

}  // namespace colmap_lidar
