// The scene presets of the synthesiser: triangle meshes with materials,
// ground-truth crease edges, where the survey tripods stand and the path
// the handheld rig walks. One file per preset (scene_<preset>.cc), made of
// the shared blocks of scene_blocks.h; BuildScene dispatches by name. The
// geometry is fixed per preset and length factor (it does not depend on
// SynthesisOptions::seed), so datasets generated with different seeds share
// the same reference.
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
  // Borders of painted marks on the ground (texture edges, not creases);
  // empty for scenes without paint.
  std::vector<PaintEdge> paint_edges;
  // What departs from the common conventions (e.g. surfaces above z = 0
  // that a user might take for the ground); empty if nothing.
  std::string notes;
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
// "street_bent": a 12 m wide street canyon of two straight 45 m legs
// meeting at the origin with a 28 degree bend to the left (leg 1 along +x
// for x in [-45, 0], leg 2 along (cos 28, sin 28)); repetitive brick
// facades (same window grid) with protruding window frames and sills;
// 2.5 m raised pavements (0.13 m kerbs, crease edges along the kerbs) on
// both sides of a 7 m asphalt road with painted lane lines (edge lines,
// dashed centre line, a zebra crossing; their borders are paint edges);
// benches, bollards, trees and parked cars (boxes). The rig walks 70 m on
// the road through the bend (rounded, radius 12 m), sweeping +-45 deg.
// length_factor >= 1 makes both legs that many times longer (facades,
// pavements and paint follow; the furniture and cars repeat every 90 m;
// the walk still ends 10 m before each end; the survey stations then stand
// every 18 m along the centre line, then every 18 m between those): the
// same street, longer, for the scale benchmark (issue 19). Throws below 1.
SynthScene BuildStreetBentScene(double length_factor = 1.0);
// "square": an open, paved 50 x 40 m square (x in [-25, 25], y in
// [-20, 20]) with buildings on three sides only (west, north, half of the
// south; the east opens onto more paving), so the ground dominates the
// views; a kiosk, benches, bollards, trees, a fountain basin and lamp posts.
// The rig walks a 46 m S-curve across it from the open east side towards
// the south-west, looking forward +-45 deg.
SynthScene BuildSquareScene();

// The preset names, e.g. "quad, street, corridor, street_bent or square".
const std::vector<std::string>& ScenePresetNames();
std::string ScenePresetNamesText();
bool IsKnownScenePreset(const std::string& preset);
// Throws colmap_lidar::Error on an unknown preset name, and on a
// length_factor other than 1 for a preset that has none (all but
// street_bent).
SynthScene BuildScene(const std::string& preset, double length_factor = 1.0);

}  // namespace colmap_lidar
