#include "src/matching/segment_similarity.h"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <limits>

namespace colmap_lidar {

int HammingDistance(const std::array<uint8_t, 32>& a,
                    const std::array<uint8_t, 32>& b) {
  int distance = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    distance += static_cast<int>(std::bitset<8>(a[i] ^ b[i]).count());
  }
  return distance;
}

SegmentComparison CompareSegments(const QuerySegment& query,
                                  const SegmentInView& query_in_view,
                                  const MatchingSegment& candidate) {
  SegmentComparison comparison;

  // a: 2D angle between the reprojected and the detected segment.
  const Eigen::Vector2d delta = query_in_view.end2D - query_in_view.start2D;
  const double length = delta.norm();
  const Eigen::Vector2d direction =
      length > 0.0 ? Eigen::Vector2d(delta / length) : Eigen::Vector2d::UnitX();
  const double cos_angle =
      std::min(1.0, std::abs(direction.dot(candidate.direction2D)));
  comparison.angle_deg = std::acos(cos_angle) * 180.0 / M_PI;

  // b: endpoints to the other segment's 2D line, both ways.
  const Eigen::Vector2d normal(-direction.y(), direction.x());
  const double query_offset = normal.dot(query_in_view.start2D);
  const auto distance_to_candidate = [&](const Eigen::Vector2d& point) {
    return std::abs(candidate.line2D.head<2>().dot(point) + candidate.line2D.z());
  };
  comparison.pixel_distance_px =
      0.25 * (distance_to_candidate(query_in_view.start2D) +
              distance_to_candidate(query_in_view.end2D) +
              std::abs(normal.dot(candidate.start2D) - query_offset) +
              std::abs(normal.dot(candidate.end2D) - query_offset));

  // c: 3D midpoint difference orthogonal to l.
  const Eigen::Vector3d direction3D =
      (query.end_in_world - query.start_in_world).normalized();
  const Eigen::Vector3d midpoint_difference =
      0.5 * (query.start_in_world + query.end_in_world) -
      0.5 * (candidate.start_in_world + candidate.end_in_world);
  comparison.orthogonal_distance_m =
      (midpoint_difference - midpoint_difference.dot(direction3D) * direction3D)
          .norm();

  // d: LBD Hamming distance.
  comparison.descriptor_distance =
      HammingDistance(query.descriptor, candidate.descriptor);

  // Overlap along pi_j(l), relative to the shorter segment.
  const double t1 = direction.dot(candidate.start2D - query_in_view.start2D);
  const double t2 = direction.dot(candidate.end2D - query_in_view.start2D);
  const double intersection = std::min(length, std::max(t1, t2)) -
                              std::max(0.0, std::min(t1, t2));
  const double shorter =
      std::min(length, (candidate.end2D - candidate.start2D).norm());
  comparison.overlap =
      shorter > 0.0 ? std::clamp(intersection / shorter, 0.0, 1.0) : 0.0;
  return comparison;
}

bool PassesThresholds(const SegmentComparison& comparison,
                      const MatchingThresholds& thresholds,
                      const double min_overlap) {
  return comparison.angle_deg < thresholds.theta_deg &&
         comparison.pixel_distance_px < thresholds.dP_px &&
         comparison.orthogonal_distance_m < thresholds.dO_m &&
         comparison.descriptor_distance < thresholds.LBD &&
         (min_overlap <= 0.0 || comparison.overlap >= min_overlap);
}

double MatchingScore(const SegmentComparison& comparison,
                     const MatchingThresholds& thresholds) {
  return comparison.angle_deg / thresholds.theta_deg +
         comparison.pixel_distance_px / thresholds.dP_px +
         comparison.orthogonal_distance_m / thresholds.dO_m +
         comparison.descriptor_distance / thresholds.LBD;
}

double SideBySideOverlap(const MatchingSegment& a, const MatchingSegment& b) {
  const double length_a = (a.end2D - a.start2D).norm();
  const double length_b = (b.end2D - b.start2D).norm();
  const double t1 = a.direction2D.dot(b.start2D - a.start2D);
  const double t2 = a.direction2D.dot(b.end2D - a.start2D);
  const double intersection =
      std::min(length_a, std::max(t1, t2)) - std::max(0.0, std::min(t1, t2));
  const double shorter = std::min(length_a, length_b);
  return shorter > 0.0 ? std::clamp(intersection / shorter, 0.0, 1.0) : 0.0;
}

ViewMatch FindBestMatchInView(const QuerySegment& query,
                              const SegmentInView& query_in_view,
                              const MatchingView& view,
                              const MatchingThresholds& thresholds,
                              const LineMatchingOptions& options) {
  ViewMatch best;
  best.score = std::numeric_limits<double>::infinity();
  ViewMatch second;
  second.score = std::numeric_limits<double>::infinity();
  const int num_buckets = static_cast<int>(view.angle_buckets.size());
  if (num_buckets == 0) return ViewMatch();
  const Eigen::Vector2d delta = query_in_view.end2D - query_in_view.start2D;
  double angle_deg = std::atan2(delta.y(), delta.x()) * 180.0 / M_PI;
  if (angle_deg < 0.0) angle_deg += 180.0;
  // Buckets meeting [angle - t_theta, angle + t_theta], modulo 180 degrees.
  const double bucket_deg = MatchingView::kAngleBucketDeg;
  const int first = static_cast<int>(
      std::floor((angle_deg - thresholds.theta_deg) / bucket_deg));
  const int last = static_cast<int>(
      std::floor((angle_deg + thresholds.theta_deg) / bucket_deg));
  const int count = std::min(num_buckets, last - first + 1);
  for (int k = 0; k < count; ++k) {
    const int bucket = ((first + k) % num_buckets + num_buckets) % num_buckets;
    for (const int idx : view.angle_buckets[bucket]) {
      const SegmentComparison comparison =
          CompareSegments(query, query_in_view, view.segments[idx]);
      if (!PassesThresholds(comparison, thresholds, options.min_overlap)) {
        continue;
      }
      const double score = MatchingScore(comparison, thresholds);
      if (score < best.score) {
        second = best;
        best.score = score;
        best.segment_idx = idx;
      } else if (score < second.score) {
        second.score = score;
        second.segment_idx = idx;
      }
    }
  }
  if (best.segment_idx < 0) return ViewMatch();
  // Two parallel edges side by side (a window lip and the wall edge a few
  // centimetres away) that score alike: no way to tell which one l is.
  if (options.max_rival_score_ratio < 1.0 && second.segment_idx >= 0 &&
      best.score >= options.max_rival_score_ratio * second.score &&
      SideBySideOverlap(view.segments[best.segment_idx],
                        view.segments[second.segment_idx]) >=
          kMinRivalOverlap) {
    return ViewMatch();
  }
  return best;
}

}  // namespace colmap_lidar
