#include "src/pipeline/pipeline_evaluation.h"

#include <filesystem>
#include <iomanip>
#include <map>
#include <sstream>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "src/dataset/poses.h"
#include "src/eval/depth_evaluator.h"
#include "src/eval/pose_evaluator.h"
#include "src/lidar/lidar_fusion.h"
#include "src/mesh/triangle_mesh.h"

namespace colmap_lidar {
namespace {

// Camera centres by frame name (image name or its file stem, as the pose
// evaluator matches them).
std::map<std::string, Eigen::Vector3d> CentresByFrame(
    const Reconstruction& model) {
  std::map<std::string, Eigen::Vector3d> centres;
  for (const Image& image : model.images) {
    std::string frame = image.name;
    const size_t slash = frame.find_last_of('/');
    if (slash != std::string::npos) {
      frame = frame.substr(slash + 1);
    }
    const size_t dot = frame.find_last_of('.');
    if (dot != std::string::npos) {
      frame = frame.substr(0, dot);
    }
    centres[frame] = image.ProjectionCenter();
  }
  return centres;
}

void WriteTrajectories(const std::string& path,
                       const std::vector<FramePose>& ground_truth,
                       const Reconstruction* prior,
                       const Reconstruction* refined) {
  const std::map<std::string, Eigen::Vector3d> prior_centres =
      prior != nullptr ? CentresByFrame(*prior)
                       : std::map<std::string, Eigen::Vector3d>();
  const std::map<std::string, Eigen::Vector3d> refined_centres =
      refined != nullptr ? CentresByFrame(*refined)
                         : std::map<std::string, Eigen::Vector3d>();
  WriteFileAtomically(
      path,
      [&](std::ostream& stream) {
        stream << std::setprecision(9);
        stream << "frame,gt_x,gt_y,gt_z,prior_x,prior_y,prior_z,refined_x,"
                  "refined_y,refined_z\n";
        const auto write_centre =
            [&stream](const std::map<std::string, Eigen::Vector3d>& centres,
                      const std::string& frame) {
              const auto it = centres.find(frame);
              if (it == centres.end()) {
                stream << ",,,";
              } else {
                stream << "," << it->second.x() << "," << it->second.y()
                       << "," << it->second.z();
              }
            };
        for (const FramePose& pose : ground_truth) {
          const Eigen::Vector3d& centre = pose.world_from_cam.translation;
          stream << pose.frame << "," << centre.x() << "," << centre.y()
                 << "," << centre.z();
          write_centre(prior_centres, pose.frame);
          write_centre(refined_centres, pose.frame);
          stream << "\n";
        }
      },
      /*binary=*/false);
}

// Evaluates `model_path` with `alignment` into <dir>/poses_<name>_<alignment>
// .json.
PoseEvaluation EvaluateModelPoses(const Reconstruction& model,
                                  const std::vector<FramePose>& ground_truth,
                                  const std::string& alignment,
                                  const std::string& name,
                                  const std::string& dir) {
  PoseEvaluationOptions options;
  options.alignment = alignment;
  const PoseEvaluation evaluation = EvaluatePoses(model, ground_truth, options);
  WritePoseEvaluationJson(
      JoinPaths(dir, "poses_" + name + "_" + alignment + ".json"), evaluation);
  LOG(INFO) << "evaluate: " << name << " poses (" << alignment << "): mean "
            << evaluation.position_stats_m.mean << " m, "
            << evaluation.rotation_stats_deg.mean << " deg over "
            << evaluation.num_matched << " of "
            << evaluation.num_ground_truth_frames << " frames";
  return evaluation;
}

// A mesh's alignment refined by ICP.
struct MeshIcpRecord {
  std::string name;
  Eigen::Affine3d reference_from_estimate;
  MeshIcpResult result;
};

// The applied mesh alignments (the trajectory fit, and per mesh the fit
// refined by ICP), for the report and for anyone re-evaluating the meshes
// with their own tools.
void WriteMeshAlignmentJson(const std::string& path,
                            const std::string& alignment,
                            const Eigen::Affine3d& reference_from_estimate,
                            const std::vector<MeshIcpRecord>& icp) {
  Json json;
  json["alignment"] = alignment;
  json["reference_from_estimate"] =
      MatrixRowsToJson(reference_from_estimate.matrix());
  // Per mesh: the fit refined by ICP against the reference.
  Json icp_json = Json::object();
  for (const MeshIcpRecord& record : icp) {
    const MeshIcpResult& result = record.result;
    Json& mesh = icp_json[record.name];
    mesh["reference_from_estimate"] =
        MatrixRowsToJson(record.reference_from_estimate.matrix());
    mesh["rotation_deg"] = result.rotation_deg;
    mesh["translation_m"] = result.translation_m;
    mesh["max_distance_m"] = result.stage_distances_m.back();
    mesh["inlier_ratio_before"] = result.inlier_ratio_before;
    mesh["inlier_ratio"] = result.inlier_ratio;
    mesh["inlier_rmse_before_m"] = result.inlier_rmse_before_m;
    mesh["inlier_rmse_m"] = result.inlier_rmse_m;
    mesh["converged"] = result.converged;
  }
  json["icp"] = std::move(icp_json);
  WriteJsonFile(path, json);
}

// Evaluates a mesh into <dir>/mesh_<name>.json and the two coloured PLYs;
// returns F at the threshold closest to 0.1 m.
double EvaluateMeshInto(const std::string& mesh_path,
                        const std::string& reference_path,
                        const MeshEvaluationOptions& options,
                        const Eigen::Affine3d& reference_from_estimate,
                        const std::string& name, const std::string& dir,
                        bool write_colored = true) {
  const MeshEvaluation evaluation = EvaluateMeshFiles(
      mesh_path, reference_path, options, reference_from_estimate);
  WriteMeshEvaluationJson(JoinPaths(dir, "mesh_" + name + ".json"),
                          evaluation);
  if (write_colored) {
    WritePrecisionColoredPly(
        JoinPaths(dir, "mesh_" + name + "_precision.ply"), evaluation);
    WriteRecallColoredPly(JoinPaths(dir, "mesh_" + name + "_recall.ply"),
                          evaluation);
  }
  size_t best = 0;
  for (size_t i = 0; i < evaluation.thresholds_m.size(); ++i) {
    if (std::abs(evaluation.thresholds_m[i] - 0.1) <
        std::abs(evaluation.thresholds_m[best] - 0.1)) {
      best = i;
    }
  }
  LOG(INFO) << "evaluate: mesh " << name << ": F "
            << evaluation.fscores[best] << " at "
            << evaluation.thresholds_m[best] << " m";
  return evaluation.fscores[best];
}

// Evaluates the mesh after the trajectory fit into mesh_<name>.json and,
// with options.mesh_icp, after an ICP refinement of that fit into
// mesh_<name>_icp.json (recorded in *records; a failed ICP is a warning and
// leaves no file). Returns "F@0.1 a", "F@0.1 a (ICP b)" or
// "F@0.1 a (no ICP)".
std::string EvaluateMeshWithIcp(const std::string& mesh_path,
                                const std::string& reference_path,
                                const MeshEvaluationOptions& mesh_options,
                                const PipelineEvaluationOptions& options,
                                const Eigen::Affine3d& reference_from_estimate,
                                const std::string& name,
                                const std::string& dir,
                                std::vector<MeshIcpRecord>* records) {
  std::ostringstream note;
  note << std::setprecision(3) << "F@0.1 "
       << EvaluateMeshInto(mesh_path, reference_path, mesh_options,
                           reference_from_estimate, name, dir);
  if (options.mesh_icp) {
    MeshIcpRecord record;
    record.name = name;
    try {
      record.result = RefineMeshAlignmentIcpFiles(
          mesh_path, reference_path, reference_from_estimate,
          mesh_options.ColorThreshold(), mesh_options.crop_margin_m,
          options.icp);
    } catch (const Error& error) {
      // E.g. no part of the mesh near the reference: the figures after the
      // trajectory fit stand alone.
      LOG(WARNING) << "evaluate: no ICP refinement of mesh " << name << ": "
                   << error.what();
      note << " (no ICP)";
      return note.str();
    }
    record.reference_from_estimate =
        record.result.refined_from_aligned * reference_from_estimate;
    LOG(INFO) << "evaluate: ICP of mesh " << name << ": "
              << FormatMeshIcpResult(record.result);
    note << " (ICP "
         << EvaluateMeshInto(mesh_path, reference_path, mesh_options,
                             record.reference_from_estimate, name + "_icp",
                             dir, /*write_colored=*/false)
         << ")";
    records->push_back(record);
  }
  return note.str();
}

// The LIDAR-only baseline: the registered cloud's points with a normal,
// meshed by stock poisson_mesher into `mesh_path`.
void MeshLidarWithPoisson(const std::string& cloud_path,
                          const std::string& work_dir,
                          const std::string& mesh_path,
                          const PipelineEvaluationOptions& options) {
  const FusedLidarCloud cloud = ReadFusedLidarCloud(cloud_path);
  std::vector<PlyPoint> points;
  points.reserve(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    // Points without a plane fit have a zero normal; Poisson needs one.
    if (cloud.normals[i].squaredNorm() > 0.5f) {
      PlyPoint point;
      point.xyz = cloud.points[i];
      point.normal = cloud.normals[i];
      points.push_back(point);
    }
  }
  THROW_CHECK(!points.empty(), "No LIDAR point with a normal in "
                                   << cloud_path);
  const std::string input_path = JoinPaths(work_dir, "lidar_points.ply");
  WriteColmapPlyPoints(input_path, points);
  const ColmapRunner colmap(options.colmap);
  const std::string raw_path = JoinPaths(work_dir, "lidar_poisson_raw.ply");
  colmap.Run("poisson_mesher",
             {{"input_path", input_path},
              {"output_path", raw_path},
              {"PoissonMeshing.depth", std::to_string(options.poisson_depth)},
              {"PoissonMeshing.trim", std::to_string(options.poisson_trim)},
              {"PoissonMeshing.color", "0"},
              {"PoissonMeshing.num_threads",
               std::to_string(options.num_threads)}});
  TriangleMesh mesh = ReadMeshPly(raw_path);
  const size_t num_dropped = RemoveNonFiniteFaces(&mesh);
  if (num_dropped > 0) {
    LOG(WARNING) << "evaluate: poisson_mesher gave " << num_dropped
                 << " faces with a non-finite vertex; dropped";
  }
  WriteMeshPly(mesh_path, mesh);
  std::filesystem::remove(raw_path);
}

}  // namespace

std::string EvaluatePipeline(const PipelineEvaluationInput& input,
                             const PipelineEvaluationOptions& options) {
  StagedDirectory staged(input.output_path);
  const std::string& dir = staged.path();
  std::ostringstream note;
  note << std::setprecision(3);

  // Identity unless the refined model and the ground truth give one.
  std::string mesh_alignment = "none";
  Eigen::Affine3d reference_from_estimate = Eigen::Affine3d::Identity();
  const std::string gt_path = JoinPaths(input.dataset_path, "poses_gt.txt");
  if (ExistsFile(gt_path)) {
    const std::vector<FramePose> ground_truth = ReadPoses(gt_path);
    std::unique_ptr<Reconstruction> prior;
    std::unique_ptr<Reconstruction> refined;
    if (ExistsModel(input.prior_model_path)) {
      prior = std::make_unique<Reconstruction>(
          ReadReconstruction(input.prior_model_path));
      note << "priors "
           << EvaluateModelPoses(*prior, ground_truth, "none", "prior", dir)
                  .position_stats_m.mean
           << " m; ";
    }
    if (ExistsModel(input.refined_model_path)) {
      refined = std::make_unique<Reconstruction>(
          ReadReconstruction(input.refined_model_path));
      note << "refined "
           << EvaluateModelPoses(*refined, ground_truth, "none", "refined",
                                 dir)
                  .position_stats_m.mean
           << " m (none), ";
      const PoseEvaluation se3 =
          EvaluateModelPoses(*refined, ground_truth, "se3", "refined", dir);
      const PoseEvaluation sim3 =
          EvaluateModelPoses(*refined, ground_truth, "sim3", "refined", dir);
      // The fit of centres and orientations: the centres alone leave the
      // roll about a straight walk free (a corridor's 0.45 deg read as
      // 13.7 deg), so its figures are the ones to quote.
      const PoseEvaluation sim3_axes = EvaluateModelPoses(
          *refined, ground_truth, "sim3_axes", "refined", dir);
      note << sim3.position_stats_m.mean << " m (sim3), "
           << sim3_axes.position_stats_m.mean << " m / "
           << sim3_axes.rotation_stats_deg.mean << " deg (sim3_axes); ";
      if (options.mesh_alignment == "se3") {
        mesh_alignment = options.mesh_alignment;
        reference_from_estimate = GroundTruthFromEstimate(se3);
      } else if (options.mesh_alignment == "sim3") {
        mesh_alignment = options.mesh_alignment;
        reference_from_estimate = GroundTruthFromEstimate(sim3);
      } else if (options.mesh_alignment == "se3_axes" ||
                 options.mesh_alignment == "sim3_axes") {
        mesh_alignment = options.mesh_alignment;
        reference_from_estimate = GroundTruthFromEstimate(EvaluateModelPoses(
            *refined, ground_truth, mesh_alignment, "refined", dir));
      }
    }
    if (ExistsModel(input.mapper_model_path)) {
      const Reconstruction mapper = ReadReconstruction(input.mapper_model_path);
      if (mapper.images.size() >= 3) {
        note << "colmap mapper "
             << EvaluateModelPoses(mapper, ground_truth, "sim3",
                                   "colmap_mapper", dir)
                    .position_stats_m.mean
             << " m (sim3, " << mapper.images.size() << " images); ";
      }
    }
    WriteTrajectories(JoinPaths(dir, "trajectories.csv"), ground_truth,
                      prior.get(), refined.get());
  }

  const std::string reference_path =
      JoinPaths(input.dataset_path, "reference.ply");
  if (ExistsFile(reference_path)) {
    MeshEvaluationOptions mesh_options = options.mesh;
    if (mesh_options.observed_cloud_path.empty() &&
        ExistsFile(input.lidar_cloud_path)) {
      mesh_options.observed_cloud_path = input.lidar_cloud_path;
    }
    // The true surface of a synthetic recording judges precision where
    // the survey is too sparse to (mesh_evaluator.h).
    const std::string surface_path =
        JoinPaths(input.dataset_path, "ground_truth/scene.ply");
    if (mesh_options.reference_surface_path.empty() &&
        ExistsFile(surface_path)) {
      mesh_options.reference_surface_path = surface_path;
    }
    // Its crease edges give the figures near them (edge_region.h), where
    // the line samples are meant to help.
    const std::string edges_path =
        JoinPaths(input.dataset_path, "ground_truth/crease_edges.txt");
    if (mesh_options.edge_region_path.empty() && ExistsFile(edges_path)) {
      mesh_options.edge_region_path = edges_path;
    }
    note << "meshes aligned (" << mesh_alignment << "): ";
    std::vector<MeshIcpRecord> icp_records;
    if (ExistsFile(input.mesh_path)) {
      note << "mesh "
           << EvaluateMeshWithIcp(input.mesh_path, reference_path,
                                  mesh_options, options,
                                  reference_from_estimate, "ours", dir,
                                  &icp_records);
    }
    if (options.lidar_baseline && ExistsFile(input.lidar_cloud_path)) {
      const std::string poisson_path =
          JoinPaths(dir, "mesh_lidar_poisson.ply");
      MeshLidarWithPoisson(input.lidar_cloud_path, dir, poisson_path, options);
      note << ", LIDAR-only Poisson "
           << EvaluateMeshWithIcp(poisson_path, reference_path,
                                  mesh_options, options,
                                  reference_from_estimate, "lidar_poisson",
                                  dir, &icp_records);
    }
    WriteMeshAlignmentJson(JoinPaths(dir, "mesh_alignment.json"),
                           mesh_alignment, reference_from_estimate,
                           icp_records);
  }
  if ((!ExistsFile(gt_path) || options.real_data_always) &&
      ExistsFile(input.database_path) &&
      ExistsModel(input.refined_model_path)) {
    RealDataEvaluationInput real_input;
    real_input.database_path = input.database_path;
    real_input.prior_model_path = input.prior_model_path;
    real_input.refined_model_path = input.refined_model_path;
    real_input.mesh_path = input.mesh_path;
    real_input.lidar_cloud_path = input.lidar_cloud_path;
    RealDataEvaluationOptions real_options = options.real_data;
    real_options.num_threads = options.num_threads;
    const RealDataEvaluation real = EvaluateRealData(real_input, real_options);
    WriteRealDataJson(JoinPaths(dir, "real_data.json"), real);
    note << (note.tellp() > 0 ? "; " : "") << "crispness refined "
         << real.refined_crispness.median_m << " m";
    if (real.has_prior) {
      note << ", prior " << real.prior_crispness.median_m << " m";
    }
    note << "; length / odometry " << real.trajectory.length_ratio;
  }
  // Depth maps against the synthesizer's ground truth (depth_maps.json):
  // the dense workspace is the folder of lidar_fused.ply.
  const std::string dense_path =
      std::filesystem::path(input.lidar_cloud_path).parent_path().string();
  if (ExistsDir(JoinPaths(input.dataset_path, "ground_truth/depth_maps")) &&
      ExistsDir(JoinPaths(dense_path, "stereo/depth_maps"))) {
    DepthEvaluationOptions depth_options;
    depth_options.num_threads = options.num_threads;
    const DepthEvaluation depth =
        EvaluateDepthMaps(dense_path, input.dataset_path, depth_options);
    WriteDepthEvaluationJson(JoinPaths(dir, "depth_maps.json"), depth);
    const std::string summary = DepthSummary(depth, "geometric").empty()
                                    ? DepthSummary(depth, "photometric")
                                    : DepthSummary(depth, "geometric");
    LOG(INFO) << "evaluate: depth maps of " << depth.images.size()
              << " images: " << DepthSummary(depth, "photometric") << "; "
              << DepthSummary(depth, "geometric");
    note << (note.tellp() > 0 ? "; " : "") << "depth maps " << summary;
  }
  staged.Commit();
  return note.str();
}

}  // namespace colmap_lidar
