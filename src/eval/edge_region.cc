#include "src/eval/edge_region.h"

#include <cmath>

#include "colmap_ext/util/logging.h"
#include "src/eval/mesh_evaluator.h"
#include "src/eval/nearest_neighbor.h"

namespace colmap_lidar {

std::vector<double> DistancesToSegments(
    const std::vector<Eigen::Vector3d>& points,
    const std::vector<Segment3D>& segments) {
  THROW_CHECK(!segments.empty(), "No edge segments to measure distances to");
  // Each segment is the degenerate triangle (start, end, end), which the
  // exact point-to-triangle distance treats as the segment.
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  vertices.reserve(2 * segments.size());
  triangles.reserve(segments.size());
  for (const Segment3D& segment : segments) {
    THROW_CHECK(segment.start.allFinite() && segment.end.allFinite(),
                "Edge segment " << triangles.size()
                                << " has a non-finite coordinate");
    const int first = static_cast<int>(vertices.size());
    vertices.push_back(segment.start);
    vertices.push_back(segment.end);
    triangles.emplace_back(first, first + 1, first + 1);
  }
  const TriangleMeshIndex index(vertices, triangles);
  return index.NearestDistances(points);
}

EdgeRegionEvaluation EvaluateEdgeRegion(const MeshEvaluation& evaluation,
                                        const std::vector<Segment3D>& edges,
                                        double radius_m) {
  THROW_CHECK(radius_m > 0.0 && std::isfinite(radius_m),
              "The edge region radius must be positive, got " << radius_m);
  THROW_CHECK(!edges.empty(), "The edge region needs at least one edge");
  EdgeRegionEvaluation region;
  region.radius_m = radius_m;
  region.num_edges = edges.size();
  region.thresholds_m = evaluation.thresholds_m;

  const std::vector<double> estimate_to_edges =
      DistancesToSegments(evaluation.estimate_points, edges);
  std::vector<double> accuracy;
  for (size_t i = 0; i < evaluation.estimate_points.size(); ++i) {
    if (evaluation.estimate_in_crop[i] && estimate_to_edges[i] <= radius_m) {
      accuracy.push_back(evaluation.estimate_distances[i]);
    }
  }
  const std::vector<double> reference_to_edges =
      DistancesToSegments(evaluation.reference_points, edges);
  std::vector<double> completeness;
  for (size_t i = 0; i < evaluation.reference_points.size(); ++i) {
    if (evaluation.reference_kept[i] && reference_to_edges[i] <= radius_m) {
      completeness.push_back(evaluation.reference_distances[i]);
    }
  }
  region.num_estimate_points = accuracy.size();
  region.num_reference_points = completeness.size();
  if (accuracy.empty() || completeness.empty()) {
    LOG(WARNING) << "Edge region (" << radius_m << " m around " << edges.size()
                 << " edges) holds " << accuracy.size()
                 << " estimate samples and " << completeness.size()
                 << " reference points";
  }
  region.accuracy_m = ComputeErrorStats(accuracy);
  region.completeness_m = ComputeErrorStats(completeness);
  for (const double t : region.thresholds_m) {
    const double precision = ShareBelow(accuracy, t);
    const double recall = ShareBelow(completeness, t);
    region.precisions.push_back(precision);
    region.recalls.push_back(recall);
    region.fscores.push_back(FScore(precision, recall));
  }
  return region;
}

}  // namespace colmap_lidar
