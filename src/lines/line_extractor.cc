#include "src/lines/line_extractor.h"

#include <chrono>

#include <opencv2/imgproc.hpp>

#include "colmap_ext/util/logging.h"
#include "src/lidar/sensor_estimation.h"
#include "src/lines/lbd_descriptor.h"

namespace colmap_lidar {
namespace {

class StageTimer {
 public:
  StageTimer() : start_(std::chrono::steady_clock::now()) {}
  // Milliseconds since construction or the previous call.
  double Lap() {
    const auto now = std::chrono::steady_clock::now();
    const double ms =
        std::chrono::duration<double, std::milli>(now - start_).count();
    start_ = now;
    return ms;
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

bool LineExtractionOptions::Check() const {
  bool ok = lsd.Check();
  ok = edges.Check() && ok;
  ok = projection.Check() && ok;
  ok = association.Check() && ok;
  ok = planes.Check() && ok;
  ok = fusion.Check() && ok;
  if (num_threads == 0 || num_threads < -1) {
    LOG(ERROR) << "LineExtraction.num_threads must be -1 or >= 1";
    ok = false;
  }
  return ok;
}

ViewLines ExtractViewLines(const cv::Mat& image, const LidarScan& scan,
                           const Camera& camera, const Rigid3d& cam_from_lidar,
                           const LineExtractionOptions& options) {
  THROW_CHECK(!image.empty(), "ExtractViewLines: empty image");
  THROW_CHECK(image.cols == static_cast<int>(camera.width) &&
                  image.rows == static_cast<int>(camera.height),
              "ExtractViewLines: image is " << image.cols << "x" << image.rows
                                            << " but camera "
                                            << camera.camera_id << " is "
                                            << camera.width << "x"
                                            << camera.height);
  ViewLines result;
  StageTimer timer;
  cv::Mat gray;
  if (image.channels() == 3) {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  } else {
    gray = image;
  }
  const std::vector<LineSegment2D> segments =
      DetectLineSegments(gray, options.lsd);
  result.num_lsd_segments = static_cast<int>(segments.size());
  result.timings.lsd_ms = timer.Lap();

  RingNeighbors ring_neighbors;
  const std::vector<int> edge_idxs =
      DetectLidarEdges(scan, options.edges, &ring_neighbors);
  result.num_edge_points = static_cast<int>(edge_idxs.size());
  result.timings.edges_ms = timer.Lap();

  const ProjectedScan projected =
      ProjectScan(scan, camera, cam_from_lidar, options.projection);
  for (const int idx : edge_idxs) {
    if (projected.visible[idx]) {
      result.visible_edge_point_idxs.push_back(idx);
      result.visible_edge_pixels.push_back(projected.pixels[idx]);
    }
  }
  result.timings.projection_ms = timer.Lap();

  // The scan's range noise: the texture test's exclusion and the plane
  // lifting's inlier distance.
  const bool need_noise =
      options.planes.enabled ||
      (options.association.texture.enabled &&
       options.association.texture.exclusion_noise_sigmas > 0.0);
  result.range_noise_m = options.planes.range_noise_m;
  if (need_noise && result.range_noise_m <= 0.0) {
    result.range_noise_m =
        EstimateRangeNoise({scan}, RangeNoiseOptions()).sigma_m;
  }
  result.timings.noise_ms = timer.Lap();
  EdgeAssociationOptions association = options.association;
  association.texture.range_noise_m = result.range_noise_m;

  std::vector<LiftResult> edge_results;
  std::vector<std::optional<LineSurfaceType>> edge_surfaces;
  std::vector<ViewLineSegment> lifted =
      LiftSegments(segments, camera, projected, result.visible_edge_point_idxs,
                   association, &result.lift_result_counts, &ring_neighbors,
                   nullptr, &edge_results, &edge_surfaces);
  result.outcomes.resize(segments.size());
  for (size_t i = 0, k = 0; i < segments.size(); ++i) {
    SegmentOutcome& outcome = result.outcomes[i];
    outcome.segment = segments[i];
    outcome.edge_result = edge_results[i];
    outcome.edge_surface = edge_surfaces[i];
    if (outcome.edge_result == LiftResult::kLifted) {
      outcome.lifted2D = lifted[k].segment2D;
      outcome.start3D_in_cam = lifted[k].start3D_in_cam;
      outcome.end3D_in_cam = lifted[k].end3D_in_cam;
      ++k;
    }
  }
  result.timings.association_ms = timer.Lap();

  if (options.planes.enabled) {
    for (SegmentOutcome& outcome : result.outcomes) {
      if (outcome.edge_result == LiftResult::kLifted) continue;
      ViewLineSegment plane_lifted;
      outcome.plane_result = LiftSegmentByPlanes(
          outcome.segment, camera, projected, options.planes,
          result.range_noise_m, options.association.max_reprojection_angle_deg,
          options.association.max_reprojection_distance_px,
          options.association.min_ray_line_angle_deg, &plane_lifted);
      if (outcome.plane_result != PlaneLiftResult::kCrease &&
          outcome.plane_result != PlaneLiftResult::kOcclusion) {
        continue;
      }
      if (plane_lifted.start3D_in_cam.norm() >
              options.association.max_endpoint_range ||
          plane_lifted.end3D_in_cam.norm() >
              options.association.max_endpoint_range) {
        outcome.plane_result = PlaneLiftResult::kOutOfRange;
        continue;
      }
      outcome.lifted2D = plane_lifted.segment2D;
      outcome.start3D_in_cam = plane_lifted.start3D_in_cam;
      outcome.end3D_in_cam = plane_lifted.end3D_in_cam;
      lifted.push_back(std::move(plane_lifted));
      ++result.num_plane_lifted_segments;
    }
  }
  result.num_lifted_segments = static_cast<int>(lifted.size());
  result.timings.planes_ms = timer.Lap();

  result.segments =
      FuseSegments(std::move(lifted), projected.points_in_cam, camera,
                   options.fusion, options.association.min_ray_line_angle_deg);
  result.timings.fusion_ms = timer.Lap();

  if (options.compute_descriptors && !result.segments.empty()) {
    std::vector<LineSegment2D> final_segments;
    final_segments.reserve(result.segments.size());
    for (const ViewLineSegment& segment : result.segments) {
      final_segments.push_back(segment.segment2D);
    }
    const std::vector<LbdDescriptor> descriptors =
        ComputeLbdDescriptors(gray, final_segments);
    for (size_t i = 0; i < descriptors.size(); ++i) {
      result.segments[i].descriptor = descriptors[i];
    }
  }
  result.timings.descriptor_ms = timer.Lap();
  return result;
}

}  // namespace colmap_lidar
