#include "src/eval/line_evaluator.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "src/eval/eval_stats.h"
#include "src/eval/nearest_neighbor.h"

namespace colmap_lidar {

bool LineEvaluationOptions::Check() const {
  bool ok = CheckThresholds(thresholds_m, "LineEvaluation.thresholds_m");
  if (!(sample_step_m > 0.0) || !std::isfinite(sample_step_m)) {
    LOG(ERROR) << "LineEvaluation.sample_step_m must be positive, got "
               << sample_step_m;
    ok = false;
  }
  return ok;
}

size_t SegmentDistanceIndex::CellHash::operator()(
    const Eigen::Vector3i& cell) const {
  size_t hash = static_cast<uint32_t>(cell.x());
  hash = hash * 73856093u ^ static_cast<uint32_t>(cell.y());
  hash = hash * 19349663u ^ static_cast<uint32_t>(cell.z());
  return hash;
}

Eigen::Vector3i SegmentDistanceIndex::CellOf(
    const Eigen::Vector3d& point) const {
  return (point / cell_size_).array().floor().cast<int>();
}

SegmentDistanceIndex::SegmentDistanceIndex(
    const std::vector<Segment3D>& segments, double max_distance)
    : segments_(segments),
      max_distance_(max_distance),
      cell_size_(2.0 * max_distance) {
  THROW_CHECK(max_distance > 0.0,
              "SegmentDistanceIndex: max_distance must be positive");
  // Walk points at most cell/2 apart: every point of a segment is within
  // cell/4 of one. A query within max_distance = cell/2 of the segment is
  // then within 3/4 cell of a walk point, hence in one of the 27 cells
  // around the walk point's cell, where the segment is registered.
  for (size_t s = 0; s < segments_.size(); ++s) {
    const Segment3D& segment = segments_[s];
    const double length = segment.Length();
    const int num_steps =
        std::max(1, static_cast<int>(std::ceil(length / (0.5 * cell_size_))));
    Eigen::Vector3i last_cell(std::numeric_limits<int>::min(), 0, 0);
    for (int k = 0; k <= num_steps; ++k) {
      const Eigen::Vector3d walk =
          segment.start + (static_cast<double>(k) / num_steps) *
                              (segment.end - segment.start);
      const Eigen::Vector3i center = CellOf(walk);
      if (center == last_cell) {
        continue;
      }
      last_cell = center;
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dz = -1; dz <= 1; ++dz) {
            std::vector<int>& cell =
                cells_[center + Eigen::Vector3i(dx, dy, dz)];
            if (cell.empty() || cell.back() != static_cast<int>(s)) {
              cell.push_back(static_cast<int>(s));
            }
          }
        }
      }
    }
  }
}

double SegmentDistanceIndex::Distance(const Eigen::Vector3d& point) const {
  double best = std::numeric_limits<double>::infinity();
  const auto it = cells_.find(CellOf(point));
  if (it == cells_.end()) {
    return best;
  }
  for (const int s : it->second) {
    best = std::min(best, PointSegmentDistance(point, segments_[s].start,
                                               segments_[s].end));
  }
  return best <= max_distance_ ? best
                               : std::numeric_limits<double>::infinity();
}

namespace {

struct SegmentSamples {
  std::vector<double> distances;
  std::vector<double> weights;
  // Samples of segment s are [first[s], first[s + 1]).
  std::vector<size_t> first;
  double total_length = 0.0;
};

// Midpoints of the pieces of every segment, with their distance to `index`.
SegmentSamples SampleAndMeasure(const std::vector<Segment3D>& segments,
                                const SegmentDistanceIndex& index,
                                double step) {
  SegmentSamples samples;
  samples.first.push_back(0);
  for (const Segment3D& segment : segments) {
    const double length = segment.Length();
    samples.total_length += length;
    const int n = std::max(1, static_cast<int>(std::ceil(length / step)));
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d point =
          segment.start + ((k + 0.5) / n) * (segment.end - segment.start);
      samples.distances.push_back(index.Distance(point));
      samples.weights.push_back(length / n);
    }
    samples.first.push_back(samples.distances.size());
  }
  return samples;
}

}  // namespace

