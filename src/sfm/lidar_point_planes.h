// The LIDAR depth of the sparse points (not in the paper): for each
// observation of a triangulated point, the local plane of the observing
// image's own scan around the point, a term of the adjustment
// (LidarPointPlaneCostFunctor, src/optim/cost_functions.h).
//
// Why: the paper takes the metric scale from the LIDAR lines alone, and the
// LIDAR pose graph's registrations are blind along surfaces that do not
// change along a direction (a corridor's or a straight street's axis:
// measured on the corridor, steps off by up to 4 cm of 3.4 m). A feature on
// a wall whose distance from the camera the scan gives is at a known
// position along the wall through its bearing; hundreds of such features
// pin every step.
//
// Plane of one observation (image i, point X): X in camera i's frame, then
// the points of scan i (in the same frame) within a radius r of it. r starts
// at max(min_radius_m, 5 sigma) (sigma: the range noise measured on the
// scans, src/lidar/sensor_estimation.h) and doubles, up to
// max_radius_range_fraction of X's range, until the neighbours spread in
// two directions (both in-plane spreads at least min_spread_fraction of r:
// a ring-scanning LIDAR's nearest neighbours lie on one ring, a line, and
// the radius that reaches the next ring follows the ring spacing at that
// range, whatever the sensor). The neighbours' PCA plane is kept when
// - it is flat: its rms residual is at most max_rms_sigmas times sigma (a
//   crease, a kerb or vegetation is not one plane);
// - X lies within max_distance_sigmas plane sigmas of it (a point in front
//   of the surface, or a wrong association), and at most half the radius
//   from the neighbours' centroid along the plane (not past an occlusion
//   boundary).
// The plane's sigma is its rms residual, never below the range noise.
#pragma once

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "colmap_ext/database/database.h"
#include "colmap_ext/scene/reconstruction.h"
#include "src/lidar/lidar_scan.h"
#include "src/optim/line_bundle_adjustment.h"

namespace colmap_lidar {

struct LidarPointPlaneOptions {
  // First search radius, metres, > 0 (raised to 5 range-noise sigmas).
  double min_radius_m = 0.05;
  // Largest search radius as a fraction of the point's range, > 0: the
  // ring spacing of a 16-ring scanner (2 deg) is 0.035 of the range.
  double max_radius_range_fraction = 0.1;
  // Points within the radius needed for a plane, >= 3.
  int min_neighbors = 6;
  // Both in-plane spreads (standard deviations) of the neighbours must
  // reach this fraction of the radius, (0, 1).
  double min_spread_fraction = 0.15;
  // Flatness: rms residual of the fit at most this many range sigmas, > 0.
  double max_rms_sigmas = 3.0;
  // Distance gate of the point to the plane, in plane sigmas, > 0.
  double max_distance_sigmas = 10.0;
  // Points farther than this from the camera get no plane, metres, > 0
  // (their triangulated depth is too uncertain to associate).
  double max_range_m = 60.0;
  // -1: all cores.
  int num_threads = -1;

  bool Check() const;
};

struct LidarPointPlaneSummary {
  // Observations of adjusted points tried, and planes found.
  int num_observations = 0;
  int num_planes = 0;
  // Images with a scan.
  int num_scans = 0;
  // Range noise the thresholds rest on, metres.
  double range_sigma_m = 0.0;
  // Median plane sigma, metres (0 without planes).
  double median_plane_sigma_m = 0.0;

  std::string ToString() const;
};

// One image's scan (LIDAR frame) and where its LIDAR sits in the camera.
struct LidarPlaneScanInput {
  image_t image_id = kInvalidImageId;
  LidarScan scan;
  Rigid3d cam_from_lidar;
};

// The scans of a model's images, in their camera frames, with a search
// index each; loaded once, searched every iteration.
class LidarPlaneScans {
 public:
  // The given scans; the range noise is measured over (up to 8 of) them.
  explicit LidarPlaneScans(std::vector<LidarPlaneScanInput> scans);
  // Reads the scan of every image of `model` that the database has one for
  // (ext_lidar_scans; LidarScanFilePath). Throws colmap_lidar::Error
  // naming the file when a scan cannot be read.
  LidarPlaneScans(const Database& database, const Reconstruction& model);
  ~LidarPlaneScans();

  int NumScans() const;
  double RangeSigma() const { return range_sigma_m_; }

  // The planes of the points of `model` with at least min_track_length
  // observations, one per observation whose image has a scan and whose
  // neighbourhood passes the checks above, at the model's current poses.
  std::vector<PointPlaneObservation> Associate(
      const Reconstruction& model, int min_track_length,
      const LidarPointPlaneOptions& options,
      LidarPointPlaneSummary* summary) const;

 private:
  struct Scan;
  void Build(std::vector<LidarPlaneScanInput> scans);

  std::unordered_map<image_t, std::unique_ptr<Scan>> scans_;
  double range_sigma_m_ = 0.0;
};

}  // namespace colmap_lidar
