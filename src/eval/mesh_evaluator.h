// Surface accuracy and completeness of a reconstructed mesh (or point
// cloud) against a reference point cloud, as in Knapitsch et al. 2017
// ("Tanks and Temples", Sec. 4) and Li et al. 2023 (Neuralangelo):
//   precision(t) = share of estimate points whose distance to the nearest
//                  reference point is < t;
//   recall(t)    = share of (kept) reference points whose distance to the
//                  estimate is < t;
//   F(t)         = 2 P R / (P + R).
// Estimate points are uniform area-weighted samples of the mesh triangles
// (sample_density_per_m2, seeded) or, for a PLY without faces, its
// vertices. "Distance to the estimate" is the exact point-to-triangle
// distance to the mesh surface (CloudCompare's cloud-to-mesh distance, the
// dense-sampling limit of Tanks and Temples) when the estimate has faces and
// recall_to_mesh is set, else the distance to the nearest estimate point.
//
// Reference selection (recall): with observed_cloud_path, reference points
// farther than observed_radius_m from every observed point (e.g. the
// registered LIDAR + camera points) are dropped, since no method can
// recover what no sensor saw. With visible_model_path (a model of the
// cameras in the reference's frame, e.g. the true poses), reference points
// that no camera could see (outside every image, or hidden by the
// reference's own surface: reference_visibility.h) are dropped as well: the
// paper's "whole reference, occluded parts removed".
// Estimate selection (precision): estimate points outside the axis-aligned
// bounding box of the kept reference points enlarged by crop_margin_m on
// every side are ignored (surfaces beyond the surveyed area cannot be
// judged); crop_margin_m < 0 disables the crop. Precision distances are
// taken to the full reference, kept or not: correct geometry is correct
// even where the sensors did not look.
// Reference surface (precision): a surveyed cloud is sparse where the survey
// grazes (the square's ground 25-60 m from the stations holds 4-20 points per
// m2), so an estimate lying exactly on the true surface there is 0.15-0.45 m
// from the nearest reference point and would count as wrong. When the true
// surface is known (a synthetic scene's ground_truth/scene.ply),
// reference_surface_path makes the precision distances exact distances to
// that surface; recall still counts the reference points.
// Edge region: with edge_region_path (the scene's crease edges, e.g. a
// synthetic scene's ground_truth/crease_edges.txt, in the reference's
// frame), the same figures are also given for the points within
// edge_region_radius_m of a crease (src/eval/edge_region.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "src/eval/edge_region.h"
#include "src/eval/eval_stats.h"

namespace colmap_lidar {

struct MeshEvaluationOptions {
  // Distance thresholds t in metres; positive and strictly increasing.
  std::vector<double> thresholds_m = {0.02, 0.05, 0.1, 0.2, 0.5};
  // Samples per square metre of mesh surface for precision (> 0).
  double sample_density_per_m2 = 1000.0;
  // Recall distances to the mesh surface itself (exact) instead of to the
  // samples; ignored for a point-cloud estimate.
  bool recall_to_mesh = true;
  // Optional PLY of what the sensors observed; empty: keep all reference
  // points.
  std::string observed_cloud_path = "";
  // Reference points farther than this from the observed cloud are dropped
  // (metres, > 0).
  double observed_radius_m = 0.2;
  // The observed cloud is in the reference's frame already (e.g. the scans
  // fused with the true poses, so that reconstructions in different frames,
  // a baseline's and ours, are judged on the same region); else it is in the
  // estimate's frame and carried with it (EvaluateMeshFiles).
  bool observed_cloud_in_reference_frame = false;
  // Optional COLMAP model (cameras and poses in the reference's frame):
  // only the reference points its images could see count for recall.
  // Empty: no visibility test.
  std::string visible_model_path = "";
  // Margin of the precision crop box around the kept reference (metres);
  // negative disables the crop.
  double crop_margin_m = 0.5;
  // Optional mesh PLY of the true surface, in the reference's frame; when
  // set, precision distances are to this surface instead of to the nearest
  // reference point (see above). Empty: the reference points.
  std::string reference_surface_path = "";
  // Optional file of crease edges (any format of ReadSegments, e.g.
  // ground_truth/crease_edges.txt), in the reference's frame; when set the
  // figures are also reported for the region near them. Empty: none.
  std::string edge_region_path = "";
  // Radius of that region around each edge (metres, > 0).
  double edge_region_radius_m = 0.2;
  // Distance shown red in the coloured PLYs (metres); 0 picks the largest
  // threshold <= 0.1 m, or the smallest threshold when all exceed 0.1 m.
  double color_threshold_m = 0.0;
  // Seed of the mesh sampling.
  int seed = 0;

