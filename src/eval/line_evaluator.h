// Accuracy and completeness of reconstructed 3D line segments against
// ground-truth edges, with the length-based metrics of LIMAP (Liu et al.
// 2023, "3D Line Mapping Revisited", Sec. 5 / supplementary):
//   length precision(t) = share of the estimated segment length lying
//                         within t of some ground-truth edge;
//   length recall(t)    = share of the ground-truth edge length lying
//                         within t of some estimated segment;
//   inlier segments(t)  = estimated segments lying entirely within t of the
//                         ground truth (all their samples), and their share
//                         of the estimated segments.
// Distances are exact point-to-segment distances. Lengths are measured by
// splitting each segment into n = max(1, ceil(length / sample_step_m))
// equal pieces and testing the midpoint of each piece, which carries
// length / n; "within t" means distance < t.
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "src/eval/segment_io.h"

namespace colmap_lidar {

struct LineEvaluationOptions {
  // Distance thresholds t in metres; positive and strictly increasing.
  std::vector<double> thresholds_m = {0.01, 0.02, 0.05, 0.1};
  // Length of the pieces whose midpoints are tested (metres, > 0).
  double sample_step_m = 0.01;

  bool Check() const;
};

// Distances from points to the nearest of a set of segments, exact up to
// `max_distance`: a uniform grid of cells 2 * max_distance wide lists the
// segments passing near each cell, so a query only tests the segments of
// its own cell. Queries farther than max_distance from every segment get
// +infinity.
class SegmentDistanceIndex {
 public:
  SegmentDistanceIndex(const std::vector<Segment3D>& segments,
                       double max_distance);
  double Distance(const Eigen::Vector3d& point) const;

 private:
  struct CellHash {
    size_t operator()(const Eigen::Vector3i& cell) const;
  };
  struct CellEqual {
    bool operator()(const Eigen::Vector3i& a, const Eigen::Vector3i& b) const {
      return a == b;
    }
  };
  Eigen::Vector3i CellOf(const Eigen::Vector3d& point) const;

  std::vector<Segment3D> segments_;
  double max_distance_;
  double cell_size_;
  std::unordered_map<Eigen::Vector3i, std::vector<int>, CellHash, CellEqual>
      cells_;
};

struct LineEvaluation {
  size_t num_estimated_segments = 0;
  size_t num_ground_truth_segments = 0;
  double estimated_length_m = 0.0;
  double ground_truth_length_m = 0.0;
  std::vector<double> thresholds_m;
  std::vector<double> length_precisions;
  std::vector<double> length_recalls;
  std::vector<size_t> num_inlier_segments;
  std::vector<double> inlier_segment_shares;
};

// Throws colmap_lidar::Error on invalid options or no ground-truth
// segments; no estimated segments is a value (all zeros) plus a warning.
LineEvaluation EvaluateLines(const std::vector<Segment3D>& estimate,
                             const std::vector<Segment3D>& ground_truth,
                             const LineEvaluationOptions& options);

std::string FormatLineEvaluation(const LineEvaluation& evaluation);
void WriteLineEvaluationJson(const std::string& path,
                             const LineEvaluation& evaluation);

}  // namespace colmap_lidar
