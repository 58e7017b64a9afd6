// The mesh_evaluator subcommand as a typed function: a mesh (or point cloud)
// evaluated against a reference cloud (mesh_evaluator.h), optionally after
// carrying it into the reference's frame by the trajectory fit of the
// sparse model it was built with to ground-truth poses (pose_evaluator.h),
// and optionally again after an ICP refinement of that fit (mesh_icp.h);
// the JSON reports and coloured PLYs written where asked.
#pragma once

#include <Eigen/Geometry>
#include <ostream>
#include <string>
#include <vector>

#include "src/eval/mesh_evaluator.h"
#include "src/eval/mesh_icp.h"

namespace colmap_lidar {

struct MeshEvaluationJob {
  // Estimated mesh PLY (faces are sampled) or point cloud PLY (no faces:
  // its vertices are used). Required.
  std::string input_path = "";
  // Reference point cloud PLY (same world frame, metres). Required.
  std::string reference_path = "";
  // JSON report to write; empty: none.
  std::string output_path = "";
  // PLY of the estimate points coloured by distance to the reference
  // (precision view); empty: none.
  std::string colored_path = "";
  // PLY of the reference points coloured by distance to the estimate
  // (recall view); empty: none.
  std::string colored_reference_path = "";
  // none | se3 | sim3 | se3_axes | sim3_axes: the fit of the cameras of
  // alignment_model_path to ground_truth_poses_path that carries the
  // estimate (and the observed cloud) into the reference's frame.
  std::string alignment = "none";
  // Sparse model folder the estimate was built with; needed unless
  // alignment is none.
  std::string alignment_model_path = "";
  // Ground-truth poses (poses_gt.txt layout); needed unless alignment is
  // none.
  std::string ground_truth_poses_path = "";
  // *_axes only: weight of the orientations against the centres, >= 0.
  double axes_weight = 1.0;
  // Then refine the alignment by ICP of the mesh against the reference and
  // evaluate again.
  bool icp = false;
  // JSON report after ICP; empty: IcpOutputPath()'s default.
  std::string icp_output_path = "";
  // [MeshEvaluation]: thresholds, sampling, observed cloud, crop, surface.
  MeshEvaluationOptions evaluation_options;
  // [MeshIcp], used with icp.
  MeshIcpOptions icp_options;

  // Logs an error naming the option (as the command line spells it) and
  // returns false on the first invalid option or missing input: the
  // evaluation and ICP options, the alignment, axes_weight, the model
  // folder (unless alignment is none), then the input, reference and
  // ground-truth files.
  bool Check() const;

  // Where the report after ICP goes: icp_output_path, else output_path
  // with _icp before its .json (or _icp.json appended when it does not end
  // in .json), else empty (none).
  std::string IcpOutputPath() const;
};

struct MeshEvaluationJobResult {
  // The applied alignment, x_reference = reference_from_estimate *
  // x_estimate (identity for none).
  Eigen::Affine3d reference_from_estimate = Eigen::Affine3d::Identity();
  // The figures after that alignment.
  MeshEvaluation evaluation;
  // With job.icp: the ICP correction and the figures after it.
  bool has_icp = false;
  MeshIcpResult icp;
  MeshEvaluation icp_evaluation;
  // The files written, in the order written (JSON, coloured PLYs, JSON
  // after ICP).
  std::vector<std::string> written_paths;
};

// Runs `job` (which must pass Check(), else throws colmap_lidar::Error).
// With `out`, writes there what mesh_evaluator prints, each part as soon as
// it is computed: FormatMeshEvaluation of the figures, and with ICP
// "After ICP: " + FormatMeshIcpResult + a newline + the figures after it.
// Throws colmap_lidar::Error naming the file on unreadable inputs, and when
// the alignment or the ICP fails (e.g. fewer than 3 matched cameras, no
// mesh part near the reference); files written before stay.
MeshEvaluationJobResult RunMeshEvaluationJob(const MeshEvaluationJob& job,
                                             std::ostream* out = nullptr);

}  // namespace colmap_lidar
