#include "src/mesh/line_observations.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

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

template <typename T>
void AppendValue(const T& value, std::string* bytes) {
  bytes->append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <typename T>
T ExtractValue(const std::string& bytes, size_t* offset) {
  THROW_CHECK(sizeof(T) <= bytes.size() - *offset,
              "Line observations from rank 0 are truncated");
  T value;
  std::memcpy(&value, bytes.data() + *offset, sizeof(T));
  *offset += sizeof(T);
  return value;
}

}  // namespace

std::string SerializeLineObservations(
    const std::map<line3D_t, std::vector<LineObservedInterval>>&
        observations) {
  std::string bytes;
  AppendValue<uint64_t>(observations.size(), &bytes);
  for (const auto& [line_id, intervals] : observations) {
    AppendValue<uint64_t>(line_id, &bytes);
    AppendValue<uint64_t>(intervals.size(), &bytes);
    for (const LineObservedInterval& interval : intervals) {
      AppendValue<uint32_t>(interval.image_id, &bytes);
      AppendValue(interval.t_begin, &bytes);
      AppendValue(interval.t_end, &bytes);
    }
  }
  return bytes;
}

std::map<line3D_t, std::vector<LineObservedInterval>>
DeserializeLineObservations(const std::string& bytes) {
  std::map<line3D_t, std::vector<LineObservedInterval>> observations;
  size_t offset = 0;
  const uint64_t num_lines = ExtractValue<uint64_t>(bytes, &offset);
  for (uint64_t i = 0; i < num_lines; ++i) {
    const line3D_t line_id = ExtractValue<uint64_t>(bytes, &offset);
    const uint64_t num_intervals = ExtractValue<uint64_t>(bytes, &offset);
    // Checked before anything is allocated for them.
    THROW_CHECK(num_intervals <= (bytes.size() - offset) / kObservationBytes,
                "Line observations from rank 0 are truncated");
    std::vector<LineObservedInterval>& intervals = observations[line_id];
    intervals.resize(num_intervals);
    for (LineObservedInterval& interval : intervals) {
      interval.image_id = ExtractValue<uint32_t>(bytes, &offset);
      interval.t_begin = ExtractValue<double>(bytes, &offset);
      interval.t_end = ExtractValue<double>(bytes, &offset);
    }
  }
  THROW_CHECK(offset == bytes.size(),
              "Line observations from rank 0 have trailing bytes");
  return observations;
}

}  // namespace colmap_lidar
