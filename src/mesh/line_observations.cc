#include "src/mesh/line_observations.h"

#include <algorithm>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

LineObservedInterval ObservedLineInterval(const Line3D& line3D, const Image& image,
                                     const LineSegmentRecord& segment) {
  const Eigen::Vector3d direction = line3D.end_in_world - line3D.start_in_world;
  const double squared_length = direction.squaredNorm();
  THROW_CHECK(squared_length > 0, "A 3D line of image "
                                      << image.image_id
                                      << "'s track has coincident endpoints");
  const Rigid3d world_from_cam = image.cam_from_world.Inverse();
  auto parameter = [&](const Eigen::Vector3d& point_in_cam) {
    return (world_from_cam * point_in_cam - line3D.start_in_world)
               .dot(direction) /
           squared_length;
  };
  const double t1 = parameter(segment.start3D_in_cam);
  const double t2 = parameter(segment.end3D_in_cam);
  LineObservedInterval observation;
  observation.image_id = image.image_id;
  observation.t_begin = std::min(t1, t2);
  observation.t_end = std::max(t1, t2);
  return observation;
}

std::map<line3D_t, std::vector<LineObservedInterval>> ReadLineObservations(
    const Reconstruction& lines_model, const Database& database) {
  LineSegmentCache segments(database);
  std::map<line3D_t, std::vector<LineObservedInterval>> observations;
  for (const auto& [line3D_id, line3D] : lines_model.lines3D) {
    std::vector<LineObservedInterval>& line_observations =
        observations[line3D_id];
    for (const LineTrackElement& element : line3D.track) {
      const Image* image = lines_model.FindImage(element.image_id);
      if (image == nullptr) continue;
      line_observations.push_back(ObservedLineInterval(
          line3D, *image,
          segments.Segment(element.image_id, element.line2D_idx, line3D_id)));
    }
  }
  return observations;
}

}  // namespace colmap_lidar
