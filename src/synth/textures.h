// Procedural surface textures of the synthetic scene, evaluated in surface
// coordinates so that they are exact at any distance (no texture maps, no
// resampling): (u, v) in metres along the surface, u horizontal and v up on
// vertical faces, (x, y) on horizontal ones. Colours are linear RGB albedo
// in [0, 1]. The patterns are chosen to give SIFT and LSD what real
// facades give them: brick and stone joints (many corners and lines),
// per-block colour variation and fine grain (distinctive descriptors),
// plaster that is nearly uniform (the featureless walls of the paper).
#pragma once

#include <cstdint>

#include <Eigen/Core>

#include "src/synth/scene_mesh.h"

namespace colmap_lidar {

// Surface coordinates of a world point on a face with the given unit
// normal: vertical faces use (horizontal tangent, z), others (x, y).
Eigen::Vector2d SurfaceCoordinates(const Eigen::Vector3d& point,
                                   const Eigen::Vector3d& normal);

// Linear RGB albedo of `material` at surface coordinates `uv`;
// `texture_seed` decorrelates the random variation of different surfaces
// that share a material.
Eigen::Vector3d MaterialAlbedo(Material material, const Eigen::Vector2d& uv,
                               uint32_t texture_seed);

// Smooth value noise in [0, 1] (C1 interpolation of hashed lattice values)
// and its fractal sum; exposed for tests.
double ValueNoise(double x, double y, uint32_t seed);
double FractalNoise(double x, double y, int octaves, uint32_t seed);

}  // namespace colmap_lidar
