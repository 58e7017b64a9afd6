// Minimum s-t cut of a directed graph with terminal capacities, by
// Boost.Graph's Boykov-Kolmogorov max-flow (Boykov and Kolmogorov 2004) on a
// compressed sparse row graph, to keep memory near 24 bytes per directed
// edge. Used to label the Delaunay cells inside (sink) / outside (source).
#pragma once

#include <cstdint>
#include <vector>

namespace colmap_lidar {

struct GraphCutEdge {
  uint32_t from = 0;
  uint32_t to = 0;
  float capacity = 0;          // from -> to
  float reverse_capacity = 0;  // to -> from
};

struct GraphCutResult {
  double max_flow = 0;
  // true: node is on the source side of the minimum cut. Of all minimum
  // cuts, the one with the largest source side (nodes that cannot reach the
  // sink in the residual graph).
  std::vector<bool> is_source_side;
};

// Nodes 0..n-1 with capacities source -> node and node -> sink; capacities
// must be finite and >= 0. Each pair of nodes should appear at most once in
// `edges` (both directions in one entry). Throws on bad input.
GraphCutResult ComputeMinStCut(const std::vector<float>& source_capacities,
                               const std::vector<float>& sink_capacities,
                               const std::vector<GraphCutEdge>& edges);

}  // namespace colmap_lidar
