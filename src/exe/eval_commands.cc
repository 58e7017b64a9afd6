// Subcommands that evaluate results against ground truth: pose_evaluator,
// mesh_evaluator, line_evaluator, depth_evaluator; and without it:
// real_data_evaluator. Each prints a table (or a line) on stdout and
// optionally writes a JSON report (--output_path) for scripts.
#include <cstdlib>
#include <iostream>
#include <string>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/dataset/poses.h"
#include "src/eval/depth_evaluator.h"
#include "src/eval/line_evaluator.h"
#include "src/eval/mesh_evaluation_job.h"
#include "src/eval/mesh_evaluator.h"
#include "src/eval/mesh_icp.h"
#include "src/eval/pose_evaluator.h"
#include "src/eval/real_data_evaluator.h"
#include "src/eval/segment_io.h"
#include "src/exe/commands.h"
#include "src/exe/option_manager.h"

namespace colmap_lidar {
namespace {

// Section [PoseEvaluation]; keep configs/pose_evaluator.ini in step.
void AddPoseEvaluationOptions(PoseEvaluationOptions* evaluation,
                              OptionManager* options) {
  options->AddOption("PoseEvaluation.alignment", &evaluation->alignment,
                     "Alignment of the estimate to the ground truth before "
                     "measuring: none | se3 | sim3 (Umeyama on the camera "
                     "centres) | se3_axes | sim3_axes (fit of the centres "
                     "and the camera orientations, which fixes the roll "
                     "about a straight trajectory); all but none need >= 3 "
                     "matched images.");
  options->AddOption("PoseEvaluation.axes_weight", &evaluation->axes_weight,
                     "*_axes only: weight of the orientations against the "
                     "centres, >= 0; 1 puts the axis points at the RMS "
                     "spread of the centres.");
  options->AddOption("PoseEvaluation.position_thresholds_m",
                     &evaluation->position_thresholds_m,
                     "Position error thresholds for the recalls, metres, "
                     "positive and increasing.");
  options->AddOption("PoseEvaluation.rotation_thresholds_deg",
                     &evaluation->rotation_thresholds_deg,
                     "Rotation error thresholds for the recalls, degrees, "
                     "positive and increasing; paired with the position "
                     "thresholds when both lists have the same length.");
  options->AddCheck([evaluation] { return evaluation->Check(); });
}

// Section [MeshEvaluation]; keep configs/mesh_evaluator.ini in step.
void AddMeshEvaluationOptions(MeshEvaluationOptions* evaluation,
                              OptionManager* options) {
  options->AddOption("MeshEvaluation.thresholds_m", &evaluation->thresholds_m,
                     "Distance thresholds of precision / recall / F-score, "
                     "metres, positive and increasing.");
  options->AddOption("MeshEvaluation.sample_density_per_m2",
                     &evaluation->sample_density_per_m2,
                     "Uniform samples per square metre of the estimated "
                     "mesh (precision side), > 0.");
  options->AddOption("MeshEvaluation.recall_to_mesh",
                     &evaluation->recall_to_mesh,
                     "Recall distances to the mesh surface itself (exact "
                     "point-to-triangle); if 0, to the mesh samples.");
  options->AddOption("MeshEvaluation.observed_cloud_path",
                     &evaluation->observed_cloud_path,
                     "Optional PLY of what the sensors observed; reference "
                     "points farther than observed_radius_m from it are not "
                     "counted for recall. Empty: keep all.");
  options->AddOption("MeshEvaluation.observed_radius_m",
                     &evaluation->observed_radius_m,
                     "Radius around the observed cloud, metres, > 0.");
  options->AddOption("MeshEvaluation.observed_cloud_in_reference_frame",
                     &evaluation->observed_cloud_in_reference_frame,
                     "The observed cloud is in the reference's frame (e.g. "
                     "the scans fused with the true poses, to judge "
                     "reconstructions in different frames on one region); "
                     "0: in the estimate's, carried with it.");
  options->AddOption("MeshEvaluation.visible_model_path",
                     &evaluation->visible_model_path,
                     "Optional COLMAP model of the cameras in the reference's "
                     "frame (e.g. the true poses): only the reference points "
                     "its images could see (inside an image, not hidden by "
                     "the reference's own surface) count for recall, the "
                     "paper's whole visible reference. Empty: no test.");
  options->AddOption("MeshEvaluation.crop_margin_m",
                     &evaluation->crop_margin_m,
                     "Estimate points outside the bounding box of the kept "
                     "reference enlarged by this margin (metres) are "
                     "ignored for precision; < 0 disables the crop.");
  options->AddOption("MeshEvaluation.reference_surface_path",
                     &evaluation->reference_surface_path,
                     "Optional mesh PLY of the true surface (a synthetic "
                     "scene's ground_truth/scene.ply), in the reference's "
                     "frame: precision distances are then to this surface "
                     "instead of to the nearest reference point, which is "
                     "sparse where the survey grazes. Empty: the reference "
                     "points. automatic_reconstructor uses the dataset's "
                     "ground_truth/scene.ply when it exists.");
  options->AddOption("MeshEvaluation.edge_region_path",
                     &evaluation->edge_region_path,
                     "Optional file of crease edges (x1 y1 z1 x2 y2 z2 per "
                     "line, e.g. a synthetic scene's "
                     "ground_truth/crease_edges.txt, or a segment PLY), in "
                     "the reference's frame: the figures are also reported "
                     "for the samples and reference points within "
                     "edge_region_radius_m of an edge. Empty: none. "
                     "automatic_reconstructor uses the dataset's "
                     "ground_truth/crease_edges.txt when it exists.");
  options->AddOption("MeshEvaluation.edge_region_radius_m",
                     &evaluation->edge_region_radius_m,
                     "Radius of the edge region around each edge, metres, "
                     "> 0.");
  options->AddOption("MeshEvaluation.color_threshold_m",
                     &evaluation->color_threshold_m,
                     "Distance shown red in the coloured PLYs, metres; 0: "
                     "the largest threshold <= 0.1 m.");
  options->AddOption("MeshEvaluation.seed", &evaluation->seed,
                     "Seed of the mesh sampling, >= 0.");
  options->AddCheck([evaluation] { return evaluation->Check(); });
}

// Section [MeshIcp]; keep configs/mesh_evaluator.ini and the
// automatic_reconstructor's evaluate stage in step.
void AddMeshIcpOptions(MeshIcpOptions* icp, OptionManager* options) {
  options->AddOption("MeshIcp.method", &icp->method,
                     "point_to_plane (reference normals from local plane "
                     "fits) | point_to_point.");
  options->AddOption("MeshIcp.max_distance_factor", &icp->max_distance_factor,
                     "Final largest correspondence distance as a multiple of "
                     "the colour threshold (the largest evaluation threshold "
                     "<= 0.1 m), > 0.");
  options->AddOption("MeshIcp.num_stages", &icp->num_stages,
                     "Coarse-to-fine stages, the distance halving per stage "
                     "down to the final one, >= 1.");
  options->AddOption("MeshIcp.max_num_iterations", &icp->max_num_iterations,
                     "ICP iterations per stage at most, >= 1.");
  options->AddOption("MeshIcp.max_num_samples", &icp->max_num_samples,
                     "Mesh samples (cropped to the reference's box) used at "
                     "most, >= 100.");
  options->AddOption("MeshIcp.normal_num_neighbors",
                     &icp->normal_num_neighbors,
                     "Neighbours of the reference's normal plane fits, >= 3.");
  options->AddOption("MeshIcp.seed", &icp->seed,
                     "Seed of the mesh sampling, >= 0.");
  options->AddCheck([icp] { return icp->Check(); });
}

// Section [LineEvaluation]; keep configs/line_evaluator.ini in step.
void AddLineEvaluationOptions(LineEvaluationOptions* evaluation,
                              OptionManager* options) {
  options->AddOption("LineEvaluation.thresholds_m", &evaluation->thresholds_m,
                     "Distance thresholds of the length precision / recall, "
                     "metres, positive and increasing.");
  options->AddOption("LineEvaluation.sample_step_m",
                     &evaluation->sample_step_m,
                     "Length of the segment pieces whose midpoints are "
                     "tested, metres, > 0.");
  options->AddCheck([evaluation] { return evaluation->Check(); });
}

// Section [RealDataEvaluation]; keep configs/real_data_evaluator.ini in step.
void AddRealDataEvaluationOptions(RealDataEvaluationOptions* evaluation,
                                  OptionManager* options) {
  options->AddOption("RealDataEvaluation.crispness_voxel_size_m",
                     &evaluation->crispness_voxel_size_m,
                     "Voxel thinning each scan for the crispness, metres, "
                     ">= 0; 0: median range of the first scan times "
                     "crispness_voxel_angle_deg, clamped to [0.05, 0.3].");
  options->AddOption("RealDataEvaluation.crispness_voxel_angle_deg",
                     &evaluation->crispness_voxel_angle_deg,
                     "Angle giving the data-derived voxel, degrees, > 0.");
  options->AddOption("RealDataEvaluation.crispness_radius_voxels",
                     &evaluation->crispness_radius_voxels,
                     "Plane neighbourhood radius in voxels, > 1.");
  options->AddOption("RealDataEvaluation.crispness_min_neighbors",
                     &evaluation->crispness_min_neighbors,
                     "Points of other scans needed for a plane, >= 3.");
  options->AddOption("RealDataEvaluation.crispness_min_planarity",
                     &evaluation->crispness_min_planarity,
                     "Middle / largest covariance eigenvalue below which a "
                     "neighbourhood is a line, not a plane, [0, 1].");
  options->AddOption("RealDataEvaluation.crispness_max_queries_per_scan",
                     &evaluation->crispness_max_queries_per_scan,
                     "Query points per scan at most, >= 1.");
  options->AddOption("RealDataEvaluation.min_range_m",
                     &evaluation->registration.min_range_m,
                     "LIDAR points nearer than this to their scanner are "
                     "ignored (the ego vehicle), metres, >= 0.");
  options->AddOption("RealDataEvaluation.max_range_m",
                     &evaluation->registration.max_range_m,
                     "LIDAR points farther than this are ignored, metres.");
  options->AddOption("RealDataEvaluation.min_fitness",
                     &evaluation->min_fitness,
                     "Odometry registrations below this fitness are counted "
                     "as failed, [0, 1].");
  options->AddOption("RealDataEvaluation.mesh_thresholds_m",
                     &evaluation->mesh_thresholds_m,
                     "Mesh vs LIDAR distance thresholds, metres, positive "
                     "and increasing.");
  options->AddOption("RealDataEvaluation.mesh_sample_density_per_m2",
                     &evaluation->mesh_sample_density_per_m2,
                     "Mesh samples per square metre, > 0 (lowered to at "
                     "most max_mesh_samples samples).");
  options->AddOption("RealDataEvaluation.max_mesh_samples",
                     &evaluation->max_mesh_samples,
                     "Mesh samples at most, >= 1000.");
  options->AddOption("RealDataEvaluation.mesh_view_max_depth_m",
                     &evaluation->mesh_view_max_depth_m,
                     "LIDAR points in view: in a refined camera's image and "
                     "at most this deep in front of it, metres, > 0 (the "
                     "in-view share of LIDAR points near the mesh).");
  options->AddOption("RealDataEvaluation.num_threads",
                     &evaluation->num_threads, "Threads; <= 0: all cores.");
  options->AddCheck([evaluation] { return evaluation->Check(); });
}

// Section [DepthEvaluation]; keep configs/depth_evaluator.ini in step.
void AddDepthEvaluationOptions(DepthEvaluationOptions* evaluation,
                               OptionManager* options) {
  options->AddOption("DepthEvaluation.thresholds_m",
                     &evaluation->thresholds_m,
                     "Depth error thresholds, metres, positive and "
                     "increasing; JSON keys within_<cm>cm.");
  options->AddOption("DepthEvaluation.max_bilinear_spread",
                     &evaluation->max_bilinear_spread,
                     "The truth is interpolated bilinearly where its 4 "
                     "neighbours are valid and (max - min) <= this times "
                     "min (relative, >= 0), else its nearest pixel is taken "
                     "(depth edges are never blended); 0: always nearest.");
  options->AddOption("DepthEvaluation.max_normal_relative_step",
                     &evaluation->max_normal_relative_step,
                     "Surface distances (surface_within_<cm>cm): the truth's "
                     "normal is taken where a neighbour on each axis differs "
                     "in depth by at most this share (> 0), else the depth "
                     "error is the distance.");
  options->AddOption("DepthEvaluation.map_types", &evaluation->map_types,
                     "Depth map types to evaluate: photometric, geometric.");
  options->AddOption("DepthEvaluation.num_threads",
                     &evaluation->num_threads,
                     "Threads over the images; <= 0: all cores.");
  options->AddCheck([evaluation] { return evaluation->Check(); });
}

}  // namespace

int RunPoseEvaluator(int argc, char** argv) {
  std::string input_path;
  std::string ground_truth_path;
  std::string output_path;
  PoseEvaluationOptions evaluation_options;

  OptionManager options;
  options.AddRequiredOption("input_path", &input_path,
                            "Sparse model folder (cameras, images, points3D "
                            ".bin or .txt) to evaluate.");
  options.AddRequiredOption("ground_truth_path", &ground_truth_path,
                            "Ground-truth poses (poses_gt.txt: frame tx ty "
                            "tz qx qy qz qw, world_from_cam).");
  options.AddOption("output_path", &output_path,
                    "JSON report to write; empty: none.");
  AddPoseEvaluationOptions(&evaluation_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (!ExistsDir(input_path)) {
    LOG(ERROR) << "--input_path " << input_path << " is not a folder";
    return EXIT_FAILURE;
  }
  if (!ExistsFile(ground_truth_path)) {
    LOG(ERROR) << "--ground_truth_path " << ground_truth_path
               << " does not exist";
    return EXIT_FAILURE;
  }

  const Reconstruction model = ReadReconstruction(input_path);
  const std::vector<FramePose> ground_truth = ReadPoses(ground_truth_path);
  const PoseEvaluation evaluation =
      EvaluatePoses(model, ground_truth, evaluation_options);
  std::cout << FormatPoseEvaluation(evaluation) << std::flush;
  if (!output_path.empty()) {
    WritePoseEvaluationJson(output_path, evaluation);
  }
  return EXIT_SUCCESS;
}

int RunMeshEvaluator(int argc, char** argv) {
  MeshEvaluationJob job;
  OptionManager options;
  options.AddRequiredOption("input_path", &job.input_path,
                            "Estimated mesh PLY (faces are sampled) or point "
                            "cloud PLY (no faces: its vertices are used).");
  options.AddRequiredOption("reference_path", &job.reference_path,
                            "Reference point cloud PLY (same world frame, "
                            "metres).");
  options.AddOption("output_path", &job.output_path,
                    "JSON report to write; empty: none.");
  options.AddOption("colored_path", &job.colored_path,
                    "PLY of the estimate points coloured by distance to the "
                    "reference (precision view); empty: none.");
  options.AddOption("colored_reference_path", &job.colored_reference_path,
                    "PLY of the reference points coloured by distance to "
                    "the estimate (recall view); empty: none.");
  options.AddOption("alignment", &job.alignment,
                    "none | se3 | sim3 | se3_axes | sim3_axes: before the "
                    "comparison, the estimate (and the observed cloud) are "
                    "carried into the reference's frame by the fit of "
                    "alignment_model_path's cameras to "
                    "ground_truth_poses_path (the gauge of a reconstruction "
                    "from noisy priors): Umeyama on the camera centres, or "
                    "(*_axes, as Tanks and Temples) on the centres and "
                    "orientations, which fixes the roll about a straight "
                    "trajectory.");
  options.AddOption("axes_weight", &job.axes_weight,
                    "*_axes only: weight of the orientations against the "
                    "centres, >= 0 (see pose_evaluator).");
  options.AddOption("icp", &job.icp,
                    "Then refine the alignment by ICP of the mesh against "
                    "the reference ([MeshIcp]) and report the figures after "
                    "it too.");
  options.AddOption("icp_output_path", &job.icp_output_path,
                    "JSON report after ICP; empty: output_path with _icp "
                    "before .json (none without output_path).");
  options.AddOption("alignment_model_path", &job.alignment_model_path,
                    "Sparse model whose poses the estimate was built with; "
                    "needed unless alignment is none.");
  options.AddOption("ground_truth_poses_path", &job.ground_truth_poses_path,
                    "Ground-truth poses (poses_gt.txt layout); needed "
                    "unless alignment is none.");
  AddMeshEvaluationOptions(&job.evaluation_options, &options);
  AddMeshIcpOptions(&job.icp_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (!job.Check()) {
    return EXIT_FAILURE;
  }
  // Prints the figures (and those after ICP) as each is computed.
  RunMeshEvaluationJob(job, &std::cout);
  return EXIT_SUCCESS;
}

int RunLineEvaluator(int argc, char** argv) {
  std::string input_path;
  std::string ground_truth_path;
  std::string output_path;
  LineEvaluationOptions evaluation_options;

  OptionManager options;
  options.AddRequiredOption("input_path", &input_path,
                            "Estimated 3D segments: a sparse model folder "
                            "(its lines3D), a .ply (edge element or vertex "
                            "pairs), an .obj (l elements) or a text file "
                            "(x1 y1 z1 x2 y2 z2 per line).");
  options.AddRequiredOption("ground_truth_path", &ground_truth_path,
                            "Ground-truth edges in the same formats, e.g. "
                            "ground_truth/crease_edges.txt.");
  options.AddOption("output_path", &output_path,
                    "JSON report to write; empty: none.");
  AddLineEvaluationOptions(&evaluation_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (!ExistsDir(input_path) && !ExistsFile(input_path)) {
    LOG(ERROR) << "--input_path " << input_path << " does not exist";
    return EXIT_FAILURE;
  }
  if (!ExistsFile(ground_truth_path)) {
    LOG(ERROR) << "--ground_truth_path " << ground_truth_path
               << " does not exist";
    return EXIT_FAILURE;
  }

  const std::vector<Segment3D> estimate = ReadSegments(input_path);
  const std::vector<Segment3D> ground_truth = ReadSegments(ground_truth_path);
  THROW_CHECK(!ground_truth.empty(),
              "--ground_truth_path " << ground_truth_path
                                     << " holds no segments");
  const LineEvaluation evaluation =
      EvaluateLines(estimate, ground_truth, evaluation_options);
  std::cout << FormatLineEvaluation(evaluation) << std::flush;
  if (!output_path.empty()) {
    WriteLineEvaluationJson(output_path, evaluation);
  }
  return EXIT_SUCCESS;
}

int RunRealDataEvaluator(int argc, char** argv) {
  std::string workspace_path;
  std::string output_path;
  RealDataEvaluationOptions evaluation_options;

  OptionManager options;
  options.AddRequiredOption(
      "workspace_path", &workspace_path,
      "Pipeline workspace: database.db (scans), sparse/refined, "
      "sparse/prior (optional), dense/meshed-delaunay.ply and "
      "dense/lidar_fused.ply (optional, for the mesh figures).");
  options.AddOption("output_path", &output_path,
                    "JSON report to write (e.g. <ws>/eval/real_data.json); "
                    "empty: none.");
  AddRealDataEvaluationOptions(&evaluation_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (!ExistsDir(workspace_path)) {
    LOG(ERROR) << "--workspace_path " << workspace_path << " does not exist";
    return EXIT_FAILURE;
  }
  RealDataEvaluationInput input;
  input.database_path = JoinPaths(workspace_path, "database.db");
  input.prior_model_path = JoinPaths(workspace_path, "sparse/prior");
  input.refined_model_path = JoinPaths(workspace_path, "sparse/refined");
  input.mesh_path = JoinPaths(workspace_path, "dense/meshed-delaunay.ply");
  input.lidar_cloud_path = JoinPaths(workspace_path, "dense/lidar_fused.ply");
  const RealDataEvaluation evaluation =
      EvaluateRealData(input, evaluation_options);
  std::cout << FormatRealDataEvaluation(evaluation) << std::endl;
  if (!output_path.empty()) {
    WriteRealDataJson(output_path, evaluation);
  }
  return EXIT_SUCCESS;
}


int RunDepthEvaluator(int argc, char** argv) {
  std::string workspace_path;
  std::string dataset_path;
  std::string output_path;
  DepthEvaluationOptions evaluation_options;

  OptionManager options;
  options.AddRequiredOption("workspace_path", &workspace_path,
                            "Pipeline workspace (its dense/ is used) or a "
                            "dense workspace (images/, sparse/, "
                            "stereo/depth_maps/).");
  options.AddRequiredOption("dataset_path", &dataset_path,
                            "Synthesized recording with calibration.yaml and "
                            "ground_truth/depth_maps/<frame>.bin.");
  options.AddOption("output_path", &output_path,
                    "JSON report to write (e.g. <ws>/eval/depth_maps.json); "
                    "empty: none.");
  AddDepthEvaluationOptions(&evaluation_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  std::string dense_path = workspace_path;
  if (!ExistsDir(JoinPaths(dense_path, "stereo"))) {
    dense_path = JoinPaths(workspace_path, "dense");
  }
  if (!ExistsDir(JoinPaths(dense_path, "stereo/depth_maps"))) {
    LOG(ERROR) << "--workspace_path " << workspace_path
               << " has no stereo/depth_maps, neither itself nor in dense/";
    return EXIT_FAILURE;
  }
  if (!ExistsDir(JoinPaths(dataset_path, "ground_truth/depth_maps"))) {
    LOG(ERROR) << "--dataset_path " << dataset_path
               << " has no ground_truth/depth_maps (synthesize writes them "
                  "with --write_depth_maps 1)";
    return EXIT_FAILURE;
  }
  const DepthEvaluation evaluation =
      EvaluateDepthMaps(dense_path, dataset_path, evaluation_options);
  std::cout << FormatDepthEvaluation(evaluation) << std::flush;
  if (!output_path.empty()) {
    WriteDepthEvaluationJson(output_path, evaluation);
  }
  return EXIT_SUCCESS;
}

}  // namespace colmap_lidar
