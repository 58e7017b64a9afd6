// The evaluate stage of automatic_reconstructor: everything the report
// compares, computed against the recording's ground truth and written as
// JSON / CSV / PLY into one folder (replaced as a whole):
//   poses_refined_none.json, poses_refined_sim3.json   our refined model;
//   poses_prior_none.json                               the prior poses;
//   poses_colmap_mapper_sim3.json                       stock `colmap
//       mapper` without priors (lidar_mapper's initialisation), when it ran;
//   trajectories.csv      per ground-truth frame: camera centres of the
//                         ground truth, the priors and the refined model
//                         (world frame, no alignment; empty when missing);
//   poses_refined_<mesh_alignment>.json  also for se3_axes / sim3_axes;
//   mesh_ours.json (+ _precision.ply, _recall.ply coloured by distance),
//       after the mesh_alignment of the options (the trajectory fit);
//   mesh_lidar_poisson.{ply,json} (+ coloured PLYs): stock poisson_mesher
//       on the LIDAR cloud registered with the refined poses, the LIDAR-only
//       baseline of the paper's Table II;
//   mesh_ours_icp.json, mesh_lidar_poisson_icp.json (with mesh_icp): the
//       same after an ICP refinement of each mesh's alignment against the
//       reference (as Tanks and Temples; no coloured PLYs);
//   mesh_alignment.json  the applied transforms: "alignment" and
//       "reference_from_estimate" (the fit), and per mesh under "icp" the
//       refined transform with the size of the ICP correction.
//   real_data.json        without poses_gt.txt (see real_data_evaluator.h).
// Pose files need poses_gt.txt, mesh files reference.ply; recall counts the
// reference points near the registered LIDAR cloud (what the sensors saw).
#pragma once

#include <string>

#include "colmap_ext/runner/colmap_runner.h"
#include "src/eval/mesh_evaluator.h"
#include "src/eval/mesh_icp.h"
#include "src/eval/real_data_evaluator.h"

namespace colmap_lidar {

struct PipelineEvaluationInput {
  // Recording with poses_gt.txt and/or reference.ply.
  std::string dataset_path;
  std::string prior_model_path;
  std::string refined_model_path;
  // Stock mapper's model; skipped when it does not exist.
  std::string mapper_model_path;
  // Our mesh; skipped when it does not exist.
  std::string mesh_path;
  // lidar_fused.ply of the dense workspace: the recall crop and the input of
  // the LIDAR-only baseline.
  std::string lidar_cloud_path;
  // database.db: the LIDAR scans of the real-data figures.
  std::string database_path;
  // Output folder.
  std::string output_path;
};

struct PipelineEvaluationOptions {
  MeshEvaluationOptions mesh;
  // Alignment of the meshes to the ground truth before their evaluation:
  // none | se3 | sim3 (the pose evaluation's Umeyama fit of the refined
  // model's camera centres to poses_gt.txt) | se3_axes | sim3_axes (the fit
  // of the centres and the orientations, as Tanks and Temples: the centres
  // alone leave the roll about a straight street free and tilt the mesh);
  // see EvaluateMeshFiles. With
  // priors as noisy as the paper's, the world frame of the reconstruction is
  // only known to a few centimetres to decimetres (the gauge), which would
  // otherwise dominate the errors at 0.1 m and below. "none" without
  // poses_gt.txt or a refined model.
  std::string mesh_alignment = "se3_axes";
  // Also evaluate each mesh after an ICP refinement of its alignment against
  // reference.ply (mesh_*_icp.json).
  bool mesh_icp = true;
  MeshIcpOptions icp;
  // Mesh the LIDAR cloud with stock poisson_mesher and evaluate it too.
  bool lidar_baseline = true;
  // --PoissonMeshing.depth and .trim.
  int poisson_depth = 10;
  double poisson_trim = 7.0;
  // Figures without ground truth (real_data.json: LIDAR map crispness,
  // trajectory vs LIDAR odometry, mesh vs LIDAR), computed when the
  // recording has no poses_gt.txt, or always with real_data_always.
  RealDataEvaluationOptions real_data;
  bool real_data_always = false;
  // <= 0: all cores.
  int num_threads = -1;
  ColmapRunnerOptions colmap;
};

// Returns a one-line summary (the stage's note). Throws naming the file on
// unreadable inputs; the output folder is then unchanged.
std::string EvaluatePipeline(const PipelineEvaluationInput& input,
                             const PipelineEvaluationOptions& options);

}  // namespace colmap_lidar
