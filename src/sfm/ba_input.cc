#include "src/sfm/ba_input.h"

#include <unordered_map>

#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/database/line_tracks_table.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

std::vector<LineTrack> LoadLineTracks(const Database& database,
                                      const Reconstruction& model,
                                      int min_track_length,
                                      LineTrackLoadSummary* summary) {
  LineTrackLoadSummary local_summary;
  const std::vector<LineTrackRecord> records = ReadLineTracks(database);
  local_summary.num_tracks_in_database = static_cast<int>(records.size());

  // Segments are read once per image that some track references.
  LineSegmentCache segments(database);
  std::vector<LineTrack> tracks;
  tracks.reserve(records.size());
  for (const LineTrackRecord& record : records) {
    LineTrack track;
    track.line3D_id = record.line3D_id;
    track.plucker_in_world = record.plucker;
    track.start_in_world = record.start_in_world;
    track.end_in_world = record.end_in_world;
    for (const LineTrackElement& element : record.elements) {
      if (model.FindImage(element.image_id) == nullptr) {
        ++local_summary.num_observations_without_image;
        continue;
      }
      const LineSegmentRecord& segment = segments.Segment(
          element.image_id, element.line2D_idx, record.line3D_id);
      LineObservation observation;
      observation.image_id = element.image_id;
      observation.line2D_idx = element.line2D_idx;
      observation.start2D = segment.start2D;
      observation.end2D = segment.end2D;
      observation.has_lidar = true;
      observation.start_in_cam = segment.start3D_in_cam;
      observation.end_in_cam = segment.end3D_in_cam;
      track.observations.push_back(observation);
    }
    if (static_cast<int>(track.observations.size()) < min_track_length) {
      continue;
    }
    local_summary.num_observations +=
        static_cast<int>(track.observations.size());
    local_summary.num_lidar_observations +=
        static_cast<int>(track.observations.size());
    tracks.push_back(std::move(track));
  }
  local_summary.num_tracks = static_cast<int>(tracks.size());
  if (summary != nullptr) {
    *summary = local_summary;
  }
  return tracks;
}

std::unordered_map<image_t, Rigid3d> ReadPosePriors(
    const Database& database, const Reconstruction& model) {
  std::unordered_map<image_t, Rigid3d> priors;
  for (const DatabaseImage& db_image : database.ReadAllImages()) {
    if (!db_image.prior_q || !db_image.prior_t) {
      continue;
    }
    const Image* image = model.FindImageByName(db_image.name);
    if (image == nullptr) {
      continue;
    }
    // prior_t is the camera centre c; cam_from_world = (R, -R c).
    const Eigen::Quaterniond rotation = db_image.prior_q->normalized();
    priors[image->image_id] = Rigid3d(rotation, -(rotation * *db_image.prior_t));
  }
  return priors;
}

}  // namespace colmap_lidar
