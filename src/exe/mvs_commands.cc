// Subcommands of the dense module (paper section III-E): lidar_fuser and
// lidar_patch_match_stereo.
#include <cstdlib>
#include <iostream>
#include <string>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/process_group.h"
#include "src/exe/commands.h"
#include "src/exe/option_manager.h"
#include "src/exe/option_sections.h"
#include "src/lidar/lidar_fusion.h"
#include "src/mvs/lidar_patch_match_stereo.h"

namespace colmap_lidar {

// Section [LidarFusion]; keep configs/lidar_fuser.ini in step.
void AddLidarFusionOptions(LidarFusionOptions* o, OptionManager* options) {
  const std::string s = "LidarFusion.";
  options->AddOption(s + "voxel_size_m", &o->voxel_size_m,
                     "Voxel edge, metres, > 0.");
  options->AddOption(s + "min_range_m", &o->min_range_m,
                     "LIDAR points nearer to their scanner are ignored, "
                     "metres, >= 0.");
  options->AddOption(s + "max_range_m", &o->max_range_m,
                     "LIDAR points farther from their scanner are ignored, "
                     "metres.");
  options->AddOption(s + "min_points_per_voxel", &o->min_points_per_voxel,
                     "Voxels with fewer raw points are dropped, >= 1.");
  options->AddOption(s + "normal_radius_voxels", &o->normal_radius_voxels,
                     "Normal plane fit over voxels within this Chebyshev "
                     "distance, >= 1.");
  options->AddOption(s + "normal_min_neighbors", &o->normal_min_neighbors,
                     "Voxels needed for a normal, >= 3.");
  options->AddOption(s + "normal_min_eigenvalue_ratio",
                     &o->normal_min_eigenvalue_ratio,
                     "A normal needs the neighbourhood's second covariance "
                     "eigenvalue at least this share of the largest (not a "
                     "line of centroids), [0, 1).");
  options->AddOption(s + "max_num_visible_images",
                     &o->max_num_visible_images,
                     "Frames listed per voxel in lidar_fused.ply.vis, >= 1.");
  options->AddOption(s + "free_space_filter", &o->free_space.enabled,
                     "Drop voxels that other scans see through (moving "
                     "objects: their rays return from beyond the voxel), "
                     "0/1. Not in the paper.");
  options->AddOption(s + "free_space_neighborhood_ring_gaps",
                     &o->free_space.neighborhood_ring_gaps,
                     "Free-space test: the nearest return within this many "
                     "ring spacings (measured per scan) of the voxel's "
                     "direction counts, > 0.");
  options->AddOption(s + "free_space_margin_voxels",
                     &o->free_space.margin_voxels,
                     "Free-space test: that return must lie this many voxel "
                     "edges beyond the voxel, > 0.");
  options->AddOption(s + "free_space_min_see_through_frames",
                     &o->free_space.min_see_through_frames,
                     "Free-space test: a voxel is dropped when at least this "
                     "many scans see through it and they outnumber the scans "
                     "that hit it, >= 1.");
  options->AddCheck([o] { return o->Check(); });
}

// Section [LidarPatchMatch]; keep configs/lidar_patch_match_stereo.ini in
// step.
void AddLidarPatchMatchOptions(LidarPatchMatchOptions* o,
                               OptionManager* options) {
  const std::string s = "LidarPatchMatch.";
  options->AddOption(s + "init", &o->init,
                     "Initialisation: lidar (features + fused LIDAR) | "
                     "random (photogrammetry baseline).");
  options->AddOption(s + "max_image_size", &o->max_image_size,
                     "Larger map side at most, pixels; <= 0: full size.");
  options->AddOption(s + "max_num_src_images", &o->max_num_src_images,
                     "Source views per reference at most, [1, 64].");
  options->AddOption(s + "min_triangulation_angle_deg",
                     &o->min_triangulation_angle_deg,
                     "Minimum source triangulation angle, degrees.");
  options->AddOption(s + "lidar_covisibility_weight",
                     &o->lidar_covisibility_weight,
                     "Source score: weight of a shared LIDAR voxel vs a "
                     "shared sparse point, >= 0; 0 = COLMAP's score. Not in "
                     "the paper.");
  options->AddOption(s + "far_propagation", &o->far_propagation,
                     "Propagation strips of 15 instead of 7 pixels, 0/1.");
  options->AddOption(s + "num_iterations", &o->num_iterations,
                     "Photometric iterations, >= 1.");
  options->AddOption(s + "geom_consistency", &o->geom_consistency,
                     "Geometric pass and *.geometric.bin maps, 0/1.");
  options->AddOption(s + "num_geom_iterations", &o->num_geom_iterations,
                     "Geometric iterations, >= 1.");
  options->AddOption(s + "geom_consistency_regularizer",
                     &o->geom_consistency_regularizer,
                     "Weight of the reprojection error (pixels) in the "
                     "geometric cost, >= 0.");
  options->AddOption(s + "geom_consistency_max_cost",
                     &o->geom_consistency_max_cost,
                     "Reprojection error clamp, pixels, > 0.");
  options->AddOption(s + "window_radius", &o->window_radius,
                     "NCC window radius, pixels, >= 1.");
  options->AddOption(s + "window_step", &o->window_step,
                     "NCC window sampling step, pixels, >= 1.");
  options->AddOption(s + "sigma_spatial", &o->sigma_spatial,
                     "Bilateral spatial sigma, pixels; <= 0: window_radius.");
  options->AddOption(s + "sigma_color", &o->sigma_color,
                     "Bilateral colour sigma, grey values in [0, 1], > 0.");
  options->AddOption(s + "best_views_fraction", &o->best_views_fraction,
                     "Cost = mean of the best ceil(fraction * n) views, "
                     "(0, 1].");
  options->AddOption(s + "visible_sources_only", &o->visible_sources_only,
                     "n of the cost and the views the geometric filter asks "
                     "for count only the sources whose image contains the "
                     "point (and the LIDAR). Not in the paper or COLMAP.");
  options->AddOption(s + "source_plane_depth", &o->source_plane_depth,
                     "The geometric term and filter read a source's depth "
                     "at the sub-pixel projection from its nearest pixel's "
                     "plane, not that pixel's depth (not in the paper).");
  options->AddOption(s + "lidar_prior_weight", &o->lidar_prior_weight,
                     "Soft LIDAR prior weight in the cost; 0: off (the "
                     "paper: the LIDAR only initialises). Not in the "
                     "paper.");
  options->AddOption(s + "lidar_prior_tolerance", &o->lidar_prior_tolerance,
                     "Relative depth deviation at which the prior term "
                     "saturates, > 0.");
  options->AddOption(s + "lidar_prior_across_depth_edges",
                     &o->lidar_prior_across_depth_edges,
                     "The prior and the LIDAR's vote also hold the pixels "
                     "that take the nearest vertex's plane in a triangle "
                     "across a depth edge (a guess; not in the paper).");
  options->AddOption(s + "occlusion_window_radius",
                     &o->occlusion_window_radius,
                     "Neighbourhood of the LIDAR occlusion check, pixels.");
  options->AddOption(s + "occlusion_relative_tolerance",
                     &o->occlusion_relative_tolerance,
                     "A LIDAR sample deeper than (1 + this) x its "
                     "neighbourhood mean is dropped, >= 0.");
  options->AddOption(s + "lidar_samples_at_pixel_centres",
                     &o->lidar_samples_at_pixel_centres,
                     "LIDAR samples carried along their plane to their "
                     "pixel's centre; a pixel takes the median of its front "
                     "surface's samples, not the nearest (not in the paper).");
  options->AddOption(s + "lidar_own_scan_min_incidence_deg",
                     &o->lidar_own_scan_min_incidence_deg,
                     "Where the view sees a surface at more than this angle "
                     "from its normal, the plane of its own LIDAR scan "
                     "replaces the fused cloud's; degrees, 90: off (off by "
                     "default: it loses on KITTI; not in the paper).");
  options->AddOption(s + "interpolation_max_depth_ratio",
                     &o->interpolation_max_depth_ratio,
                     "Delaunay triangles with a larger depth ratio use the "
                     "nearest vertex's plane, > 1.");
  options->AddOption(s + "interpolation_max_edge_factor",
                     &o->interpolation_max_edge_factor,
                     "A triangle of LIDAR samples whose longest 3D edge over "
                     "its depth exceeds this times the view's median is not "
                     "interpolated (space the LIDAR did not sample, e.g. "
                     "sky between wall tops), >= 0; 0: all are. Not in the "
                     "paper.");
  options->AddOption(s + "init_extrapolate_planes",
                     &o->init_extrapolate_planes,
                     "Pixels outside the interpolated samples start from the "
                     "nearest interpolated pixel's plane, not a random one "
                     "(no LIDAR prior there; not in the paper).");
  options->AddOption(s + "keep_lidar_where_unseen", &o->keep_lidar_where_unseen,
                     "Geometric maps: where no source view can see the "
                     "LIDAR prior's point, the pixel takes the LIDAR's plane "
                     "(confirmed by the LIDAR alone, not fused; not in the "
                     "paper).");
  options->AddOption(s + "min_depth", &o->min_depth,
                     "LIDAR and feature depths below this are ignored, "
                     "metres, > 0.");
  options->AddOption(s + "fill_textureless_regions",
                     &o->fill_textureless_regions,
                     "Geometric maps: the empty pixels of a textureless "
                     "region whose measured pixels fit one plane take it "
                     "(not fused; not in the paper).");
  options->AddOption(s + "filter_max_cost", &o->filter_max_cost,
                     "Pixels with a higher cost (1 - NCC) are invalid, "
                     "(0, 2].");
  options->AddOption(s + "filter_min_num_consistent",
                     &o->filter_min_num_consistent,
                     "Geometric maps: consistent source views needed, >= 0.");
  options->AddOption(s + "filter_max_reproj_error",
                     &o->filter_max_reproj_error,
                     "Consistency: reprojection error, pixels, > 0.");
  options->AddOption(s + "filter_max_relative_depth_error",
                     &o->filter_max_relative_depth_error,
                     "Consistency: relative depth error, > 0.");
  options->AddOption(s + "filter_reproj_parallax", &o->filter_reproj_parallax,
                     "The filter's reprojection tolerance grows by the "
                     "parallax of filter_max_relative_depth_error of the "
                     "source's depth (not in the paper).");
  options->AddOption(s + "filter_lidar_as_view", &o->filter_lidar_as_view,
                     "Geometric maps, init lidar: agreeing with the "
                     "interpolated LIDAR depth counts as one consistent "
                     "view. Not in the paper.");
  options->AddOption(s + "filter_lidar_max_relative_depth_error",
                     &o->filter_lidar_max_relative_depth_error,
                     "... within this relative depth error of it, > 0.");
  options->AddOption(s + "num_threads", &o->num_threads,
                     "Threads; -1: all cores.");
  options->AddOption(s + "seed", &o->seed, "Random seed.");
  options->AddOption(s + "overwrite", &o->overwrite,
                     "Recompute maps that exist (default: resume), 0/1.");
  options->AddCheck([o] { return o->Check(); });
}


int RunLidarFuserCommand(int argc, char** argv) {
  std::string database_path;
  std::string input_path;
  std::string output_path;
  LidarFusionOptions fusion_options;
  OptionManager options;
  options.AddRequiredOption("database_path", &database_path,
                            "COLMAP database with ext_lidar_scans.");
  options.AddRequiredOption("input_path", &input_path,
                            "Sparse model with the refined poses.");
  options.AddRequiredOption("output_path", &output_path,
                            "Dense workspace (from image_undistorter); "
                            "receives lidar_fused.ply(.vis) and "
                            "lidar_origins.txt.");
  AddLidarFusionOptions(&fusion_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (!ExistsFile(database_path)) {
    LOG(ERROR) << "--database_path " << database_path << " does not exist";
    return EXIT_FAILURE;
  }
  if (!ExistsModel(input_path)) {
    LOG(ERROR) << "--input_path " << input_path << " holds no sparse model";
    return EXIT_FAILURE;
  }
  const LidarFuserSummary summary =
      RunLidarFuser(database_path, input_path, output_path, fusion_options);
  std::cout << "Fused " << summary.num_raw_points << " LIDAR points of "
            << summary.num_frames - summary.num_frames_without_scan
            << " frames into " << summary.num_voxels << " voxels ("
            << summary.num_frames_without_scan << " frames without scan)"
            << std::endl;
  return EXIT_SUCCESS;
}

int RunLidarPatchMatchStereoCommand(int argc, char** argv) {
  std::string workspace_path;
  LidarPatchMatchOptions patch_match_options;
  OptionManager options;
  options.AddRequiredOption("workspace_path", &workspace_path,
                            "Dense workspace (image_undistorter output, plus "
                            "lidar_fused.ply for init lidar).");
  AddLidarPatchMatchOptions(&patch_match_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (!ExistsDir(workspace_path)) {
    LOG(ERROR) << "--workspace_path " << workspace_path << " is not a folder";
    return EXIT_FAILURE;
  }
  const LidarPatchMatchSummary summary =
      RunLidarPatchMatchStereo(workspace_path, patch_match_options);
  // Under mpirun the counts are every rank's; rank 0 prints them.
  if (!ProcessGroup::World().IsRoot()) {
    return EXIT_SUCCESS;
  }
  std::cout << "PatchMatch: " << summary.num_references << " images, "
            << summary.num_photometric_computed << " photometric ("
            << summary.num_photometric_skipped << " skipped), "
            << summary.num_geometric_computed << " geometric ("
            << summary.num_geometric_skipped << " skipped), "
            << summary.num_without_sources << " without sources, "
            << summary.seconds << " s" << std::endl;
  if (summary.support.Total() > 0) {
    std::cout << "Geometric maps: " << summary.support.Format() << "; "
              << summary.num_not_fused << " kept out of fusion ("
              << FusionMaskDir(workspace_path) << "); " << summary.num_filled
              << " textureless pixels filled" << std::endl;
  }
  return EXIT_SUCCESS;
}

}  // namespace colmap_lidar
