#include "src/matching/line_tracks.h"

#include <algorithm>
#include <map>

#include <Eigen/Dense>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

Eigen::Matrix<double, 6, 1> FitPluckerLine(
    const std::vector<Eigen::Vector3d>& points, Eigen::Vector3d* start,
    Eigen::Vector3d* end) {
  THROW_CHECK(points.size() >= 2,
              "A 3D line needs at least 2 points, got " << points.size());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& point : points) centroid += point;
  centroid /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& point : points) {
    const Eigen::Vector3d offset = point - centroid;
    scatter += offset * offset.transpose();
  }
  THROW_CHECK(scatter.trace() > 0.0, "A 3D line through identical points");
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  Eigen::Vector3d direction = solver.eigenvectors().col(2).normalized();
  // Orient along the first point -> last point, for a stable sign.
  if (direction.dot(points.back() - points.front()) < 0.0) {
    direction = -direction;
  }
  double t_min = 0.0;
  double t_max = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    const double t = direction.dot(points[i] - centroid);
    if (i == 0 || t < t_min) t_min = t;
    if (i == 0 || t > t_max) t_max = t;
  }
  if (start != nullptr) *start = centroid + t_min * direction;
  if (end != nullptr) *end = centroid + t_max * direction;
  Eigen::Matrix<double, 6, 1> plucker;
  plucker.head<3>() = direction;
  plucker.tail<3>() = centroid.cross(direction);
  return plucker;
}

std::vector<LineTrackRecord> BuildLineTracks(
    const std::vector<MatchingView>& views,
    const std::vector<TrackObservation>& observations,
    const std::vector<int>& cluster_ids, const int min_track_length) {
  THROW_CHECK(observations.size() == cluster_ids.size(),
              "BuildLineTracks: " << observations.size()
                                  << " observations but "
                                  << cluster_ids.size() << " cluster ids");
  // Clusters in order of first appearance.
  std::vector<int> cluster_order;
  std::map<int, std::vector<size_t>> members;
  for (size_t i = 0; i < observations.size(); ++i) {
    if (cluster_ids[i] < 0) continue;
    auto [it, inserted] = members.try_emplace(cluster_ids[i]);
    if (inserted) cluster_order.push_back(cluster_ids[i]);
    it->second.push_back(i);
  }
  std::vector<LineTrackRecord> tracks;
  for (const int cluster : cluster_order) {
    const std::vector<size_t>& indices = members.at(cluster);
    if (static_cast<int>(indices.size()) < min_track_length) continue;
    LineTrackRecord track;
    track.line3D_id = static_cast<line3D_t>(tracks.size() + 1);
    std::vector<Eigen::Vector3d> points;
    for (const size_t i : indices) {
      const auto [view_idx, segment_idx] = observations[i];
      const MatchingView& view = views.at(view_idx);
      const MatchingSegment& segment = view.segments.at(segment_idx);
      points.push_back(segment.start_in_world);
      points.push_back(segment.end_in_world);
      track.elements.push_back(
          {view.image_id, static_cast<uint32_t>(segment_idx)});
    }
    std::sort(track.elements.begin(), track.elements.end(),
              [](const LineTrackElement& a, const LineTrackElement& b) {
                return a.image_id < b.image_id;
              });
    for (size_t k = 1; k < track.elements.size(); ++k) {
      THROW_CHECK(track.elements[k].image_id != track.elements[k - 1].image_id,
                  "Line cluster " << cluster << " holds two observations of image "
                                  << track.elements[k].image_id);
    }
    track.plucker =
        FitPluckerLine(points, &track.start_in_world, &track.end_in_world);
    tracks.push_back(std::move(track));
  }
  return tracks;
}

}  // namespace colmap_lidar
