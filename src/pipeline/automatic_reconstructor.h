// `colmap-lidar automatic_reconstructor`: from a camera + LIDAR recording (or
// an existing COLMAP workspace) to refined poses, 3D lines, a mesh, its
// evaluation and a report, in the manner of COLMAP's automatic_reconstructor
// but as resumable stages (pipeline_stages.h):
//
//   synthesize   the built-in default scene into <workspace>/dataset, when
//                no dataset_path is given and that folder has no recording;
//   import       lidar_importer (src/dataset/importer.h) into <workspace>;
//   odometry     LIDAR odometry priors (src/lidar/lidar_prior_poses.h) when
//                fewer than 3 images have prior poses (e.g. KITTI raw);
//   sfm          lidar_mapper (src/sfm/lidar_mapper.h): stock SIFT and
//                matching, lines, association, point + line adjustment ->
//                sparse/refined (+ lines3D, lines3D.ply);
//   dense        stock image_undistorter of sparse/refined into dense/, and
//                the LIDAR scans fused on the refined poses
//                (dense/lidar_fused.ply, lidar_fuser);
//   patch_match  LIDAR-initialised PatchMatch (src/mvs);
//   fusion       stock stereo_fusion -> dense/fused.ply (+ .vis);
//   mesh         Delaunay meshing of visual points, LIDAR voxels and line
//                samples (src/mesh) -> dense/meshed-delaunay.ply;
//   evaluate     when the recording has poses_gt.txt / reference.ply: pose
//                errors of the refined model, of the priors and of stock
//                COLMAP's mapper, mesh precision / recall / F-score of ours
//                and of the LIDAR-only Poisson baseline -> eval/;
//   report       report/index.html (self-contained) + PNGs (report.h).
//
// Each stage logs one line when it starts and one with its wall time, CPU
// time and peak memory when it ends, and leaves a mark
// <workspace>/pipeline/<stage>.done (stage_record.h); a re-run skips marked
// stages unless `overwrite` is set, and re-running a stage removes the marks
// of the later ones. Stage outputs are written under temporary names and
// renamed, so an interruption never leaves a stage half-done and marked.
// Stock colmap's output goes to <workspace>/pipeline/colmap.log.
#pragma once

#include <string>
#include <vector>

#include "src/dataset/importer.h"
#include "src/eval/mesh_evaluator.h"
#include "src/lidar/lidar_fusion.h"
#include "src/lidar/lidar_odometry.h"
#include "src/lidar/lidar_prior_poses.h"
#include "src/mesh/delaunay_mesher.h"
#include "src/mvs/patch_match_options.h"
#include "src/pipeline/pipeline_stages.h"
#include "src/pipeline/stage_record.h"
#include "src/sfm/lidar_mapper.h"
#include "src/synth/synthesis_options.h"

namespace colmap_lidar {

// The pipeline's PatchMatch: the module's defaults with 2 photometric and 1
// geometric iterations instead of 5 and 2. Initialised from the LIDAR, the
// maps are within 5 cm of the truth on 97.6 % of the pixels before any
// iteration and 97.9 % after 2 (docs/benchmarks/patch_match.md); the
// remaining iterations serve the random initialisation.
LidarPatchMatchOptions PipelinePatchMatchOptions();

struct AutomaticReconstructorOptions {
  // Recording to import (rig format or KITTI raw); empty: the default
  // synthetic scene in <workspace>/dataset (generated when missing).
  std::string dataset_path = "";
  // Stages to run: "all", one stage name, or "first:last".
  std::string stages = "all";
  // Re-run stages that are marked done.
  bool overwrite = false;
  // Threads of every stage (ours and stock colmap's); <= 0: all cores.
  int num_threads = -1;
  // Stock colmap binary; empty: $COLMAP_BINARY or `colmap` on PATH.
  std::string colmap_binary = "";
  // Python 3 interpreter (with numpy and matplotlib) of the report; see
  // ReportOptions::python_binary.
  std::string python_binary = "/usr/bin/python3";

  // Dense stages: every n-th image of the refined model is a PatchMatch
  // reference and is fused (all images stay source views); 1 uses all.
  int dense_image_step = 1;
  // image_undistorter's --max_image_size; -1 keeps the full size.
  int dense_max_image_size = -1;
  // stereo_fusion's --StereoFusion.min_num_pixels (colmap's default 5).
  int fusion_min_num_pixels = 5;
  // stereo_fusion's --StereoFusion.num_threads; <= 0: num_threads. With
  // more than one thread stock stereo_fusion's output depends on the
  // threads' timing (about 1 % of the points differ between two runs on the
  // same depth maps), and so does the mesh; with one it is reproducible, for
  // 1.2x the fusion time (seconds; a small part of the pipeline).
  int fusion_num_threads = 1;
  // stereo_fusion's input: "geometric" (after the consistency pass, needs
  // patch_match.geom_consistency) or "photometric".
  std::string fusion_input_type = "geometric";
  // Sample the refined 3D line segments into the Delaunay triangulation.
  bool mesh_with_lines = true;

  // Evaluation: alignment of the meshes to the ground truth (none | se3 |
  // sim3 | se3_axes | sim3_axes, from the refined trajectory; see
  // PipelineEvaluationOptions).
  std::string mesh_alignment = "se3_axes";
  // Evaluation: also evaluate the meshes after an ICP refinement of that
  // alignment against reference.ply (mesh_*_icp.json).
  bool mesh_icp = true;
  // Evaluation: also mesh the registered LIDAR cloud with stock
  // poisson_mesher (the LIDAR-only baseline of the paper's Table II).
  bool evaluate_lidar_baseline = true;
  // poisson_mesher --PoissonMeshing.depth and .trim of that baseline.
  int lidar_baseline_poisson_depth = 10;
  double lidar_baseline_poisson_trim = 7.0;

  // Options of the stages (their own defaults; automatic_reconstructor sets
  // the thread counts and colmap binary from the fields above).
  SynthesisOptions synthesis;
  ImporterOptions import;
  LidarOdometryOptions odometry;
  LidarPriorPosesOptions odometry_priors;
  LidarMapperOptions mapper;
  LidarFusionOptions lidar_fusion;
  LidarPatchMatchOptions patch_match = PipelinePatchMatchOptions();
  DelaunayMeshingOptions meshing;
  MeshingInputOptions meshing_input;
  MeshEvaluationOptions mesh_evaluation;

  bool Check() const;
};

struct AutomaticReconstructorSummary {
  // One record per selected stage that ran or was skipped as done before;
  // stages that did not apply (e.g. odometry with priors) are absent.
  std::vector<StageRecord> ran;
  std::vector<StageRecord> skipped;
  std::vector<std::string> not_applicable;
  std::string mesh_path;
  std::string report_path;
};

// The folder layout of a pipeline workspace.
struct PipelinePaths {
  explicit PipelinePaths(const std::string& workspace_path);

  std::string workspace;
  std::string database;
  std::string images;
  std::string prior_model;
  std::string refined_model;
  std::string mapper_model;  // Stock mapper's model (lidar_mapper init).
  std::string dense;
  std::string fused;
  std::string mesh;
  std::string eval;
  std::string report;
  std::string pipeline;  // Stage marks, stages.json, colmap.log.
  std::string default_dataset;

  std::string StageMark(PipelineStage stage) const;
};

// Runs the selected stages. Throws colmap_lidar::Error naming the stage and
// the file or option at fault; stages that finished keep their marks.
AutomaticReconstructorSummary RunAutomaticReconstructor(
    const std::string& workspace_path,
    const AutomaticReconstructorOptions& options);

}  // namespace colmap_lidar
