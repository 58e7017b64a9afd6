// Mesh accuracy and completeness near the scene's creases.
//
// The paper's claim for its line samples (Amblard et al., Sec. IV-D and
// V-C: the surface is "more precise where lines were found") is about the
// places where two surfaces meet. Whole-scene figures dilute them: creases
// are a small share of the area. This evaluator restricts the mesh
// evaluator's figures to
//   precision: estimate samples counted by the mesh evaluation (in its crop
//              box) that lie within radius_m of a ground-truth crease edge;
//   recall:    reference points counted for recall (observed) that lie
//              within radius_m of a crease edge,
// with the same distances (to the reference surface or cloud, and to the
// estimate) and the same thresholds, so the figures compare directly with
// the whole-scene ones and between meshes of the same scene.
// Distances to the edges are exact point-to-segment distances.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "src/eval/eval_stats.h"
#include "src/eval/segment_io.h"

namespace colmap_lidar {

struct MeshEvaluation;

struct EdgeRegionEvaluation {
  // Radius of the region around each crease edge (metres).
  double radius_m = 0.2;
  size_t num_edges = 0;
  // Estimate samples in the crop box and in the region.
  size_t num_estimate_points = 0;
  // Kept (observed) reference points in the region.
  size_t num_reference_points = 0;
  std::vector<double> thresholds_m;
  std::vector<double> precisions;
  std::vector<double> recalls;
  std::vector<double> fscores;
  ErrorStats accuracy_m;
  ErrorStats completeness_m;
};

// Exact distance of each point to the nearest segment. Throws
// colmap_lidar::Error when `segments` is empty.
std::vector<double> DistancesToSegments(
    const std::vector<Eigen::Vector3d>& points,
    const std::vector<Segment3D>& segments);

// The figures of `evaluation` restricted to the region within radius_m
// (> 0) of `edges` (in the reference's frame, as the evaluation's points).
// An empty region gives zero shares and a warning. Throws
// colmap_lidar::Error when `edges` is empty or radius_m is not positive.
EdgeRegionEvaluation EvaluateEdgeRegion(const MeshEvaluation& evaluation,
                                        const std::vector<Segment3D>& edges,
                                        double radius_m);

}  // namespace colmap_lidar
