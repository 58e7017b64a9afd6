// The PatchMatch engine (Schoenberger et al. 2016; Bleyer et al. 2011) on
// the CPU: each pixel of the reference view holds a plane hypothesis that
// is improved by red-black (checkerboard) propagation from its neighbours
// and by random refinement. Pixels of one colour are updated in parallel
// (row-parallel std::threads) while they read only pixels of the other
// colour, so the result does not depend on the thread count. Candidates per
// pixel and iteration: per direction (up, down, left, right) the plane of
// the lowest-cost neighbour among those 1, 3, 5, 7 pixels away (up to 15
// with far_propagation), and three refinements (perturbed
// depth and normal, perturbed normal, a random plane), with perturbation
// ranges halving every iteration.
//
// Costs come from PatchCostComputer (bilateral NCC, optionally the
// geometric term). The optional LIDAR prior adds
//   lidar_prior_weight * min(|d - d_prior| / (d_prior * tolerance), 1)
// at pixels with a prior depth (> 0).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "src/mvs/ncc_cost.h"
#include "src/mvs/patch_match_options.h"
#include "src/mvs/plane_map.h"

namespace colmap_lidar {

struct PatchMatchProblem {
  const PatchCostComputer* cost = nullptr;
  // Depth range of hypotheses (z, metres), 0 < depth_min < depth_max.
  float depth_min = 0.0f;
  float depth_max = 0.0f;
  // Per-pixel prior depth (0: none), row-major, or nullptr.
  const std::vector<float>* prior_depth = nullptr;
};

// Called after each iteration with the iteration index (0-based).
using PatchMatchCallback = std::function<void(int, const PlaneMap&)>;

// Runs `num_iterations` iterations on `state` (ref view size). Pixels whose
// depth is outside [depth_min, depth_max] or whose normal does not face the
// camera start from a random plane. On return depth/normal/cost are set for
// every pixel (cost = matching cost + prior term).
void RunPatchMatch(const PatchMatchProblem& problem,
                   const LidarPatchMatchOptions& options, int num_iterations,
                   uint64_t seed, PlaneMap* state,
                   const PatchMatchCallback& on_iteration = nullptr);

// A random plane per pixel (inverse depth uniform in the range, normal
// uniform on the hemisphere facing the camera): COLMAP's initialisation.
void RandomizePlaneMap(const MvsView& ref, float depth_min, float depth_max,
                       uint64_t seed, PlaneMap* state);

}  // namespace colmap_lidar
