#include "src/eval/mesh_evaluation_job.h"

#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/poses.h"
#include "src/eval/corner_test_scene.h"
#include "src/eval/mesh_sampling.h"

namespace colmap_lidar {
namespace {

using testing::Corner;
using testing::CornerMesh;
using testing::Displacement;
using testing::EstimateFromReference;

// The corner mesh carried by `transform`, written to `path`.
void WriteCorner(const std::string& path, const Eigen::Affine3d& transform) {
  Corner corner = CornerMesh();
  for (Eigen::Vector3d& vertex : corner.vertices) {
    vertex = transform * vertex;
  }
  testing::WritePointsPly(path, corner.vertices, corner.triangles);
}

// The inputs of a job in a fresh test folder: the true corner sampled as
// the reference cloud (2000 points per m2, 2.2 cm apart), ground-truth
// poses of six cameras around it, and a sparse model of those cameras in
// the estimate's frame (EstimateFromReference).
struct Inputs {
  std::string dir;
  std::string reference_path;
  std::string ground_truth_poses_path;
  std::string model_path;
};

Inputs WriteInputs() {
  Inputs inputs;
  inputs.dir = testing::CreateTestDir();
  inputs.reference_path = JoinPaths(inputs.dir, "reference.ply");
  inputs.ground_truth_poses_path = JoinPaths(inputs.dir, "poses_gt.txt");
  inputs.model_path = JoinPaths(inputs.dir, "sparse");
  const Corner corner = CornerMesh();
  testing::WritePointsPly(inputs.reference_path,
              SampleTriangleMesh(corner.vertices, corner.triangles, 2000.0,
                                 /*seed=*/5));

  testing::WriteCornerCameras(inputs.ground_truth_poses_path,
                              inputs.model_path);
  return inputs;
}

MeshEvaluationJob JobFor(const Inputs& inputs, const std::string& mesh_path) {
  MeshEvaluationJob job;
  job.input_path = mesh_path;
  job.reference_path = inputs.reference_path;
  job.alignment_model_path = inputs.model_path;
  job.ground_truth_poses_path = inputs.ground_truth_poses_path;
  job.evaluation_options.thresholds_m = {0.05, 0.2};
  job.evaluation_options.sample_density_per_m2 = 300.0;
  job.icp_options.max_num_samples = 5000;
  return job;
}

// The true corner, not aligned: near perfect at 5 cm; the report, the two
// coloured PLYs and the text are those of the evaluation.
TEST(MeshEvaluationJob, WithoutAlignmentWritesReportAndColouredPlys) {
  const Inputs inputs = WriteInputs();
  const std::string mesh_path = JoinPaths(inputs.dir, "mesh.ply");
  WriteCorner(mesh_path, Eigen::Affine3d::Identity());
  MeshEvaluationJob job = JobFor(inputs, mesh_path);
  job.output_path = JoinPaths(inputs.dir, "eval.json");
  job.colored_path = JoinPaths(inputs.dir, "precision.ply");
  job.colored_reference_path = JoinPaths(inputs.dir, "recall.ply");
  ASSERT_TRUE(job.Check());
  std::ostringstream out;
  const MeshEvaluationJobResult result = RunMeshEvaluationJob(job, &out);

  EXPECT_TRUE(result.reference_from_estimate.matrix().isIdentity());
  EXPECT_TRUE(result.evaluation.estimate_is_mesh);
  EXPECT_NEAR(result.evaluation.estimate_area_m2, 72.0, 1e-9);
  ASSERT_EQ(result.evaluation.fscores.size(), 2u);
  EXPECT_GT(result.evaluation.precisions[0], 0.99);
  EXPECT_DOUBLE_EQ(result.evaluation.recalls[0], 1.0);  // Exact to the mesh.
  EXPECT_FALSE(result.has_icp);
  EXPECT_EQ(out.str(), FormatMeshEvaluation(result.evaluation));
  EXPECT_EQ(result.written_paths,
            std::vector<std::string>({job.output_path, job.colored_path,
                                      job.colored_reference_path}));
  const Json json = ReadJsonFile(job.output_path);
  EXPECT_EQ(json.at("evaluator"), "mesh");
  EXPECT_EQ(json.at("fscore"), Json(result.evaluation.fscores));
  EXPECT_EQ(ReadPly(job.colored_path).NumVertices(),
            result.evaluation.estimate_points.size());
  EXPECT_EQ(ReadPly(job.colored_reference_path).NumVertices(),
            result.evaluation.reference_points.size());
  // No ICP: no _icp report, though output_path names one.
  EXPECT_FALSE(ExistsFile(JoinPaths(inputs.dir, "eval_icp.json")));
}

// The corner in the reconstruction's frame: unaligned it misses the
// reference; aligned by the model's cameras against the ground-truth poses
// (se3 and the fit of centres and axes) it matches it.
TEST(MeshEvaluationJob, AlignmentByTheCamerasCarriesTheMesh) {
  const Inputs inputs = WriteInputs();
  const std::string mesh_path = JoinPaths(inputs.dir, "mesh.ply");
  WriteCorner(mesh_path, EstimateFromReference());
  MeshEvaluationJob job = JobFor(inputs, mesh_path);
  const MeshEvaluationJobResult unaligned = RunMeshEvaluationJob(job);
  EXPECT_LT(unaligned.evaluation.fscores[0], 0.2);
  EXPECT_TRUE(unaligned.written_paths.empty());

  for (const std::string alignment : {"se3", "sim3_axes"}) {
    job.alignment = alignment;
    ASSERT_TRUE(job.Check()) << alignment;
    const MeshEvaluationJobResult aligned = RunMeshEvaluationJob(job);
    EXPECT_TRUE(aligned.reference_from_estimate.matrix().isApprox(
        EstimateFromReference().inverse().matrix(), 1e-6))
        << alignment;
    EXPECT_GT(aligned.evaluation.precisions[0], 0.99) << alignment;
    EXPECT_GT(aligned.evaluation.recalls[0], 0.999) << alignment;
    EXPECT_LT(aligned.evaluation.completeness_m.max, 1e-6) << alignment;
  }

  // Cameras that match no ground-truth frame cannot align.
  Reconstruction model = ReadReconstruction(inputs.model_path);
  for (Image& image : model.images) {
    image.name = "other_" + image.name;
  }
  WriteReconstruction(inputs.model_path, model, ModelFormat::kBinary);
  EXPECT_THROW(RunMeshEvaluationJob(job), Error);
}

// ICP after the (here: no) alignment removes a residual misplacement; the
// report after it goes to output_path with _icp before .json.
TEST(MeshEvaluationJob, IcpRefinesAndWritesTheIcpReport) {
  const Inputs inputs = WriteInputs();
  const std::string mesh_path = JoinPaths(inputs.dir, "mesh.ply");
  WriteCorner(mesh_path, Displacement());
  MeshEvaluationJob job = JobFor(inputs, mesh_path);
  job.output_path = JoinPaths(inputs.dir, "eval.json");
  job.icp = true;
  EXPECT_EQ(job.IcpOutputPath(), JoinPaths(inputs.dir, "eval_icp.json"));
  std::ostringstream out;
  const MeshEvaluationJobResult result = RunMeshEvaluationJob(job, &out);

  ASSERT_TRUE(result.has_icp);
  const Eigen::Affine3d residual =
      result.icp.refined_from_aligned * Displacement();
  EXPECT_LT(Eigen::AngleAxisd(residual.linear()).angle() * 180.0 / M_PI, 0.05);
  EXPECT_LT(residual.translation().norm(), 0.005);
  EXPECT_LT(result.evaluation.fscores[0], 0.7);
  EXPECT_GT(result.icp_evaluation.fscores[0], 0.97);
  EXPECT_EQ(out.str(), FormatMeshEvaluation(result.evaluation) +
                           "After ICP: " + FormatMeshIcpResult(result.icp) +
                           "\n" + FormatMeshEvaluation(result.icp_evaluation));
  EXPECT_EQ(result.written_paths,
            std::vector<std::string>({job.output_path, job.IcpOutputPath()}));
  EXPECT_EQ(ReadJsonFile(job.output_path).at("fscore"),
            Json(result.evaluation.fscores));
  EXPECT_EQ(ReadJsonFile(job.IcpOutputPath()).at("fscore"),
            Json(result.icp_evaluation.fscores));

  // The _icp path: explicit wins; appended when output_path is not .json;
  // none without either.
  job.icp_output_path = JoinPaths(inputs.dir, "after.json");
  EXPECT_EQ(job.IcpOutputPath(), job.icp_output_path);
  job.icp_output_path = "";
  job.output_path = "report.txt";
  EXPECT_EQ(job.IcpOutputPath(), "report.txt_icp.json");
  job.output_path = "";
  EXPECT_EQ(job.IcpOutputPath(), "");
}

TEST(MeshEvaluationJob, RefusesBadOptionsAndMissingInputs) {
  const Inputs inputs = WriteInputs();
  const std::string mesh_path = JoinPaths(inputs.dir, "mesh.ply");
  WriteCorner(mesh_path, Eigen::Affine3d::Identity());
  const MeshEvaluationJob good = JobFor(inputs, mesh_path);
  EXPECT_TRUE(good.Check());
  const auto refused = [](const MeshEvaluationJob& job) {
    if (job.Check()) {
      return false;
    }
    try {
      RunMeshEvaluationJob(job);
    } catch (const Error&) {
      return true;
    }
    return false;
  };

  MeshEvaluationJob job = good;
  job.alignment = "foo";
  EXPECT_TRUE(refused(job));
  job = good;
  job.axes_weight = -1.0;
  EXPECT_TRUE(refused(job));
  job = good;
  job.input_path = JoinPaths(inputs.dir, "missing.ply");
  EXPECT_TRUE(refused(job));
  job = good;
  job.reference_path = JoinPaths(inputs.dir, "missing.ply");
  EXPECT_TRUE(refused(job));
  job = good;
  job.alignment = "se3";
  EXPECT_TRUE(job.Check());
  job.alignment_model_path = JoinPaths(inputs.dir, "no_model");
  EXPECT_TRUE(refused(job));
  job.alignment_model_path = "";
  EXPECT_TRUE(refused(job));
  job = good;
  job.alignment = "sim3";
  job.ground_truth_poses_path = JoinPaths(inputs.dir, "no_poses.txt");
  EXPECT_TRUE(refused(job));
  // Not needed without an alignment.
  job.alignment = "none";
  job.alignment_model_path = "";
  EXPECT_TRUE(job.Check());
  job = good;
  job.evaluation_options.thresholds_m = {0.2, 0.05};
  EXPECT_TRUE(refused(job));
  job = good;
  job.icp_options.method = "magic";
  EXPECT_TRUE(refused(job));
}

}  // namespace
}  // namespace colmap_lidar
