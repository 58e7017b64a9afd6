#include "src/matching/candidate_views.h"

#include <algorithm>

namespace colmap_lidar {

SegmentInView ProjectSegmentIntoView(const Eigen::Vector3d& start_in_world,
                                     const Eigen::Vector3d& end_in_world,
                                     const MatchingView& view,
                                     const LineMatchingOptions& options) {
  SegmentInView result;
  const Eigen::Vector3d start = view.cam_from_world * start_in_world;
  const Eigen::Vector3d end = view.cam_from_world * end_in_world;
  const double min_depth = options.min_depth_m;
  if (start.z() <= min_depth && end.z() <= min_depth) {
    return result;
  }
  const int num_samples = options.num_visibility_samples;
  const double width = static_cast<double>(view.camera.width);
  const double height = static_cast<double>(view.camera.height);

  // Depth first, so that the occlusion tolerance can follow it.
  double depth_sum = 0.0;
  int num_in_front = 0;
  for (int s = 0; s < num_samples; ++s) {
    const double t = static_cast<double>(s) / (num_samples - 1);
    const double z = (1.0 - t) * start.z() + t * end.z();
    if (z > min_depth) {
      depth_sum += z;
      ++num_in_front;
    }
  }
  result.depth = depth_sum / num_in_front;
  const MatchingThresholds thresholds = EffectiveThresholds(
      options, result.depth, view.camera.MeanFocalLength());

  int num_visible = 0;
  for (int s = 0; s < num_samples; ++s) {
    const double t = static_cast<double>(s) / (num_samples - 1);
    const Eigen::Vector3d point = (1.0 - t) * start + t * end;
    if (point.z() <= min_depth) continue;
    const Eigen::Vector2d pixel = view.camera.ImgFromCam(point);
    if (!(pixel.x() >= 0.0 && pixel.y() >= 0.0 && pixel.x() <= width &&
          pixel.y() <= height)) {
      continue;
    }
    const double lidar_depth = view.lidar_depth.NearestDepth(pixel);
    if (point.z() > lidar_depth * (1.0 + options.visibility_relative_tolerance) +
                        thresholds.visibility_absolute_m) {
      continue;
    }
    ++num_visible;
  }
  result.visible_fraction = static_cast<double>(num_visible) / num_samples;
  result.visible = result.visible_fraction >= options.min_visible_fraction;
  if (!result.visible) return result;

  // Clip to the part in front of the camera and project.
  Eigen::Vector3d clipped_start = start;
  Eigen::Vector3d clipped_end = end;
  if (clipped_start.z() <= min_depth || clipped_end.z() <= min_depth) {
    const double t = (min_depth + 1e-6 - start.z()) / (end.z() - start.z());
    const Eigen::Vector3d cut = start + t * (end - start);
    if (clipped_start.z() <= min_depth) {
      clipped_start = cut;
    } else {
      clipped_end = cut;
    }
  }
  result.start2D = view.camera.ImgFromCam(clipped_start);
  result.end2D = view.camera.ImgFromCam(clipped_end);
  return result;
}

}  // namespace colmap_lidar
