// The scene presets of the synthesiser: triangle meshes with materials,
// ground-truth crease edges, where the survey tripods stand and the path
// the handheld rig walks. The geometry is fixed per preset (it does not
// depend on SynthesisOptions::seed), so datasets generated with different
// seeds share the same reference.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "src/synth/scene_mesh.h"

namespace colmap_lidar {

// Where and how the rig is carried: a polyline in the ground plane walked
// at constant speed, the camera `look_yaw_offset_deg` to the left (positive)
// or right (negative) of the walking direction, oscillating by
// `yaw_amplitude_deg` with a period of `yaw_period_frames` frames.
struct WalkPath {
  std::vector<Eigen::Vector2d> waypoints;
  bool closed = true;
  double height_m = 1.5;
  double look_yaw_offset_deg = 0.0;
  double yaw_amplitude_deg = 10.0;
  double yaw_period_frames = 9.0;
  // Mean upward pitch of the camera; pitch and roll also get Gaussian
  // jitter of jitter_deg (hand shake).
  double pitch_deg = 6.0;
  double jitter_deg = 1.5;
};

struct SynthScene {
  std::string name;
  SceneMesh mesh;
  std::vector<CreaseEdge> crease_edges;
  // Candidate survey tripod positions (x, y), in order of preference.
  std::vector<Eigen::Vector2d> survey_stations;
  WalkPath path;
};

// "quad": a 30 x 20 m courtyard (x in [-15, 15], y in [-10, 10]) enclosed
// by ten buildings of 8-15 m in brick, stone and plaster with recessed
// windows and doors, paved ground, a tree, a planter, a bench, bollards, a
// lamp post and a plinth; the rig walks an ellipse (semi-axes 9.5 x 5.5 m)
// counter-clockwise looking outwards-forwards at the walls.
SynthScene BuildQuadScene();
// "street": an 80 m long, 12 m wide street (x in [-40, 40], facades at
// y = +-6) lined by buildings of 9-18 m, with parked cars (boxes), trees
// and bollards; the rig walks 50 m along it, sweeping its view from one
// side to the other.
SynthScene BuildStreetScene();
// "corridor": a 64 m straight walk down the middle of a 6 m wide alley
// (x in [-40, 40], walls at y = +-3, 14-17 m high, few openings), looking
// forward +-8 degrees; the roll about the straight path is weakly observed.
SynthScene BuildCorridorScene();
// Throws colmap_lidar::Error on an unknown preset name.
SynthScene BuildScene(const std::string& preset);

}  // namespace colmap_lidar
