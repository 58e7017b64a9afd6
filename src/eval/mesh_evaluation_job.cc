#include "src/eval/mesh_evaluation_job.h"

#include <utility>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/dataset/poses.h"
#include "src/eval/pose_evaluator.h"

namespace colmap_lidar {

bool MeshEvaluationJob::Check() const {
  if (!evaluation_options.Check() || !icp_options.Check()) {
    return false;
  }
  if (!IsPoseAlignment(alignment)) {
    LOG(ERROR) << "--alignment must be none, se3, sim3, se3_axes or "
                  "sim3_axes, got '"
               << alignment << "'";
    return false;
  }
  if (!(axes_weight >= 0.0)) {
    LOG(ERROR) << "--axes_weight must be >= 0, got " << axes_weight;
    return false;
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
      return false;
    }
  }
  for (const auto& [name, path] : required_files) {
    if (!ExistsFile(path)) {
      LOG(ERROR) << name << " '" << path << "' does not exist";
      return false;
    }
  }
  return true;
}

std::string MeshEvaluationJob::IcpOutputPath() const {
  if (!icp_output_path.empty() || output_path.empty()) {
    return icp_output_path;
  }
  const size_t dot = output_path.rfind(".json");
  return dot != std::string::npos && dot + 5 == output_path.size()
             ? output_path.substr(0, dot) + "_icp.json"
             : output_path + "_icp.json";
}

MeshEvaluationJobResult RunMeshEvaluationJob(const MeshEvaluationJob& job,
                                             std::ostream* out) {
  THROW_CHECK(job.Check(), "Invalid mesh evaluation of " << job.input_path);
  MeshEvaluationJobResult result;
  if (job.alignment != "none") {
    PoseEvaluationOptions pose_options;
    pose_options.alignment = job.alignment;
    pose_options.axes_weight = job.axes_weight;
    const PoseEvaluation poses =
        EvaluatePoses(ReadReconstruction(job.alignment_model_path),
                      ReadPoses(job.ground_truth_poses_path), pose_options);
    result.reference_from_estimate = GroundTruthFromEstimate(poses);
    LOG(INFO) << "Aligned (" << job.alignment << ") by " << poses.num_matched
              << " camera centres, mean residual "
              << poses.position_stats_m.mean << " m";
  }
  result.evaluation =
      EvaluateMeshFiles(job.input_path, job.reference_path,
                        job.evaluation_options, result.reference_from_estimate);
  if (out != nullptr) {
    *out << FormatMeshEvaluation(result.evaluation) << std::flush;
  }
  if (!job.output_path.empty()) {
    WriteMeshEvaluationJson(job.output_path, result.evaluation);
    result.written_paths.push_back(job.output_path);
  }
  if (!job.colored_path.empty()) {
    WritePrecisionColoredPly(job.colored_path, result.evaluation);
    result.written_paths.push_back(job.colored_path);
  }
  if (!job.colored_reference_path.empty()) {
    WriteRecallColoredPly(job.colored_reference_path, result.evaluation);
    result.written_paths.push_back(job.colored_reference_path);
  }
  if (!job.icp) {
    return result;
  }
  result.icp = RefineMeshAlignmentIcpFiles(
      job.input_path, job.reference_path, result.reference_from_estimate,
      job.evaluation_options.ColorThreshold(),
      job.evaluation_options.crop_margin_m, job.icp_options);
  result.icp_evaluation = EvaluateMeshFiles(
      job.input_path, job.reference_path, job.evaluation_options,
      result.icp.refined_from_aligned * result.reference_from_estimate);
  result.has_icp = true;
  if (out != nullptr) {
    *out << "After ICP: " << FormatMeshIcpResult(result.icp) << "\n"
         << FormatMeshEvaluation(result.icp_evaluation) << std::flush;
  }
  const std::string icp_path = job.IcpOutputPath();
  if (!icp_path.empty()) {
    WriteMeshEvaluationJson(icp_path, result.icp_evaluation);
    result.written_paths.push_back(icp_path);
  }
  return result;
}

}  // namespace colmap_lidar