  bool Check() const;
  // color_threshold_m resolved as documented above.
  double ColorThreshold() const;
};

struct MeshEvaluation {
  bool estimate_is_mesh = false;
  // Precision distances measured to the reference surface (mesh) rather
  // than to the reference points.
  bool precision_to_surface = false;
  double estimate_area_m2 = 0.0;
  size_t num_estimate_vertices = 0;
  size_t num_estimate_triangles = 0;
  // Estimate points (mesh samples or cloud points) and their distance to
  // the nearest reference point; in_crop marks the ones counted.
  std::vector<Eigen::Vector3d> estimate_points;
  std::vector<double> estimate_distances;
  std::vector<bool> estimate_in_crop;
  size_t num_estimate_points_in_crop = 0;

  // Reference points and their distance to the estimate; kept marks the
  // ones counted for recall (observed).
  std::vector<Eigen::Vector3d> reference_points;
  std::vector<double> reference_distances;
  std::vector<bool> reference_kept;
  size_t num_reference_points_kept = 0;
  Eigen::Vector3d crop_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d crop_max = Eigen::Vector3d::Zero();

  std::vector<double> thresholds_m;
  std::vector<double> precisions;
  std::vector<double> recalls;
  std::vector<double> fscores;
  // Accuracy: estimate -> reference distances (in crop). Completeness:
  // reference (kept) -> estimate distances.
  ErrorStats accuracy_m;
  ErrorStats completeness_m;
  double color_threshold_m = 0.1;
  // Figures near the crease edges (options.edge_region_path).
  bool has_edge_region = false;
  EdgeRegionEvaluation edge_region;
};

// The true surface for the precision side (reference frame).
struct ReferenceSurface {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
};

// Evaluates in-memory data. `triangles` empty means a point-cloud estimate
// given by `estimate_vertices`. With `surface` (non-null, with triangles)
// the precision distances are to it (options.reference_surface_path is not
// read here). With `reference_visible` (one flag per reference point; see
// VisibleFromCameras) only the visible points count for recall
// (options.visible_model_path is not read here). Throws colmap_lidar::Error on
// invalid options, an empty estimate or reference, or non-finite coordinates.
MeshEvaluation EvaluateMesh(
    const std::vector<Eigen::Vector3d>& estimate_vertices,
    const std::vector<Eigen::Vector3i>& triangles,
    const std::vector<Eigen::Vector3d>& reference,
    const std::vector<Eigen::Vector3d>& observed,
    const MeshEvaluationOptions& options,
    const ReferenceSurface* surface = nullptr,
    const std::vector<bool>* reference_visible = nullptr);

// Reads the PLYs (estimate mesh or cloud, reference cloud and, if set,
// options.observed_cloud_path and options.reference_surface_path) and
// evaluates; with options.edge_region_path, reads the edges and adds the
// edge region's figures. Errors name the file.
// `reference_from_estimate` maps the estimate and the observed cloud (both
// in the reconstruction's world frame, unless
// options.observed_cloud_in_reference_frame) into the reference's frame before
// the comparison: a reconstruction from noisy priors has a gauge (a rigid
// transform, or a similarity without LIDAR) that no sensor observes, so the
// shape is judged after the trajectory alignment of the pose evaluation, as
// Tanks and Temples does.
MeshEvaluation EvaluateMeshFiles(
    const std::string& estimate_path, const std::string& reference_path,
    const MeshEvaluationOptions& options,
    const Eigen::Affine3d& reference_from_estimate = Eigen::Affine3d::Identity());

std::string FormatMeshEvaluation(const MeshEvaluation& evaluation);
void WriteMeshEvaluationJson(const std::string& path,
                             const MeshEvaluation& evaluation);
// Estimate points coloured by their distance to the reference (precision
// view; points outside the crop grey).
void WritePrecisionColoredPly(const std::string& path,
                              const MeshEvaluation& evaluation);
// Reference points coloured by their distance to the estimate (recall
// view; unobserved points grey).
void WriteRecallColoredPly(const std::string& path,
                           const MeshEvaluation& evaluation);

}  // namespace colmap_lidar
