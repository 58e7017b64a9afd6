#include "src/matching/track_export.h"

#include <map>
#include <optional>

#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// The coefficients as an array. Non-finite ones would be written as null;
// a track or segment with one is a bug upstream, so it is refused.
template <typename Vector>
Json FiniteVectorToJson(const Vector& vector) {
  THROW_CHECK(vector.allFinite(), "Non-finite number in the track JSON");
  return VectorToJson(vector);
}

}  // namespace

void WriteLineTracksJson(const std::string& path, const Database& database,
                         const std::vector<LineTrackRecord>& tracks) {
  // Per image: name and segments, read once.
  struct ImageData {
    std::string name;
    std::vector<LineSegmentRecord> segments;
  };
  std::map<image_t, ImageData> images;
  for (const LineTrackRecord& track : tracks) {
    for (const LineTrackElement& element : track.elements) {
      if (images.count(element.image_id)) continue;
      const std::optional<DatabaseImage> image =
          database.ReadImage(element.image_id);
      THROW_CHECK(image.has_value(), "Line track " << track.line3D_id
                                                   << ": image "
                                                   << element.image_id
                                                   << " not in "
                                                   << database.path());
      images[element.image_id] = {image->name,
                                  ReadLineSegments(database, element.image_id)};
    }
  }
  Json json;
  json["num_tracks"] = tracks.size();
  Json tracks_json = Json::array();
  for (const LineTrackRecord& track : tracks) {
    Json& track_json = tracks_json.emplace_back();
    track_json["line3D_id"] = track.line3D_id;
    track_json["plucker"] = FiniteVectorToJson(track.plucker);
    track_json["start_in_world"] = FiniteVectorToJson(track.start_in_world);
    track_json["end_in_world"] = FiniteVectorToJson(track.end_in_world);
    Json observations = Json::array();
    for (const LineTrackElement& element : track.elements) {
      const ImageData& image = images.at(element.image_id);
      THROW_CHECK(element.line2D_idx < image.segments.size(),
                  "Line track " << track.line3D_id << ": segment "
                                << element.line2D_idx << " of image "
                                << image.name << " not in "
                                << database.path());
      const LineSegmentRecord& segment = image.segments[element.line2D_idx];
      Json& observation = observations.emplace_back();
      observation["image_id"] = element.image_id;
      observation["image_name"] = image.name;
      observation["segment_idx"] = element.line2D_idx;
      observation["start2D"] = FiniteVectorToJson(segment.start2D);
      observation["end2D"] = FiniteVectorToJson(segment.end2D);
      observation["start3D_in_cam"] =
          FiniteVectorToJson(segment.start3D_in_cam);
      observation["end3D_in_cam"] = FiniteVectorToJson(segment.end3D_in_cam);
    }
    track_json["observations"] = std::move(observations);
  }
  json["tracks"] = std::move(tracks_json);
  WriteJsonFile(path, json);
}

}  // namespace colmap_lidar
