// Synthetic views of known 3D edges for the tests and benchmarks of the
// line association: a facade with recessed windows (each window's lip and
// back are parallel edges 15 cm apart, the hard case of section III-C),
// seen by a camera walking along it. Segments are the projections of the
// edges with pixel noise, random partial extents, depth noise on the 3D
// endpoints and per-edge LBD-like descriptors with a few flipped bits per
// view. No dependency on the line extractor.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/rigid3.h"
#include "src/matching/line_tracks.h"
#include "src/matching/matching_view.h"

namespace colmap_lidar {

struct SyntheticLineSceneOptions {
  int num_views = 12;
  int num_window_columns = 8;
  int num_window_rows = 3;
  // Distance of the window backs behind their lips, metres.
  double recess_depth_m = 0.15;
  double pixel_noise_px = 0.5;
  // Along-ray noise of the 3D endpoints, metres.
  double depth_noise_m = 0.02;
  int descriptor_bit_flips = 20;
  double min_length_px = 20.0;
  uint32_t seed = 1;
};

struct SyntheticLineScene {
  // Ground-truth edges, world frame.
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> edges;
  Camera camera;
  std::vector<Rigid3d> cam_from_world;
  // Per view: segments and the edge each one observes.
  std::vector<std::vector<LineSegmentRecord>> segments;
  std::vector<std::vector<int>> edge_of_segment;
};

SyntheticLineScene MakeSyntheticLineScene(
    const SyntheticLineSceneOptions& options);

// Views with image ids 1..N and the given poses (the scene's by default).
std::vector<MatchingView> MakeSyntheticViews(
    const SyntheticLineScene& scene, const std::vector<Rigid3d>& cam_from_world);

// Each pose perturbed as the synthesizer perturbs its priors: centre + N(0,
// sigma_t^2) per axis, rotation by N(0, sigma_r^2) about a random axis.
std::vector<Rigid3d> PerturbPoses(const std::vector<Rigid3d>& cam_from_world,
                                  double sigma_t_m, double sigma_r_deg,
                                  uint32_t seed);

struct TrackQuality {
  size_t num_tracks = 0;
  // Tracks whose observations all observe one ground-truth edge.
  size_t num_pure_tracks = 0;
  double precision = 0.0;
  double mean_track_length = 0.0;
  // Observations in tracks over all segments seen in >= 2 views.
  double recall = 0.0;
};

// Image id k + 1 is view k of the scene.
TrackQuality EvaluateTracks(const SyntheticLineScene& scene,
                            const std::vector<LineTrackRecord>& tracks);

}  // namespace colmap_lidar