LineEvaluation EvaluateLines(const std::vector<Segment3D>& estimate,
                             const std::vector<Segment3D>& ground_truth,
                             const LineEvaluationOptions& options) {
  THROW_CHECK(options.Check(), "Invalid LineEvaluation options");
  THROW_CHECK(!ground_truth.empty(), "No ground-truth segments to evaluate "
                                     "against");
  LineEvaluation evaluation;
  evaluation.num_estimated_segments = estimate.size();
  evaluation.num_ground_truth_segments = ground_truth.size();
  evaluation.thresholds_m = options.thresholds_m;
  if (estimate.empty()) {
    LOG(WARNING) << "No estimated segments: precision and recall are 0";
  }
  const double max_threshold = options.thresholds_m.back();
  const SegmentDistanceIndex ground_truth_index(ground_truth, max_threshold);
  const SegmentDistanceIndex estimate_index(estimate, max_threshold);
  const SegmentSamples estimate_samples =
      SampleAndMeasure(estimate, ground_truth_index, options.sample_step_m);
  const SegmentSamples ground_truth_samples =
      SampleAndMeasure(ground_truth, estimate_index, options.sample_step_m);
  evaluation.estimated_length_m = estimate_samples.total_length;
  evaluation.ground_truth_length_m = ground_truth_samples.total_length;

  // Shares are over the sum of the piece weights (equal to the total length
  // up to rounding), so that full coverage gives exactly 1.
  for (const double t : options.thresholds_m) {
    evaluation.length_precisions.push_back(
        ShareBelow(estimate_samples.distances, t, estimate_samples.weights));
    evaluation.length_recalls.push_back(
        ShareBelow(ground_truth_samples.distances, t,
                   ground_truth_samples.weights));
    size_t inliers = 0;
    for (size_t s = 0; s < estimate.size(); ++s) {
      bool all_within = true;
      for (size_t i = estimate_samples.first[s];
           i < estimate_samples.first[s + 1] && all_within; ++i) {
        all_within = estimate_samples.distances[i] < t;
      }
      inliers += all_within;
    }
    evaluation.num_inlier_segments.push_back(inliers);
    evaluation.inlier_segment_shares.push_back(
        estimate.empty() ? 0.0 : static_cast<double>(inliers) / estimate.size());
  }
  LOG(INFO) << "Line evaluation: " << estimate.size() << " estimated ("
            << evaluation.estimated_length_m << " m) vs "
            << ground_truth.size() << " ground-truth segments ("
            << evaluation.ground_truth_length_m << " m)";
  return evaluation;
}

std::string FormatLineEvaluation(const LineEvaluation& evaluation) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof(line),
                "Line evaluation: %zu estimated segments (%.4f m), %zu "
                "ground-truth segments (%.4f m)\n",
                evaluation.num_estimated_segments,
                evaluation.estimated_length_m,
                evaluation.num_ground_truth_segments,
                evaluation.ground_truth_length_m);
  out << line;
  std::snprintf(line, sizeof(line), "  %14s %10s %10s %10s %10s\n",
                "threshold [m]", "precision", "recall", "inliers", "share");
  out << line;
  for (size_t k = 0; k < evaluation.thresholds_m.size(); ++k) {
    std::snprintf(line, sizeof(line), "  %14g %10.4f %10.4f %10zu %10.4f\n",
                  evaluation.thresholds_m[k], evaluation.length_precisions[k],
                  evaluation.length_recalls[k],
                  evaluation.num_inlier_segments[k],
                  evaluation.inlier_segment_shares[k]);
    out << line;
  }
  return out.str();
}

void WriteLineEvaluationJson(const std::string& path,
                             const LineEvaluation& evaluation) {
  Json json;
  json["evaluator"] = "line";
  json["num_estimated_segments"] = evaluation.num_estimated_segments;
  json["num_ground_truth_segments"] = evaluation.num_ground_truth_segments;
  json["estimated_length_m"] = evaluation.estimated_length_m;
  json["ground_truth_length_m"] = evaluation.ground_truth_length_m;
  json["thresholds_m"] = evaluation.thresholds_m;
  json["length_precision"] = evaluation.length_precisions;
  json["length_recall"] = evaluation.length_recalls;
  json["num_inlier_segments"] = evaluation.num_inlier_segments;
  json["inlier_segment_share"] = evaluation.inlier_segment_shares;
  WriteJsonFile(path, json);
}

}  // namespace colmap_lidar
