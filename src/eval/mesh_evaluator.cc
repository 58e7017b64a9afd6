#include "src/eval/mesh_evaluator.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "src/eval/distance_colormap.h"
#include "src/eval/mesh_sampling.h"
#include "src/eval/nearest_neighbor.h"
#include "src/eval/reference_visibility.h"
#include "src/eval/segment_io.h"

namespace colmap_lidar {
namespace {

void CheckFinite(const std::vector<Eigen::Vector3d>& points,
                 const std::string& what) {
  for (size_t i = 0; i < points.size(); ++i) {
    THROW_CHECK(points[i].allFinite(),
                what << ": point " << i << " has a non-finite coordinate");
  }
}

std::vector<Eigen::Vector3d> ReadPlyPositions(const std::string& path,
                                              const std::string& what) {
  return ReadEvaluationMesh(path, what).vertices;
}

}  // namespace

bool MeshEvaluationOptions::Check() const {
  bool ok = CheckThresholds(thresholds_m, "MeshEvaluation.thresholds_m");
  if (!(sample_density_per_m2 > 0.0) || !std::isfinite(sample_density_per_m2)) {
    LOG(ERROR) << "MeshEvaluation.sample_density_per_m2 must be positive, got "
               << sample_density_per_m2;
    ok = false;
  }
  if (!(observed_radius_m > 0.0) || !std::isfinite(observed_radius_m)) {
    LOG(ERROR) << "MeshEvaluation.observed_radius_m must be positive, got "
               << observed_radius_m;
    ok = false;
  }
  if (!std::isfinite(crop_margin_m)) {
    LOG(ERROR) << "MeshEvaluation.crop_margin_m must be finite";
    ok = false;
  }
  if (!(color_threshold_m >= 0.0) || !std::isfinite(color_threshold_m)) {
    LOG(ERROR) << "MeshEvaluation.color_threshold_m must be >= 0 (0: auto), "
                  "got "
               << color_threshold_m;
    ok = false;
  }
  if (!(edge_region_radius_m > 0.0) || !std::isfinite(edge_region_radius_m)) {
    LOG(ERROR) << "MeshEvaluation.edge_region_radius_m must be positive, got "
               << edge_region_radius_m;
    ok = false;
  }
  if (seed < 0) {
    LOG(ERROR) << "MeshEvaluation.seed must be >= 0, got " << seed;
    ok = false;
  }
  return ok;
}

double MeshEvaluationOptions::ColorThreshold() const {
  if (color_threshold_m > 0.0) {
    return color_threshold_m;
  }
  double threshold = thresholds_m.empty() ? 0.1 : thresholds_m.front();
  for (const double t : thresholds_m) {
    if (t <= 0.1) {
      threshold = t;
    }
  }
  return threshold;
}

MeshEvaluation EvaluateMesh(
    const std::vector<Eigen::Vector3d>& estimate_vertices,
    const std::vector<Eigen::Vector3i>& triangles,
    const std::vector<Eigen::Vector3d>& reference,
    const std::vector<Eigen::Vector3d>& observed,
    const MeshEvaluationOptions& options, const ReferenceSurface* surface,
    const std::vector<bool>* reference_visible) {
  THROW_CHECK(options.Check(), "Invalid MeshEvaluation options");
  THROW_CHECK(!estimate_vertices.empty(), "The estimate has no vertices");
  THROW_CHECK(!reference.empty(), "The reference cloud has no points");
  CheckFinite(estimate_vertices, "Estimate");
  CheckFinite(reference, "Reference cloud");
  CheckFinite(observed, "Observed cloud");

  MeshEvaluation evaluation;
  evaluation.thresholds_m = options.thresholds_m;
  evaluation.color_threshold_m = options.ColorThreshold();
  evaluation.estimate_is_mesh = !triangles.empty();
  evaluation.num_estimate_vertices = estimate_vertices.size();
  evaluation.num_estimate_triangles = triangles.size();
  if (evaluation.estimate_is_mesh) {
    evaluation.estimate_area_m2 =
        TriangleMeshArea(estimate_vertices, triangles);
    evaluation.estimate_points =
        SampleTriangleMesh(estimate_vertices, triangles,
                           options.sample_density_per_m2,
                           static_cast<uint64_t>(options.seed));
    THROW_CHECK(!evaluation.estimate_points.empty(),
                "The estimate mesh has zero surface area ("
                    << triangles.size() << " degenerate triangles)");
  } else {
    evaluation.estimate_points = estimate_vertices;
  }

  // Reference points kept for recall: those near the observed cloud (and
  // visible, when given).
  evaluation.reference_points = reference;
  evaluation.reference_kept.assign(reference.size(), true);
  if (reference_visible != nullptr) {
    THROW_CHECK(reference_visible->size() == reference.size(),
                "Reference visibility has " << reference_visible->size()
                                            << " flags for " << reference.size()
                                            << " points");
    evaluation.reference_kept = *reference_visible;
  }
  if (!observed.empty()) {
    const PointCloudIndex observed_index(observed);
    const std::vector<double> to_observed =
        observed_index.NearestDistances(reference);
    for (size_t i = 0; i < reference.size(); ++i) {
      evaluation.reference_kept[i] =
          evaluation.reference_kept[i] &&
          to_observed[i] <= options.observed_radius_m;
    }
  }
  std::vector<Eigen::Vector3d> kept_reference;
  for (size_t i = 0; i < reference.size(); ++i) {
    if (evaluation.reference_kept[i]) {
      kept_reference.push_back(reference[i]);
    }
  }
  evaluation.num_reference_points_kept = kept_reference.size();
  if (kept_reference.empty()) {
    LOG(WARNING) << "No reference point lies within "
                 << options.observed_radius_m
                 << " m of the observed cloud; recall is 0";
  }

  // Precision crop box around the kept reference.
  evaluation.estimate_in_crop.assign(evaluation.estimate_points.size(), true);
  if (!kept_reference.empty()) {
    evaluation.crop_min = kept_reference.front();
    evaluation.crop_max = kept_reference.front();
    for (const Eigen::Vector3d& point : kept_reference) {
      evaluation.crop_min = evaluation.crop_min.cwiseMin(point);
      evaluation.crop_max = evaluation.crop_max.cwiseMax(point);
    }
    evaluation.crop_min.array() -= options.crop_margin_m;
    evaluation.crop_max.array() += options.crop_margin_m;
    if (options.crop_margin_m >= 0.0) {
      for (size_t i = 0; i < evaluation.estimate_points.size(); ++i) {
        const Eigen::Vector3d& point = evaluation.estimate_points[i];
        evaluation.estimate_in_crop[i] =
            (point.array() >= evaluation.crop_min.array()).all() &&
            (point.array() <= evaluation.crop_max.array()).all();
      }
    }
  }

  // Precision side: estimate points -> the true surface when given, else
  // the full reference cloud.
  if (surface != nullptr && !surface->triangles.empty()) {
    CheckFinite(surface->vertices, "Reference surface");
    const TriangleMeshIndex surface_index(surface->vertices,
                                          surface->triangles);
    evaluation.estimate_distances =
        surface_index.NearestDistances(evaluation.estimate_points);
    evaluation.precision_to_surface = true;
  } else {
    const PointCloudIndex reference_index(reference);
    evaluation.estimate_distances =
        reference_index.NearestDistances(evaluation.estimate_points);
  }
  std::vector<double> accuracy;
  for (size_t i = 0; i < evaluation.estimate_points.size(); ++i) {
    if (evaluation.estimate_in_crop[i]) {
      accuracy.push_back(evaluation.estimate_distances[i]);
    }
  }
  evaluation.num_estimate_points_in_crop = accuracy.size();
  if (accuracy.empty()) {
    LOG(WARNING) << "No estimate point lies in the crop box of the "
                    "reference; precision is 0";
  }

  // Recall side: reference points -> estimate.
  if (evaluation.estimate_is_mesh && options.recall_to_mesh) {
    const TriangleMeshIndex mesh_index(estimate_vertices, triangles);
    evaluation.reference_distances = mesh_index.NearestDistances(reference);
  } else {
    const PointCloudIndex estimate_index(evaluation.estimate_points);
    evaluation.reference_distances =
        estimate_index.NearestDistances(reference);
  }
  std::vector<double> completeness;
  for (size_t i = 0; i < reference.size(); ++i) {
    if (evaluation.reference_kept[i]) {
      completeness.push_back(evaluation.reference_distances[i]);
    }
  }

  evaluation.accuracy_m = ComputeErrorStats(accuracy);
  evaluation.completeness_m = ComputeErrorStats(completeness);
  for (const double t : options.thresholds_m) {
    const double precision = ShareBelow(accuracy, t);
    const double recall = ShareBelow(completeness, t);
    evaluation.precisions.push_back(precision);
    evaluation.recalls.push_back(recall);
    evaluation.fscores.push_back(FScore(precision, recall));
  }
  LOG(INFO) << "Mesh evaluation: " << accuracy.size()
            << " estimate points in the crop, " << completeness.size()
            << " reference points kept, accuracy (mean) "
            << evaluation.accuracy_m.mean << " m, completeness (mean) "
            << evaluation.completeness_m.mean << " m";
  return evaluation;
}

MeshEvaluation EvaluateMeshFiles(
    const std::string& estimate_path, const std::string& reference_path,
    const MeshEvaluationOptions& options,
    const Eigen::Affine3d& reference_from_estimate) {
  THROW_CHECK(options.Check(), "Invalid MeshEvaluation options");
  CheckFileExists(estimate_path, "Estimate mesh or point cloud");
  EvaluationMesh estimate = ReadEvaluationMesh(estimate_path, "Estimate");
  std::vector<Eigen::Vector3d>& vertices = estimate.vertices;
  const std::vector<Eigen::Vector3i>& triangles = estimate.triangles;
  for (Eigen::Vector3d& vertex : vertices) {
    vertex = reference_from_estimate * vertex;
  }
  if (estimate.has_faces && triangles.empty()) {
    LOG(WARNING) << estimate_path
                 << " has faces but none with 3 or more vertices; using its "
                    "vertices as a point cloud";
  }
  const std::vector<Eigen::Vector3d> reference =
      ReadPlyPositions(reference_path, "Reference cloud");
  std::vector<Eigen::Vector3d> observed;
  if (!options.observed_cloud_path.empty()) {
    observed = ReadPlyPositions(options.observed_cloud_path,
                                "MeshEvaluation.observed_cloud_path");
    if (!options.observed_cloud_in_reference_frame) {
      for (Eigen::Vector3d& point : observed) {
        point = reference_from_estimate * point;
      }
    }
  }
  ReferenceSurface surface;
  if (!options.reference_surface_path.empty()) {
    const std::string& surface_path = options.reference_surface_path;
    CheckFileExists(surface_path, "MeshEvaluation.reference_surface_path");
    const PlyData surface_data = ReadPly(surface_path);
    surface.vertices = surface_data.Positions(surface_path);
    surface.triangles = TriangulatePolygons(
        surface_data.faces, surface.vertices.size(), surface_path);
    THROW_CHECK(!surface.triangles.empty(),
                "MeshEvaluation.reference_surface_path "
                    << surface_path << " has no triangles");
  }
  LOG(INFO) << "Evaluating " << estimate_path << " (" << vertices.size()
            << " vertices, " << triangles.size() << " triangles) against "
            << reference_path << " (" << reference.size() << " points)"
            << (surface.triangles.empty()
                    ? std::string()
                    : ", precision against the surface " +
                          options.reference_surface_path + " (" +
                          std::to_string(surface.triangles.size()) +
                          " triangles)");
  std::vector<Segment3D> edges;
  if (!options.edge_region_path.empty()) {
    CheckFileExists(options.edge_region_path,
                    "MeshEvaluation.edge_region_path");
    edges = ReadSegments(options.edge_region_path);
    THROW_CHECK(!edges.empty(), "MeshEvaluation.edge_region_path "
                                    << options.edge_region_path
                                    << " holds no segments");
  }
  std::vector<bool> visible;
  if (!options.visible_model_path.empty()) {
    CheckDirExists(options.visible_model_path,
                   "MeshEvaluation.visible_model_path");
    visible = VisibleFromCameras(reference,
                                 ReadReconstruction(options.visible_model_path),
                                 ReferenceVisibilityOptions());
  }
  MeshEvaluation evaluation =
      EvaluateMesh(vertices, triangles, reference, observed, options, &surface,
                   options.visible_model_path.empty() ? nullptr : &visible);
  if (!edges.empty()) {
    evaluation.edge_region =
        EvaluateEdgeRegion(evaluation, edges, options.edge_region_radius_m);
    evaluation.has_edge_region = true;
  }
  return evaluation;
}

std::string FormatMeshEvaluation(const MeshEvaluation& evaluation) {
  std::ostringstream out;
  char line[256];
  if (evaluation.estimate_is_mesh) {
    std::snprintf(line, sizeof(line),
                  "Mesh evaluation: %zu triangles, %.6g m2, %zu samples "
                  "(%zu in the crop box)\n",
                  evaluation.num_estimate_triangles,
                  evaluation.estimate_area_m2,
                  evaluation.estimate_points.size(),
                  evaluation.num_estimate_points_in_crop);
  } else {
    std::snprintf(line, sizeof(line),
                  "Point cloud evaluation: %zu points (%zu in the crop "
                  "box)\n",
                  evaluation.estimate_points.size(),
                  evaluation.num_estimate_points_in_crop);
  }
  out << line;
  std::snprintf(
      line, sizeof(line), "  reference: %zu points, %zu kept for recall\n",
      evaluation.reference_points.size(), evaluation.num_reference_points_kept);
  out << line;
  std::snprintf(line, sizeof(line), "  %-16s %12s %12s %12s %12s\n",
                "distance [m]", "mean", "median", "rmse", "max");
  out << line;
  const ErrorStats& a = evaluation.accuracy_m;
  const ErrorStats& c = evaluation.completeness_m;
  std::snprintf(line, sizeof(line), "  %-16s %12.6f %12.6f %12.6f %12.6f\n",
                "accuracy", a.mean, a.median, a.rmse, a.max);
  out << line;
  std::snprintf(line, sizeof(line), "  %-16s %12.6f %12.6f %12.6f %12.6f\n",
                "completeness", c.mean, c.median, c.rmse, c.max);
  out << line;
  std::snprintf(line, sizeof(line), "  %14s %10s %10s %10s\n",
                "threshold [m]", "precision", "recall", "F-score");
  out << line;
  for (size_t k = 0; k < evaluation.thresholds_m.size(); ++k) {
    std::snprintf(line, sizeof(line), "  %14g %10.4f %10.4f %10.4f\n",
                  evaluation.thresholds_m[k], evaluation.precisions[k],
                  evaluation.recalls[k], evaluation.fscores[k]);
    out << line;
  }
  if (evaluation.has_edge_region) {
    const EdgeRegionEvaluation& region = evaluation.edge_region;
    std::snprintf(line, sizeof(line),
                  "  edge region (%g m around %zu creases): %zu samples, "
                  "%zu reference points\n",
                  region.radius_m, region.num_edges,
                  region.num_estimate_points, region.num_reference_points);
    out << line;
    for (size_t k = 0; k < region.thresholds_m.size(); ++k) {
      std::snprintf(line, sizeof(line), "  %14g %10.4f %10.4f %10.4f\n",
                    region.thresholds_m[k], region.precisions[k],
                    region.recalls[k], region.fscores[k]);
      out << line;
    }
  }
  return out.str();
}

namespace {

Json StatsToJson(const ErrorStats& stats) {
  Json json;
  json["count"] = stats.count;
  json["mean"] = stats.mean;
  json["median"] = stats.median;
  json["rmse"] = stats.rmse;
  json["max"] = stats.max;
  return json;
}

}  // namespace

void WriteMeshEvaluationJson(const std::string& path,
                             const MeshEvaluation& evaluation) {
  Json json;
  json["evaluator"] = "mesh";
  json["estimate_is_mesh"] = evaluation.estimate_is_mesh;
  json["precision_to_surface"] = evaluation.precision_to_surface;
  json["estimate_area_m2"] = evaluation.estimate_area_m2;
  json["num_estimate_vertices"] = evaluation.num_estimate_vertices;
  json["num_estimate_triangles"] = evaluation.num_estimate_triangles;
  json["num_estimate_points"] = evaluation.estimate_points.size();
  json["num_estimate_points_in_crop"] = evaluation.num_estimate_points_in_crop;
  json["num_reference_points"] = evaluation.reference_points.size();
  json["num_reference_points_kept"] = evaluation.num_reference_points_kept;
  json["crop_min"] = VectorToJson(evaluation.crop_min);
  json["crop_max"] = VectorToJson(evaluation.crop_max);
  json["accuracy_m"] = StatsToJson(evaluation.accuracy_m);
  json["completeness_m"] = StatsToJson(evaluation.completeness_m);
  json["thresholds_m"] = evaluation.thresholds_m;
  json["precision"] = evaluation.precisions;
  json["recall"] = evaluation.recalls;
  json["fscore"] = evaluation.fscores;
  json["color_threshold_m"] = evaluation.color_threshold_m;
  if (evaluation.has_edge_region) {
    const EdgeRegionEvaluation& region = evaluation.edge_region;
    Json edge_json;
    edge_json["radius_m"] = region.radius_m;
    edge_json["num_edges"] = region.num_edges;
    edge_json["num_estimate_points"] = region.num_estimate_points;
    edge_json["num_reference_points"] = region.num_reference_points;
    edge_json["accuracy_m"] = StatsToJson(region.accuracy_m);
    edge_json["completeness_m"] = StatsToJson(region.completeness_m);
    edge_json["precision"] = region.precisions;
    edge_json["recall"] = region.recalls;
    edge_json["fscore"] = region.fscores;
    json["edge_region"] = edge_json;
  }
  WriteJsonFile(path, json);
}

void WritePrecisionColoredPly(const std::string& path,
                              const MeshEvaluation& evaluation) {
  WriteDistanceColoredPly(path, evaluation.estimate_points,
                          evaluation.estimate_distances,
                          evaluation.estimate_in_crop,
                          evaluation.color_threshold_m);
}

void WriteRecallColoredPly(const std::string& path,
                           const MeshEvaluation& evaluation) {
  WriteDistanceColoredPly(path, evaluation.reference_points,
                          evaluation.reference_distances,
                          evaluation.reference_kept,
                          evaluation.color_threshold_m);
}

}  // namespace colmap_lidar
