#include "src/matching/track_export.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <ostream>

#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

std::string FormatNumber(double value) {
  THROW_CHECK(std::isfinite(value), "Non-finite number in the track JSON");
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

template <typename Vector>
std::string FormatArray(const Vector& vector) {
  std::string text = "[";
  for (int i = 0; i < vector.size(); ++i) {
    if (i > 0) text += ", ";
    text += FormatNumber(vector[i]);
  }
  return text + "]";
}

std::string EscapeJson(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '"': escaped += "\\\""; break;
      case '\\': escaped += "\\\\"; break;
      case '\n': escaped += "\\n"; break;
      case '\t': escaped += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof(buffer), "\\u%04x", c);
          escaped += buffer;
        } else {
          escaped += c;
        }
    }
  }
  return escaped;
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
  WriteFileAtomically(
      path,
      [&](std::ostream& out) {
        out << "{\"num_tracks\": " << tracks.size() << ",\n \"tracks\": [";
        for (size_t t = 0; t < tracks.size(); ++t) {
          const LineTrackRecord& track = tracks[t];
          out << (t > 0 ? ",\n  " : "\n  ") << "{\"line3D_id\": "
              << track.line3D_id
              << ", \"plucker\": " << FormatArray(track.plucker)
              << ", \"start_in_world\": " << FormatArray(track.start_in_world)
              << ", \"end_in_world\": " << FormatArray(track.end_in_world)
              << ",\n   \"observations\": [";
          for (size_t k = 0; k < track.elements.size(); ++k) {
            const LineTrackElement& element = track.elements[k];
            const ImageData& image = images.at(element.image_id);
            THROW_CHECK(element.line2D_idx < image.segments.size(),
                        "Line track " << track.line3D_id << ": segment "
                                      << element.line2D_idx << " of image "
                                      << image.name << " not in "
                                      << database.path());
            const LineSegmentRecord& segment =
                image.segments[element.line2D_idx];
            out << (k > 0 ? ",\n    " : "\n    ") << "{\"image_id\": "
                << element.image_id << ", \"image_name\": \""
                << EscapeJson(image.name)
                << "\", \"segment_idx\": " << element.line2D_idx
                << ", \"start2D\": " << FormatArray(segment.start2D)
                << ", \"end2D\": " << FormatArray(segment.end2D)
                << ", \"start3D_in_cam\": "
                << FormatArray(segment.start3D_in_cam)
                << ", \"end3D_in_cam\": " << FormatArray(segment.end3D_in_cam)
                << "}";
          }
          out << "]}";
        }
        out << "\n ]}\n";
      },
      /*binary=*/false);
}

}  // namespace colmap_lidar
