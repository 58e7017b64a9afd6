// Step 4 of lidar_mapper (src/sfm/lidar_mapper.h): the initial poses, from
// the LIDAR pose graph (init_method "lidar_graph"), from stock mapper's or
// a given model aligned robustly to the priors ("mapper", "model", with the
// fallback to the priors when no model agrees with them), or the priors
// themselves ("priors").
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "colmap_ext/database/database.h"
#include "colmap_ext/runner/colmap_runner.h"
#include "colmap_ext/scene/reconstruction.h"
#include "src/optim/line_bundle_adjustment.h"
#include "src/sfm/lidar_mapper.h"

namespace colmap_lidar {

struct InitialPoses {
  // Every image with a prior, at its initial pose (without points).
  Reconstruction model;
  // The first iteration adjusts points only (lines are associated from the
  // second on): init_method "priors" and the fallback to it.
  bool points_only_first = false;
  // Images registered by an accepted initial model outside its consensus:
  // their poses are wrong (or their part of the model is) and their prior
  // poses are too coarse to triangulate or associate with, so they stay at
  // their prior pose, out of triangulation and association, and only their
  // prior residual enters the adjustment (measured: keeping them in drags
  // the consensus images back to prior-level errors).
  std::unordered_map<image_t, bool> held_out;
  // init_method lidar_graph: its accepted edges, terms of every adjustment.
  std::vector<RelativePoseEdge> lidar_edges;
};

// The initialisation of options.init_method, starting from `prior_model`
// (PriorModel of the database; `priors` its poses by image). Intermediate
// models go to work_path (<workspace>/sparse/lidar_mapper). Fills the
// summary's init_used, num_initial_images, init_alignment and, by method,
// num_lidar_edges or prior_alignment_rms_m, num_init_outliers and
// num_pending_images.
InitialPoses InitializePoses(const ColmapRunner& colmap,
                             const LidarMapperPaths& paths,
                             const LidarMapperOptions& options,
                             const std::string& work_path,
                             const Database& database,
                             const Reconstruction& prior_model,
                             const std::unordered_map<image_t, Rigid3d>& priors,
                             LidarMapperSummary* summary);

}  // namespace colmap_lidar
