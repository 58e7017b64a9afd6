// Subcommand lidar_delaunay_mesher: Delaunay meshing of a dense workspace's
// fused visual points, optional LIDAR voxels and optional 3D line samples
// (Amblard et al. Sec. III-E; src/mesh/delaunay_mesher.h).
#include <cstdlib>
#include <string>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/process_group.h"
#include "src/exe/commands.h"
#include "src/exe/option_manager.h"
#include "src/exe/option_sections.h"
#include "src/mesh/delaunay_mesher.h"

namespace colmap_lidar {

// Section [DelaunayMeshing]; keep configs/lidar_delaunay_mesher.ini in step.
void AddDelaunayMeshingOptions(DelaunayMeshingOptions* meshing,
                               MeshingInputOptions* input,
                               OptionManager* options) {
  options->AddOption("DelaunayMeshing.use_visual", &input->use_visual,
                     "Use <workspace>/fused.ply (+ fused.ply.vis), which "
                     "must then exist.");
  options->AddOption("DelaunayMeshing.use_lidar", &input->use_lidar,
                     "Use <workspace>/lidar_fused.ply (+ .vis and "
                     "lidar_origins.txt) when it exists.");
  options->AddOption("DelaunayMeshing.visual_weight", &input->visual_weight,
                     "Weight of a camera ray, times 1 - exp(-n^2 / (2 "
                     "visibility_sigma^2)) for a point seen in n images; "
                     ">= 0.");
  options->AddOption("DelaunayMeshing.visibility_sigma",
                     &input->visibility_sigma,
                     "Sigma of the visibility probability above, images, "
                     "> 0.");
  options->AddOption("DelaunayMeshing.lidar_weight", &input->lidar_weight,
                     "Weight of a LIDAR voxel, spread over the frames that "
                     "saw it, times g(count); >= 0.");
  options->AddOption("DelaunayMeshing.lidar_count_mapping",
                     &input->lidar_count_mapping,
                     "g(count) of a LIDAR voxel: none (1) | linear (count) "
                     "| log (1 + ln count).");
  options->AddOption("DelaunayMeshing.max_lidar_rays_per_point",
                     &input->max_lidar_rays_per_point,
                     "Rays of a LIDAR voxel from at most this many of its "
                     "frames, the nearest scanner positions; 0: all.");
  options->AddOption("DelaunayMeshing.line_weight", &input->line_weight,
                     "Weight of each ray of a 3D line sample, times the "
                     "visibility probability of a point seen in as many "
                     "images as observed the sample, >= 0.");
  options->AddOption("DelaunayMeshing.line_sample_step_m",
                     &input->line_sample_step_m,
                     "Spacing of the samples along a 3D line segment, "
                     "metres, >= 0; 0: the spacing of the surface points "
                     "that the line validation measures (not in the "
                     "paper).");
  options->AddOption("DelaunayMeshing.validate_lines", &input->validate_lines,
                     "Sample only the 3D lines that lie on a crease of the "
                     "visual and LIDAR points, moved onto it (not in the "
                     "paper); false samples every line where it was "
                     "estimated (the paper).");
  options->AddOption("DelaunayMeshing.line_samples_only_in_gaps",
                     &input->line_samples_only_in_gaps,
                     "With validate_lines, sample a crease only where no "
                     "visual or LIDAR point lies within the validation's "
                     "plane band of the sample.");
  options->AddOption("DelaunayMeshing.lidar_denoise_radius_m",
                     &input->lidar_denoising.radius_m,
                     "LIDAR voxels are projected onto the plane fitted to "
                     "the voxels within this radius when that neighbourhood "
                     "is planar, metres; 0 disables. >= 0. Not in the "
                     "paper.");
  options->AddOption("DelaunayMeshing.lidar_denoise_max_plane_std_m",
                     &input->lidar_denoising.max_plane_std_m,
                     "A neighbourhood is planar when its standard deviation "
                     "along the fitted normal is below the larger of this "
                     "(metres, > 0) and lidar_denoise_plane_std_factor times "
                     "the median of that deviation (the measured noise).");
  options->AddOption("DelaunayMeshing.lidar_denoise_plane_std_factor",
                     &input->lidar_denoising.plane_std_factor,
                     "Planarity threshold as a multiple of the median "
                     "deviation across the local planes, >= 0; 0 keeps "
                     "lidar_denoise_max_plane_std_m alone.");
  options->AddOption("DelaunayMeshing.lidar_denoise_min_neighbors",
                     &input->lidar_denoising.min_neighbors,
                     "Fewest voxels within the radius for a plane fit, >= 3.");
  options->AddOption("DelaunayMeshing.view_depth_quantile",
                     &meshing->view_depth_quantile,
                     "Quantile of the visual points' depths in their cameras "
                     "that sets the view region's depth, (0, 1].");
  options->AddOption("DelaunayMeshing.view_depth_factor",
                     &meshing->view_depth_factor,
                     "Crop the input to the cameras' view: inside an image "
                     "and at most this times that depth quantile in front of "
                     "the camera; 0 meshes everything (surfaces only the "
                     "LIDAR sees included). 2 bounds KITTI's meshing to "
                     "minutes. >= 0.");
  options->AddOption("DelaunayMeshing.max_proj_dist_px",
                     &meshing->max_proj_dist_px,
                     "A visual point whose projection is within this many "
                     "pixels of a nearby vertex in all its images is merged "
                     "into it; 0 inserts all points. >= 0.");
  options->AddOption("DelaunayMeshing.max_depth_dist",
                     &meshing->max_depth_dist,
                     "Relative depth difference allowed for that merge, "
                     "[0, 1].");
  options->AddOption("DelaunayMeshing.min_lidar_vertex_distance_m",
                     &meshing->min_lidar_vertex_distance_m,
                     "A LIDAR voxel closer than this to a visual or line "
                     "vertex is merged into it (the LIDAR-initialised depth "
                     "maps refine the voxel there), metres; 0 inserts all. "
                     ">= 0. Not in the paper.");
  options->AddOption("DelaunayMeshing.distance_sigma_factor",
                     &meshing->distance_sigma_factor,
                     "Free-space weight falloff sigma near a point, relative "
                     "to the lower-quartile Delaunay edge length, > 0.");
  options->AddOption("DelaunayMeshing.behind_distance_factor",
                     &meshing->behind_distance_factor,
                     "The inside weight goes to the cell this many sigma "
                     "behind the point, > 0.");
  options->AddOption("DelaunayMeshing.max_free_space_length_factor",
                     &meshing->max_free_space_length_factor,
                     "Free space is carved at most this many sigma in front "
                     "of a point (long rays make the graph cut slow); 0 "
                     "carves whole rays. >= 0.");
  options->AddOption("DelaunayMeshing.quality_regularization",
                     &meshing->quality_regularization,
                     "Weight of the surface-quality term per facet "
                     "(Labatut et al. 2009), >= 0.");
  options->AddOption("DelaunayMeshing.max_edge_length_factor",
                     &meshing->max_edge_length_factor,
                     "Clean-up: remove faces with an edge longer than this "
                     "times the median edge length; 0 disables. >= 0.");
  options->AddOption("DelaunayMeshing.min_component_faces",
                     &meshing->min_component_faces,
                     "Clean-up: remove connected components with fewer "
                     "faces; 0 keeps all. >= 0.");
  options->AddOption("DelaunayMeshing.snap_to_creases",
                     &meshing->snap_to_creases,
                     "Move the mesh's vertices near the creases of the "
                     "validated 3D lines onto the creases' two faces. Not "
                     "in the paper.");
  options->AddOption("DelaunayMeshing.crease_radius_factor",
                     &meshing->crease_snapping.radius_factor,
                     "Vertices within this many point spacings of a crease "
                     "are snapped, > 0.");
  options->AddOption("DelaunayMeshing.crease_max_move_factor",
                     &meshing->crease_snapping.max_move_factor,
                     "Largest move of a snapped vertex, in point spacings, "
                     "> 0.");
  options->AddOption("DelaunayMeshing.crease_local_radius_factor",
                     &meshing->crease_snapping.local_radius_factor,
                     "A vertex is snapped only when the surface points "
                     "within this many point spacings of it lie on the "
                     "crease's faces, > 0.");
  options->AddOption("DelaunayMeshing.crease_max_local_offset_factor",
                     &meshing->crease_snapping.max_local_offset_factor,
                     "Largest median distance of those surface points to "
                     "the crease's faces, in point spacings, > 0.");
  options->AddOption("DelaunayMeshing.crease_min_local_points",
                     &meshing->crease_snapping.min_local_points,
                     "Fewest surface points around a vertex for it to be "
                     "snapped, >= 1.");
  options->AddOption("DelaunayMeshing.max_memory_gb", &meshing->max_memory_gb,
                     "Memory budget, GiB: inputs with more than "
                     "max_memory_gb * 2^30 / 2500 points are meshed by "
                     "spatial tiles that fit it (a tile that still exceeds "
                     "it is decimated on a voxel grid). > 0.");
  options->AddOption("DelaunayMeshing.tile_margin_m", &meshing->tile_margin_m,
                     "Meshing by tiles: points within this distance of a "
                     "tile's core join its meshing; only the faces whose "
                     "centroid lies in the core are kept, metres. >= 0.");
  options->AddOption("DelaunayMeshing.num_threads", &meshing->num_threads,
                     "Threads of the ray casting; <= 0 uses all cores.");
  options->AddCheck([meshing, input] {
    const bool meshing_ok = meshing->Check();
    const bool input_ok = input->Check();
    return meshing_ok && input_ok;
  });
}


int RunLidarDelaunayMesher(int argc, char** argv) {
  std::string workspace_path;
  std::string output_path;
  std::string lines_path;
  std::string database_path;
  DelaunayMeshingOptions meshing_options;
  MeshingInputOptions input_options;

  OptionManager options;
  options.AddRequiredOption("workspace_path", &workspace_path,
                            "Dense workspace (sparse/, fused.ply, "
                            "fused.ply.vis; optional lidar_fused.ply, "
                            "lidar_fused.ply.vis, lidar_origins.txt).");
  options.AddRequiredOption("output_path", &output_path,
                            "Mesh PLY to write (binary, float x y z, "
                            "faces as vertex_indices).");
  options.AddOption("lines_path", &lines_path,
                    "Model folder with lines3D.bin/.txt whose segments are "
                    "sampled into the triangulation; empty: no lines.");
  options.AddOption("database_path", &database_path,
                    "Database with the 2D line segments (ext_line_segments) "
                    "that the lines' tracks index: a sample's rays then come "
                    "only from the images that observed it. Empty: from "
                    "every image of the line's track.");
  AddDelaunayMeshingOptions(&meshing_options, &input_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (!ExistsDir(workspace_path)) {
    LOG(ERROR) << "--workspace_path " << workspace_path << " is not a folder";
    return EXIT_FAILURE;
  }
  if (!lines_path.empty() && !ExistsDir(lines_path)) {
    LOG(ERROR) << "--lines_path " << lines_path << " is not a folder";
    return EXIT_FAILURE;
  }
  if (!database_path.empty() && !ExistsFile(database_path)) {
    LOG(ERROR) << "--database_path " << database_path << " is not a file";
    return EXIT_FAILURE;
  }
  const DelaunayMeshingSummary summary =
      MeshDenseWorkspace(meshing_options, input_options, workspace_path,
                         lines_path, output_path, database_path);
  // Under mpirun the figures are rank 0's (the merged mesh).
  if (!ProcessGroup::World().IsRoot()) {
    return EXIT_SUCCESS;
  }
  LOG(INFO) << "lidar_delaunay_mesher: " << summary.num_input_points
            << " points, " << summary.num_vertices << " Delaunay vertices, "
            << summary.num_faces << " faces; triangulation "
            << summary.triangulation_seconds << " s, visibility "
            << summary.visibility_seconds << " s, graph cut "
            << summary.graph_cut_seconds << " s, total "
            << summary.total_seconds << " s; peak memory "
            << summary.peak_memory_bytes / (1024.0 * 1024.0) << " MiB";
  return EXIT_SUCCESS;
}

}  // namespace colmap_lidar
