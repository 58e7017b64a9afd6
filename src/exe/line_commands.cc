// Subcommands of the line detection module (paper section III-B):
// line_extractor and line_exporter.
#include <cstdlib>
#include <iostream>
#include <string>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/process_group.h"
#include "colmap_ext/util/string.h"
#include "src/exe/commands.h"
#include "src/exe/option_manager.h"
#include "src/lines/line_export.h"
#include "src/lines/workspace_line_extractor.h"

namespace colmap_lidar {
namespace {

// Section [LineExtraction]; keep configs/line_extractor.ini in step.
void AddLineExtractionOptions(LineExtractionOptions* o,
                              OptionManager* options) {
  const std::string s = "LineExtraction.";
  options->AddOption(s + "num_threads", &o->num_threads,
                     "Images processed in parallel; -1: all cores.");
  // LSD.
  options->AddOption(s + "lsd_min_length_px", &o->lsd.min_length_px,
                     "Minimum 2D segment length, pixels, >= 0.");
  options->AddOption(s + "lsd_scale", &o->lsd.scale,
                     "LSD image scale, (0, 1]; smaller is faster.");
  options->AddOption(s + "lsd_refine", &o->lsd.refine,
                     "LSD refinement (LSD_REFINE_STD), 0/1.");
  options->AddOption(s + "lsd_max_num_segments", &o->lsd.max_num_segments,
                     "Keep at most the N longest 2D segments; 0: all.");
  // LIDAR edges.
  options->AddOption(s + "edge_method", &o->edges.method,
                     "LIDAR edge detector: auto | ring (LeGO-LOAM "
                     "smoothness) | pca (unorganised clouds).");
  options->AddOption(s + "edge_num_rings", &o->edges.num_rings,
                     "Lasers of the LIDAR, to estimate rings when the scan "
                     "has no ring channel.");
  options->AddOption(s + "edge_num_neighbors", &o->edges.num_neighbors,
                     "Smoothness window: neighbours on each side, >= 1.");
  options->AddOption(s + "edge_smoothness_threshold",
                     &o->edges.smoothness_threshold,
                     "Smoothness above which a point is an edge, >= 0.");
  options->AddOption(s + "edge_num_sectors", &o->edges.num_sectors,
                     "Sectors per ring for the count limit, >= 1.");
  options->AddOption(s + "edge_max_edges_per_sector",
                     &o->edges.max_edges_per_sector,
                     "Edge points per ring and sector at most, >= 1.");
  options->AddOption(s + "edges_at_gaps", &o->edges.edges_at_gaps,
                     "Points next to missing returns are occluding "
                     "contours, 0/1.");
  options->AddOption(s + "edge_occlusion_range_gap",
                     &o->edges.occlusion_range_gap,
                     "Range jump of an occlusion boundary, metres, > 0.");
  options->AddOption(s + "edge_occlusion_range_ratio",
                     &o->edges.occlusion_range_ratio,
                     "... or this fraction of the nearer range when smaller "
                     "(0: off), >= 0.");
  options->AddOption(s + "edge_parallel_beam_ratio",
                     &o->edges.parallel_beam_ratio,
                     "Parallel-beam rejection: range step / range, > 0.");
  options->AddOption(s + "edge_max_elevation_step_deg",
                     &o->edges.max_elevation_step_deg,
                     "Elevation step between ring neighbours that marks a "
                     "seam between lasers, degrees, > 0.");
  options->AddOption(s + "edge_max_azimuth_gap_steps",
                     &o->edges.max_azimuth_gap_steps,
                     "Azimuth gap (in median steps) that breaks a ring, "
                     ">= 1.");
  options->AddOption(s + "edge_min_range", &o->edges.min_range,
                     "LIDAR points nearer than this are ignored, metres.");
  options->AddOption(s + "edge_max_range", &o->edges.max_range,
                     "LIDAR points farther than this are ignored, metres.");
  options->AddOption(s + "edge_min_regular_step_fraction",
                     &o->edges.min_regular_step_fraction,
                     "auto: below this fraction of regular azimuth steps "
                     "the cloud is unorganised (PCA edges), [0, 1].");
  options->AddOption(s + "edge_pca_radius", &o->edges.pca_radius,
                     "PCA edges: neighbourhood radius, metres, > 0.");
  options->AddOption(s + "edge_pca_min_neighbors",
                     &o->edges.pca_min_neighbors,
                     "PCA edges: minimum neighbours, >= 3.");
  options->AddOption(s + "edge_pca_min_surface_variation",
                     &o->edges.pca_min_surface_variation,
                     "PCA edges: surface variation threshold, (0, 1/3].");
  // Projection.
  options->AddOption(s + "min_depth", &o->projection.min_depth,
                     "LIDAR points nearer to the camera are ignored, metres.");
  options->AddOption(s + "max_depth", &o->projection.max_depth,
                     "LIDAR points farther from the camera are ignored, "
                     "metres.");
  options->AddOption(s + "zbuffer_cell_px", &o->projection.zbuffer_cell_px,
                     "Z-buffer cell size, pixels, >= 1.");
  options->AddOption(s + "zbuffer_relative_tolerance",
                     &o->projection.zbuffer_relative_tolerance,
                     "Z-buffer: visible up to min depth * (1 + this) + "
                     "absolute tolerance.");
  options->AddOption(s + "zbuffer_absolute_tolerance",
                     &o->projection.zbuffer_absolute_tolerance,
                     "Z-buffer absolute tolerance, metres.");
  // Association.
  options->AddOption(s + "max_point_distance_px",
                     &o->association.max_point_distance_px,
                     "Edge point to 2D segment distance, pixels, > 0.");
  options->AddOption(s + "ransac_inlier_distance",
                     &o->association.ransac.inlier_distance,
                     "RANSAC point-line distance of an inlier, metres.");
  options->AddOption(s + "ransac_max_iterations",
                     &o->association.ransac.max_iterations,
                     "RANSAC hypotheses at most, >= 1.");
  options->AddOption(s + "min_inliers", &o->association.ransac.min_inliers,
                     "Minimum LIDAR edge points of a 3D segment, >= 2.");
  options->AddOption(s + "refine_along_rings",
                     &o->association.refine_along_rings,
                     "Move edge points along their ring onto the 2D "
                     "segment's viewing plane, 0/1.");
  options->AddOption(s + "max_refine_steps",
                     &o->association.max_refine_steps,
                     "Ring steps searched by that refinement, >= 1.");
  options->AddOption(s + "max_refine_move_steps",
                     &o->association.max_refine_move_steps,
                     "Drop edge points that refinement moves by more than "
                     "this many ring steps (another crease nearby); 0: keep "
                     "all.");
  options->AddOption(s + "refine_max_range_jump",
                     &o->association.refine_max_range_jump,
                     "Range jump between ring neighbours not interpolated "
                     "(occluding contour), metres.");
  options->AddOption(s + "refine_range_jump_ratio",
                     &o->association.refine_range_jump_ratio,
                     "... or this fraction of the nearer range when smaller "
                     "(0: off), >= 0.");
  options->AddOption(s + "fit_in_viewing_plane",
                     &o->association.fit_in_viewing_plane,
                     "Refit the 3D line inside the 2D segment's viewing "
                     "plane, 0/1.");
  options->AddOption(s + "min_inlier_coverage",
                     &o->association.min_inlier_coverage,
                     "Fraction of the 2D segment the inliers must span, "
                     "[0, 1].");
  options->AddOption(s + "max_extrapolation",
                     &o->association.max_extrapolation,
                     "Clip the 2D segment to its LIDAR support extended by "
                     "this fraction of it on each side; < 0: no clipping.");
  options->AddOption(s + "max_reprojection_angle_deg",
                     &o->association.max_reprojection_angle_deg,
                     "Reprojected 3D line vs 2D segment angle, degrees.");
  options->AddOption(s + "max_reprojection_distance_px",
                     &o->association.max_reprojection_distance_px,
                     "2D endpoint to reprojected 3D line distance, pixels.");
  options->AddOption(s + "min_ray_line_angle_deg",
                     &o->association.min_ray_line_angle_deg,
                     "Endpoint back-projection: minimum ray-line angle, "
                     "degrees.");
  options->AddOption(s + "max_endpoint_range",
                     &o->association.max_endpoint_range,
                     "3D endpoints farther from the camera are rejected, "
                     "metres.");
  // Texture rejection.
  options->AddOption(s + "reject_texture_lines",
                     &o->association.texture.enabled,
                     "Discard lines without normal change (texture only), "
                     "0/1.");
  options->AddOption(s + "texture_radius", &o->association.texture.radius,
                     "Texture test: neighbourhood radius, metres.");
  options->AddOption(s + "texture_exclusion_distance",
                     &o->association.texture.exclusion_distance,
                     "Texture test: points this near the line are ignored, "
                     "metres.");
  options->AddOption(s + "texture_exclusion_noise_sigmas",
                     &o->association.texture.exclusion_noise_sigmas,
                     "Texture test: points within this many range-noise "
                     "sigmas of the line (measured on the scan, or "
                     "plane_range_noise_m) are ignored too (at most a "
                     "quarter of the radius), >= 0; 0: off. Not in the "
                     "paper.");
  options->AddOption(s + "texture_min_side_points",
                     &o->association.texture.min_side_points,
                     "Texture test: points per side for a plane, >= 3.");
  options->AddOption(s + "texture_min_normal_change_deg",
                     &o->association.texture.min_normal_change_deg,
                     "Texture test: normal change of an edge, degrees.");
  options->AddOption(s + "texture_keep_occlusions",
                     &o->association.texture.keep_occlusions,
                     "Keep occluding contours of planar faces (a crease "
                     "whose other face is hidden), 0/1.");
  options->AddOption(s + "texture_max_face_residual",
                     &o->association.texture.max_face_residual,
                     "Occluding contour: median distance of the face's "
                     "points to a plane through the line at most this, "
                     "metres (else a silhouette, discarded).");
  options->AddOption(s + "texture_min_face_extent",
                     &o->association.texture.min_face_extent,
                     "Occluding contour: the face reaches at least this far "
                     "from the line, metres (else a thin object's "
                     "silhouette, discarded).");
  options->AddOption(s + "texture_min_open_space_points",
                     &o->association.texture.min_open_space_points,
                     "Occluding contour: LIDAR rays past the empty side that "
                     "end behind the face's plane (open space) or on it (the "
                     "face goes on past a gap between rings: texture), at "
                     "least this many for either; else unknown, >= 0; 0: "
                     "off (an empty side is open space). Not in the paper.");
  options->AddOption(s + "texture_keep_unknown",
                     &o->association.texture.keep_unknown,
                     "Keep lines with too few LIDAR points around them to "
                     "classify, 0/1.");
  // Lifting by the surfaces on both sides (src/lines/plane_lifting.h).
  options->AddOption(s + "plane_lifting", &o->planes.enabled,
                     "Lift the segments that no edge point supports with "
                     "the LIDAR planes on their two sides (crease: the "
                     "planes' intersection; occluding or step edge: the "
                     "nearer plane's boundary), 0/1. Not in the paper.");
  options->AddOption(s + "plane_band_gap_px", &o->planes.band_gap_px,
                     "Plane lifting: points nearer the segment than this "
                     "belong to neither side, pixels, >= 0.");
  options->AddOption(s + "plane_max_band_fraction",
                     &o->planes.max_band_fraction,
                     "Plane lifting: the side bands reach this fraction of "
                     "the image diagonal, (0, 0.5].");
  options->AddOption(s + "plane_max_side_points", &o->planes.max_side_points,
                     "Plane lifting: the nearest this many points per side.");
  options->AddOption(s + "plane_min_side_points", &o->planes.min_side_points,
                     "Plane lifting: plane inliers needed per side, >= 3.");
  options->AddOption(s + "plane_range_noise_m", &o->planes.range_noise_m,
                     "Plane lifting: LIDAR range noise sigma, metres; 0: "
                     "estimated from the scans (plane inlier distance 2.5 "
                     "sigma).");
  options->AddOption(s + "plane_min_plane_spread",
                     &o->planes.min_plane_spread,
                     "Plane lifting: in-plane spread of a side's inliers, "
                     "in noise sigmas (one ring is not a plane), >= 0.");
  options->AddOption(s + "plane_min_crease_angle_deg",
                     &o->planes.min_crease_angle_deg,
                     "Plane lifting: angle between the two planes of a "
                     "crease, degrees, (0, 90].");
  options->AddOption(s + "plane_min_step_sigmas", &o->planes.min_step_sigmas,
                     "Plane lifting: depth step of an occluding or step "
                     "edge, in noise sigmas (at least 4 cm), > 0.");
  options->AddOption(s + "plane_min_coverage", &o->planes.min_coverage,
                     "Plane lifting: fraction of the segment both sides "
                     "support, [0, 1].");
  options->AddOption(s + "plane_keep_occlusions", &o->planes.keep_occlusions,
                     "Plane lifting: keep occluding and step edges, 0/1.");
  options->AddOption(s + "plane_boundary_band_fraction",
                     &o->planes.boundary_band_fraction,
                     "Plane lifting: an occluding edge's step must show in "
                     "the points within this fraction of the band's reach, "
                     "(0, 1].");
  options->AddOption(s + "plane_max_boundary_violations",
                     &o->planes.max_boundary_violations,
                     "Plane lifting: fraction of those points that may "
                     "disagree, [0, 1).");
  options->AddOption(s + "plane_snap_to_near_points",
                     &o->planes.snap_to_near_points,
                     "Plane lifting: place an occluding edge at the depth of "
                     "the near side's points next to it, 0/1.");
  // Fusion.
  options->AddOption(s + "fusion_max_angle_deg", &o->fusion.max_angle_deg,
                     "Fusion: maximum angle between 3D segments, degrees.");
  options->AddOption(s + "fusion_max_line_distance",
                     &o->fusion.max_line_distance,
                     "Fusion: endpoint to other line distance, metres.");
  options->AddOption(s + "fusion_max_gap", &o->fusion.max_gap,
                     "Fusion: gap between collinear segments, metres.");
  options->AddOption(s + "compute_descriptors", &o->compute_descriptors,
                     "Compute LBD descriptors, 0/1 (0 stores zeros).");
  options->AddCheck([o] { return o->Check(); });
}

}  // namespace

int RunLineExtractor(int argc, char** argv) {
  std::string database_path;
  std::string image_path;
  std::string image_list_path;
  std::string debug_path;
  LineExtractionOptions extraction_options;

  OptionManager options;
  options.AddRequiredOption("database_path", &database_path,
                            "COLMAP database with ext_lidar_scans (from "
                            "lidar_importer).");
  options.AddRequiredOption("image_path", &image_path, "Image folder.");
  options.AddOption("image_list_path", &image_list_path,
                    "Text file with one image name per line; empty: all "
                    "images with a LIDAR scan.");
  options.AddOption("debug_path", &debug_path,
                    "Folder for per-image overlays (PNG) and per-segment "
                    "outcomes (JSON); empty: none.");
  AddLineExtractionOptions(&extraction_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (!ExistsFile(database_path)) {
    LOG(ERROR) << "--database_path " << database_path << " does not exist";
    return EXIT_FAILURE;
  }
  if (!ExistsDir(image_path)) {
    LOG(ERROR) << "--image_path " << image_path << " is not a folder";
    return EXIT_FAILURE;
  }
  std::vector<std::string> image_names;
  if (!image_list_path.empty()) {
    if (!ExistsFile(image_list_path)) {
      LOG(ERROR) << "--image_list_path " << image_list_path
                 << " does not exist";
      return EXIT_FAILURE;
    }
    for (std::string line : StringSplit(ReadTextFile(image_list_path), "\n")) {
      line = StringTrim(line);
      if (!line.empty()) {
        image_names.push_back(line);
      }
    }
  }
  const WorkspaceLineExtractionSummary summary = ExtractWorkspaceLines(
      database_path, image_path, image_names, extraction_options, debug_path);
  // Under mpirun rank 0 has every rank's images in its summary.
  if (ProcessGroup::World().IsRoot()) {
    std::cout << summary.Format() << std::endl;
  }
  return EXIT_SUCCESS;
}

int RunLineExporter(int argc, char** argv) {
  std::string database_path;
  std::string input_path;
  std::string output_path;

  OptionManager options;
  options.AddRequiredOption("database_path", &database_path,
                            "COLMAP database with ext_line_segments.");
  options.AddRequiredOption("input_path", &input_path,
                            "Sparse model folder whose poses place the "
                            "segments in the world.");
  options.AddRequiredOption("output_path", &output_path,
                            "Output file, .ply or .obj.");
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
  const Database database(database_path);
  const LineExportSummary summary = ExportWorldLineSegments(
      database, ReadReconstruction(input_path), output_path);
  std::cout << "Exported " << summary.num_segments << " 3D segments of "
            << summary.num_images << " images to " << output_path;
  if (summary.num_images_missing > 0) {
    std::cout << " (" << summary.num_images_missing
              << " images not in the model skipped)";
  }
  std::cout << std::endl;
  return EXIT_SUCCESS;
}

}  // namespace colmap_lidar
