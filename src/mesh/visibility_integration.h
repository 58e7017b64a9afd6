// Visibility integration into the cells of the Delaunay triangulation
// (Labatut, Pons, Keriven 2009, "Robust and efficient surface
// reconstruction from range data", Sec. 4; Amblard et al. Sec. III-E).
//
// Every ray from a sensor centre (camera centre or LIDAR origin) to an
// observed vertex says that the space in between is empty. The ray is walked
// through the tetrahedra, from the vertex towards the sensor:
// - each facet it crosses gets free-space weight alpha * (1 - exp(-d^2 /
//   (2 sigma^2))) on the directed graph edge from the cell nearer the sensor
//   into the cell nearer the point (d = distance of the crossing from the
//   point, so the facets right at the point stay cheap to cut);
// - the cell that contains the sensor (or the first cell outside the convex
//   hull) gets source ("outside") weight alpha; with a length cap, the walk
//   stops that far in front of the point and its cell gets the weight;
// - the cell behind_distance_factor * sigma behind the point, on the
//   prolonged ray, gets sink ("inside") weight alpha (the last finite cell
//   if the prolonged ray leaves the convex hull on the way; the infinite
//   cell if it leaves the hull right at the point).
// sigma = distance_sigma_factor * the 25th percentile of the edge lengths.
// Rays from several input points merged into one vertex are summed, so each
// (vertex, sensor) pair is walked once.
//
// The walk (src/mesh/ray_walker.h) is a straight-line walk with CGAL's exact
// orientation predicates on a compact, spatially ordered copy of the
// triangulation; rays that pass exactly through an edge or vertex take one
// of the adjacent facets. The vertices are processed along a Hilbert curve
// in chunks shared by the threads, a chunk's rays sensor by sensor (nearly
// parallel rays in a row cross mostly the same cells); the sums are in
// fixed point, so the weights depend neither on the number of threads nor
// on the order of the rays.
#pragma once

#include <atomic>
#include <memory>
#include <vector>

#include "src/mesh/delaunay_triangulation.h"
#include "src/mesh/meshing_input.h"

namespace colmap_lidar {

struct VisibilityIntegrationOptions {
  // sigma of the free-space weight, relative to the 25th percentile of the
  // triangulation's edge lengths (> 0).
  double distance_sigma_factor = 1.0;
  // Where the inside weight goes behind the point, in units of sigma (> 0).
  double behind_distance_factor = 0.25;
  // Free space is carved at most this many sigma in front of the point;
  // the outside weight goes to the cell where the carving stops (or that
  // holds the sensor, on a shorter ray). 0 carves the whole ray. Whole rays
  // make the walks and the max-flow slow: every unit of flow then starts in
  // the few cells that hold the sensors (20 on KITTI, where the car barely
  // moves; one holds 19 % of the weight) and runs down a ray to the
  // surface. Beyond the cap nothing is carved, and such space has no
  // evidence either way; the cut keeps it outside unless inside cells
  // enclose it. 100 sigma is 4-7 m on the benchmark scenes (sigma 4-6.5
  // cm); measured in docs/benchmarks/matrix.md ("Free-space length cap").
  // >= 0.
  double max_free_space_length_factor = 100.0;
  // sigma itself, metres, when > 0 (then distance_sigma_factor is unused):
  // the tiles of one scene share their first tile's (tiled_meshing.h), so
  // that both sides of a seam weigh the rays alike. 0: from the edges.
  double distance_sigma_m = 0;
  // Worker threads; <= 0 uses all cores.
  int num_threads = -1;

  bool Check() const;
};

// Weights of the s-t graph whose nodes are the cells (by cell index).
struct CellGraphWeights {
  std::vector<float> source;  // Outside evidence per cell.
  std::vector<float> sink;    // Inside evidence per cell.
  // facet_in[4 * c + k]: capacity of the edge from cell c's neighbour k into
  // cell c.
  std::vector<float> facet_in;
  double distance_sigma = 0;
  size_t num_rays = 0;
  // Walks stopped by the step limit (numerical trouble); should be 0.
  size_t num_failed_walks = 0;
};

CellGraphWeights IntegrateVisibility(
    const VisibilityIntegrationOptions& options, const MeshingInput& input,
    const MeshingTriangulation& triangulation);

// The 25th percentile of the finite edge lengths (of at most ~1M sampled
// edges), on num_threads threads (<= 0: all cores).
double LowerQuartileEdgeLength(const MeshingTriangulation& triangulation,
                               int num_threads = -1);

// Effective number of threads for `num_threads` (<= 0: all cores).
int EffectiveNumThreads(int num_threads);

}  // namespace colmap_lidar
