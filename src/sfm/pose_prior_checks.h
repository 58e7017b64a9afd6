// Poses against their LIDAR priors, for lidar_mapper (src/sfm/
// lidar_mapper.h): the model of the prior poses (the "priors"
// initialisation and the fallback pose of images no model registered), and
// the test of the guards whether a pose lies inside the region of its
// prior's noise.
#pragma once

#include <Eigen/Geometry>

#include "colmap_ext/database/database.h"
#include "colmap_ext/scene/reconstruction.h"
#include "colmap_ext/scene/rigid3.h"

namespace colmap_lidar {

// How far a pose lies from its prior: 0 inside the 99.9 % region of the
// prior noise, 1 outside it, 2 outside the 1 - 1e-6 region. Centre: chi-square
// with 3 degrees of freedom (16.27, 30.66); rotation: the angle in RMS angles
// as a Gaussian (3.29, 4.89), a test that also holds (more loosely) for a
// Gaussian rotation vector.
int PriorOutlierLevel(const Rigid3d& cam_from_world, const Rigid3d& prior,
                      double position_sigma_m, double rotation_rms_deg);

// Per-axis rotation-vector sigma of priors whose RMS angle is
// rms_angle_deg (isotropic error: the squared angle splits over 3 axes).
double PerAxisRotationSigmaDeg(double rms_angle_deg);

// Rotation angle between two rotations, degrees.
double RotationAngleDeg(const Eigen::Quaterniond& a,
                        const Eigen::Quaterniond& b);

// Cameras of the database plus one image per database image with a prior
// pose, at that pose, without points: the starting model of the "priors"
// initialisation and the fallback pose of images the mapper missed.
Reconstruction PriorModel(const Database& database);

}  // namespace colmap_lidar
