// The memory guard of the Delaunay mesher: a voxel-grid decimation of the
// meshing input to at most a given number of points. Each occupied voxel
// keeps its heaviest point (largest ray weight; line samples win ties), with
// the union of the sensors of all points in the voxel.
#pragma once

#include <cstddef>

#include "src/mesh/meshing_input.h"

namespace colmap_lidar {

// Returns the voxel size used (metres), 0 when the input already fits.
// Grows the voxel by 25 % per attempt until at most `max_num_points`
// voxels are occupied.
double DecimateMeshingInput(size_t max_num_points, MeshingInput* input);

}  // namespace colmap_lidar
