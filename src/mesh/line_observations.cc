#include "src/mesh/line_observations.h"

#include <algorithm>
#include <cstdint>

#include "colmap_ext/util/byte_stream.h"
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

namespace {

// One observation on the wire: image id, then t_begin and t_end.
constexpr size_t kObservationBytes = sizeof(uint32_t) + 2 * sizeof(double);

}  // namespace

std::string SerializeLineObservations(
    const std::map<line3D_t, std::vector<LineObservedInterval>>&
        observations) {
  std::string bytes;
  ByteWriter writer(&bytes);
  writer.Value<uint64_t>(observations.size());
  for (const auto& [line_id, intervals] : observations) {
    writer.Value<uint64_t>(line_id);
    writer.Value<uint64_t>(intervals.size());
    for (const LineObservedInterval& interval : intervals) {
      writer.Value<uint32_t>(interval.image_id);
      writer.Value(interval.t_begin);
      writer.Value(interval.t_end);
    }
  }
  return bytes;
}

std::map<line3D_t, std::vector<LineObservedInterval>>
DeserializeLineObservations(const std::string& bytes) {
  std::map<line3D_t, std::vector<LineObservedInterval>> observations;
  ByteReader reader(bytes);
  const uint64_t num_lines = reader.Value<uint64_t>();
  for (uint64_t i = 0; i < num_lines; ++i) {
    const line3D_t line_id = reader.Value<uint64_t>();
    const uint64_t num_intervals = reader.Value<uint64_t>();
    // Checked before anything is allocated for them.
    THROW_CHECK(num_intervals <= reader.Remaining() / kObservationBytes,
                "Line observations from rank 0 are truncated");
    std::vector<LineObservedInterval>& intervals = observations[line_id];
    intervals.resize(num_intervals);
    for (LineObservedInterval& interval : intervals) {
      interval.image_id = reader.Value<uint32_t>();
      interval.t_begin = reader.Value<double>();
      interval.t_end = reader.Value<double>();
    }
  }
  THROW_CHECK(reader.AtEnd(),
              "Line observations from rank 0 have trailing bytes");
  return observations;
}

}  // namespace colmap_lidar
