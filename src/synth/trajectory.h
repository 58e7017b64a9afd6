// The rig trajectory of the synthesiser (ground truth) and the noisy prior
// poses derived from it (the model is documented in synthesis_options.h).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/rigid3.h"
#include "src/synth/scene_presets.h"

namespace colmap_lidar {

// world_from_cam of a camera at `position` whose optical axis has the given
// yaw (from +x towards +y) and pitch (positive up), rolled by `roll` about
// the optical axis; world z is up, camera x right, y down, z forward.
// Angles in radians.
Rigid3d CameraPoseFromYawPitchRoll(const Eigen::Vector3d& position,
                                   double yaw, double pitch, double roll);

// `num_frames` ground-truth camera poses (world_from_cam) at equal arc
// length along the path (a closed path is split into num_frames equal
// parts, an open one includes both ends). Seeded hand-shake jitter: 3 cm
// horizontal and 2 cm vertical position noise, pitch/roll jitter of
// path.jitter_deg. Throws colmap_lidar::Error on a path with fewer than
// two waypoints or zero length.
// With path_fraction < 1 only the first path_fraction of the arc length is
// walked, as an open path (both ends included); path_fraction in (0, 1].
std::vector<Rigid3d> GenerateTrajectory(const WalkPath& path, int num_frames,
                                        uint64_t seed,
                                        double path_fraction = 1.0);

// Prior poses: the ground truth with per-axis Gaussian translation noise
// (sigma_t metres) on the camera centre and a rotation about a uniformly
// random axis by a Gaussian angle (sigma_r_deg degrees) applied in the
// world frame: R_prior = Exp(theta * axis) * R_gt.
std::vector<Rigid3d> PerturbPoses(const std::vector<Rigid3d>& world_from_cams,
                                  double sigma_t, double sigma_r_deg,
                                  uint64_t seed);

}  // namespace colmap_lidar
