// Subcommands that evaluate results against ground truth: pose_evaluator,
// mesh_evaluator, line_evaluator. Each prints a fixed-width table on stdout
// and optionally writes a JSON report (--output_path) for scripts.
#include <cstdlib>
#include <iostream>
#include <string>

#include "colmap_ext/exe/commands.h"
#include "colmap_ext/exe/option_manager.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/dataset/poses.h"
#include "src/eval/line_evaluator.h"
#include "src/eval/mesh_evaluator.h"
#include "src/eval/pose_evaluator.h"
#include "src/eval/segment_io.h"

namespace colmap_lidar {
namespace {

// Section [PoseEvaluation]; keep configs/pose_evaluator.ini in step.
void AddPoseEvaluationOptions(PoseEvaluationOptions* evaluation,
                              OptionManager* options) {
  options->AddOption("PoseEvaluation.alignment", &evaluation->alignment,
                     "Alignment of the estimated camera centres to the "
                     "ground truth before measuring: none | se3 | sim3 "
                     "(Umeyama; se3/sim3 need >= 3 matched images).");
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
  options->AddOption("MeshEvaluation.crop_margin_m",
                     &evaluation->crop_margin_m,
                     "Estimate points outside the bounding box of the kept "
                     "reference enlarged by this margin (metres) are "
                     "ignored for precision; < 0 disables the crop.");
  options->AddOption("MeshEvaluation.color_threshold_m",
                     &evaluation->color_threshold_m,
                     "Distance shown red in the coloured PLYs, metres; 0: "
                     "the largest threshold <= 0.1 m.");
  options->AddOption("MeshEvaluation.seed", &evaluation->seed,
                     "Seed of the mesh sampling, >= 0.");
  options->AddCheck([evaluation] { return evaluation->Check(); });
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
  std::string input_path;
  std::string reference_path;
  std::string output_path;
  std::string colored_path;
  std::string colored_reference_path;
  std::string alignment = "none";
  std::string alignment_model_path;
  std::string ground_truth_poses_path;
  MeshEvaluationOptions evaluation_options;

  OptionManager options;
  options.AddRequiredOption("input_path", &input_path,
                            "Estimated mesh PLY (faces are sampled) or point "
                            "cloud PLY (no faces: its vertices are used).");
  options.AddRequiredOption("reference_path", &reference_path,
                            "Reference point cloud PLY (same world frame, "
                            "metres).");
  options.AddOption("output_path", &output_path,
                    "JSON report to write; empty: none.");
  options.AddOption("colored_path", &colored_path,
                    "PLY of the estimate points coloured by distance to the "
                    "reference (precision view); empty: none.");
  options.AddOption("colored_reference_path", &colored_reference_path,
                    "PLY of the reference points coloured by distance to "
                    "the estimate (recall view); empty: none.");
  options.AddOption("alignment", &alignment,
                    "none | se3 | sim3: before the comparison, the estimate "
                    "(and the observed cloud) are carried into the "
                    "reference's frame by the Umeyama fit of "
                    "alignment_model_path's camera centres to "
                    "ground_truth_poses_path (the gauge of a reconstruction "
                    "from noisy priors).");
  options.AddOption("alignment_model_path", &alignment_model_path,
                    "Sparse model whose poses the estimate was built with; "
                    "needed unless alignment is none.");
  options.AddOption("ground_truth_poses_path", &ground_truth_poses_path,
                    "Ground-truth poses (poses_gt.txt layout); needed "
                    "unless alignment is none.");
  AddMeshEvaluationOptions(&evaluation_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (alignment != "none" && alignment != "se3" && alignment != "sim3") {
    LOG(ERROR) << "--alignment must be none, se3 or sim3, got '" << alignment
               << "'";
    return EXIT_FAILURE;
  }
  std::vector<std::pair<std::string, std::string>> required_files = {
      {"--input_path", input_path}, {"--reference_path", reference_path}};
  if (alignment != "none") {
    required_files.emplace_back("--ground_truth_poses_path",
                                ground_truth_poses_path);
    if (!ExistsDir(alignment_model_path)) {
      LOG(ERROR) << "--alignment " << alignment
                 << " needs --alignment_model_path, a sparse model folder; "
                    "got '"
                 << alignment_model_path << "'";
      return EXIT_FAILURE;
    }
  }
  for (const auto& [name, path] : required_files) {
    if (!ExistsFile(path)) {
      LOG(ERROR) << name << " '" << path << "' does not exist";
      return EXIT_FAILURE;
    }
  }

  Eigen::Affine3d reference_from_estimate = Eigen::Affine3d::Identity();
  if (alignment != "none") {
    PoseEvaluationOptions pose_options;
    pose_options.alignment = alignment;
    const PoseEvaluation poses =
        EvaluatePoses(ReadReconstruction(alignment_model_path),
                      ReadPoses(ground_truth_poses_path), pose_options);
    reference_from_estimate = GroundTruthFromEstimate(poses);
    LOG(INFO) << "Aligned (" << alignment << ") by " << poses.num_matched
              << " camera centres, mean residual "
              << poses.position_stats_m.mean << " m";
  }
  const MeshEvaluation evaluation = EvaluateMeshFiles(
      input_path, reference_path, evaluation_options, reference_from_estimate);
  std::cout << FormatMeshEvaluation(evaluation) << std::flush;
  if (!output_path.empty()) {
    WriteMeshEvaluationJson(output_path, evaluation);
  }
  if (!colored_path.empty()) {
    WritePrecisionColoredPly(colored_path, evaluation);
  }
  if (!colored_reference_path.empty()) {
    WriteRecallColoredPly(colored_reference_path, evaluation);
  }
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

}  // namespace colmap_lidar
