#include "src/mvs/source_views.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <glog/logging.h>

namespace colmap_lidar {
namespace {

// Fewer shared sparse points than this: the angle test falls back to the
// reference's median-depth point on its optical axis.
constexpr size_t kMinSharedPointsForAngle = 5;

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2,
                   values.end());
  return values[values.size() / 2];
}

}  // namespace

SourceViewSelector::SourceViewSelector(
    const Reconstruction& model, const FusedVisibility& lidar_visibility,
    const std::vector<Eigen::Vector3f>& lidar_points,
    const LidarPatchMatchOptions& options)
    : model_(model), options_(options) {
  const size_t n = model.images.size();
  shared_points_.assign(n, std::vector<int>(n, 0));
  shared_voxels_.assign(n, std::vector<int>(n, 0));
  std::unordered_map<image_t, int> id_to_idx;
  for (size_t i = 0; i < n; ++i) id_to_idx[model.images[i].image_id] = i;
  std::vector<std::vector<double>> depths(n);
  points_of_image_.assign(n, {});
  for (const auto& [point3D_id, point] : model.points3D) {
    std::vector<int> indices;
    for (const TrackElement& element : point.track) {
      const auto it = id_to_idx.find(element.image_id);
      if (it != id_to_idx.end()) indices.push_back(it->second);
    }
    std::sort(indices.begin(), indices.end());
    indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
    if (indices.size() >= 2) {
      for (const int index : indices) {
        points_of_image_[index].push_back(&point);
      }
    }
    for (size_t a = 0; a < indices.size(); ++a) {
      const Image& image = model.images[indices[a]];
      depths[indices[a]].push_back((image.cam_from_world * point.xyz).z());
      for (size_t b = a + 1; b < indices.size(); ++b) {
        ++shared_points_[indices[a]][indices[b]];
        ++shared_points_[indices[b]][indices[a]];
      }
    }
  }
  std::vector<std::vector<double>> lidar_depths(n);
  for (size_t v = 0; v < lidar_visibility.size(); ++v) {
    const std::vector<uint32_t>& frames = lidar_visibility[v];
    for (size_t a = 0; a < frames.size(); ++a) {
      if (frames[a] >= n) continue;
      if (v < lidar_points.size() && lidar_depths[frames[a]].size() < 20000) {
        const Image& image = model.images[frames[a]];
        lidar_depths[frames[a]].push_back(
            (image.cam_from_world * lidar_points[v].cast<double>()).z());
      }
      for (size_t b = a + 1; b < frames.size(); ++b) {
        if (frames[b] >= n || frames[b] == frames[a]) continue;
        ++shared_voxels_[frames[a]][frames[b]];
        ++shared_voxels_[frames[b]][frames[a]];
      }
    }
  }
  median_depth_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    std::vector<double> positive;
    for (double d : depths[i].empty() ? lidar_depths[i] : depths[i]) {
      if (d > 0) positive.push_back(d);
    }
    median_depth_[i] = Median(positive);
  }
}

std::vector<int> SourceViewSelector::Select(int ref_idx,
                                            const PatchMatchEntry& entry) const {
  const int n = static_cast<int>(model_.images.size());
  std::vector<int> sources;
  if (entry.source_kind == PatchMatchEntry::SourceKind::kList) {
    for (const std::string& name : entry.src_image_names) {
      bool found = false;
      for (int i = 0; i < n; ++i) {
        if (model_.images[i].name == name && i != ref_idx) {
          sources.push_back(i);
          found = true;
          break;
        }
      }
      LOG_IF(WARNING, !found) << "Source image " << name << " of "
                              << entry.ref_image_name
                              << " is not in the workspace model; skipped";
    }
    return sources;
  }
  const Image& ref = model_.images[ref_idx];
  const Eigen::Vector3d ref_center = ref.ProjectionCenter();
  // Triangulation angles of the sparse points the reference shares with
  // each candidate: a camera moving along its optical axis (a car on a
  // road) sees the point ahead under no angle at all, its periphery under
  // a useful one.
  std::vector<std::vector<double>> shared_angles(n);
  {
    std::unordered_map<image_t, int> id_to_idx;
    for (int i = 0; i < n; ++i) id_to_idx[model_.images[i].image_id] = i;
    for (const Point3D* point : points_of_image_[ref_idx]) {
      const Eigen::Vector3d to_ref = (ref_center - point->xyz).normalized();
      for (const TrackElement& element : point->track) {
        const auto it = id_to_idx.find(element.image_id);
        if (it == id_to_idx.end() || it->second == ref_idx) continue;
        const Eigen::Vector3d to_other =
            (model_.images[it->second].ProjectionCenter() - point->xyz)
                .normalized();
        shared_angles[it->second].push_back(
            std::acos(std::clamp(to_ref.dot(to_other), -1.0, 1.0)));
      }
    }
  }
  const Eigen::Vector3d ref_axis =
      ref.cam_from_world.rotation.inverse() * Eigen::Vector3d::UnitZ();
  const double median_depth = median_depth_[ref_idx];
  const Eigen::Vector3d scene_point = ref_center + median_depth * ref_axis;
  const double min_angle = options_.min_triangulation_angle_deg * M_PI / 180.0;
  std::vector<std::pair<double, int>> scored;
  for (int i = 0; i < n; ++i) {
    if (i == ref_idx) continue;
    const double score =
        shared_points_[ref_idx][i] +
        options_.lidar_covisibility_weight * shared_voxels_[ref_idx][i];
    if (score <= 0) continue;
    if (shared_angles[i].size() >= kMinSharedPointsForAngle) {
      if (Median(shared_angles[i]) < min_angle) continue;
    } else if (median_depth > 0) {
      const Eigen::Vector3d a = ref_center - scene_point;
      const Eigen::Vector3d b = model_.images[i].ProjectionCenter() - scene_point;
      const double angle = std::acos(std::clamp(
          a.normalized().dot(b.normalized()), -1.0, 1.0));
      if (angle < min_angle) continue;
    }
    scored.emplace_back(score, i);
  }
  std::stable_sort(scored.begin(), scored.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  int max_num = options_.max_num_src_images;
  if (entry.source_kind == PatchMatchEntry::SourceKind::kAuto) {
    max_num = std::min(max_num, entry.num_auto_src_images);
  }
  for (const auto& [score, i] : scored) {
    if (static_cast<int>(sources.size()) >= max_num) break;
    sources.push_back(i);
  }
  return sources;
}

}  // namespace colmap_lidar
