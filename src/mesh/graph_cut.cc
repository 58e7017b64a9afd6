#include "src/mesh/graph_cut.h"

#include <cmath>

#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/property_map/property_map.hpp>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {

GraphCutResult ComputeMinStCut(const std::vector<float>& source_capacities,
                               const std::vector<float>& sink_capacities,
                               const std::vector<GraphCutEdge>& edges) {
  THROW_CHECK(source_capacities.size() == sink_capacities.size(),
              "Graph cut: source and sink capacities differ in length");
  const uint32_t num_nodes = static_cast<uint32_t>(source_capacities.size());
  const uint32_t source = num_nodes;
  const uint32_t sink = num_nodes + 1;
  auto check_capacity = [](float capacity) {
    THROW_CHECK(std::isfinite(capacity) && capacity >= 0,
                "Graph cut: invalid capacity " << capacity);
  };

  // Directed edges sorted by source node, each with its reverse: for every
  // node its graph edges, then source->node / node->sink pairs.
  // out_degree counts per node first.
  std::vector<uint32_t> degree(num_nodes + 2, 0);
  for (const GraphCutEdge& edge : edges) {
    THROW_CHECK(edge.from < num_nodes && edge.to < num_nodes &&
                    edge.from != edge.to,
                "Graph cut: bad edge " << edge.from << " -> " << edge.to);
    check_capacity(edge.capacity);
    check_capacity(edge.reverse_capacity);
    ++degree[edge.from];
    ++degree[edge.to];
  }
  for (uint32_t i = 0; i < num_nodes; ++i) {
    check_capacity(source_capacities[i]);
    check_capacity(sink_capacities[i]);
    if (source_capacities[i] > 0) {
      ++degree[source];
      ++degree[i];
    }
    if (sink_capacities[i] > 0) {
      ++degree[i];
      ++degree[sink];
    }
  }
  std::vector<uint64_t> row_begin(num_nodes + 3, 0);
  for (uint32_t i = 0; i < num_nodes + 2; ++i) {
    row_begin[i + 1] = row_begin[i] + degree[i];
  }
  const uint64_t num_edges = row_begin.back();
  THROW_CHECK(num_edges < 0xFFFFFFFFull,
              "Graph cut: " << num_edges << " edges exceed 2^32");
  // Edge e of node u lives at index row_begin[u] + (its rank), which is
  // also its edge_index in the CSR graph built from the sorted pairs below.
  std::vector<std::pair<uint32_t, uint32_t>> sorted_edges(num_edges);
  std::vector<float> capacity(num_edges);
  std::vector<uint32_t> reverse(num_edges);
  std::vector<uint64_t> fill(row_begin.begin(), row_begin.end() - 1);
  auto add_pair = [&](uint32_t u, uint32_t v, float cap_uv, float cap_vu) {
    const uint64_t e_uv = fill[u]++;
    const uint64_t e_vu = fill[v]++;
    sorted_edges[e_uv] = {u, v};
    sorted_edges[e_vu] = {v, u};
    capacity[e_uv] = cap_uv;
    capacity[e_vu] = cap_vu;
    reverse[e_uv] = static_cast<uint32_t>(e_vu);
    reverse[e_vu] = static_cast<uint32_t>(e_uv);
  };
  for (const GraphCutEdge& edge : edges) {
    add_pair(edge.from, edge.to, edge.capacity, edge.reverse_capacity);
  }
  for (uint32_t i = 0; i < num_nodes; ++i) {
    if (source_capacities[i] > 0) add_pair(source, i, source_capacities[i], 0);
    if (sink_capacities[i] > 0) add_pair(i, sink, sink_capacities[i], 0);
  }

  using Graph = boost::compressed_sparse_row_graph<
      boost::directedS, boost::no_property, boost::no_property,
      boost::no_property, uint32_t, uint32_t>;
  using Edge = boost::graph_traits<Graph>::edge_descriptor;
  Graph graph(boost::edges_are_sorted, sorted_edges.begin(),
              sorted_edges.end(), num_nodes + 2, num_edges);
  std::vector<Edge> reverse_edges(num_edges);
  for (uint64_t e = 0; e < num_edges; ++e) {
    reverse_edges[e] = Edge(sorted_edges[e].second, reverse[e]);
  }
  std::vector<std::pair<uint32_t, uint32_t>>().swap(sorted_edges);
  std::vector<uint32_t>().swap(reverse);

  std::vector<float> residual(num_edges, 0.f);
  std::vector<Edge> predecessors(num_nodes + 2);
  std::vector<boost::default_color_type> colors(num_nodes + 2);
  std::vector<uint32_t> distances(num_nodes + 2, 0);
  const auto edge_index = boost::get(boost::edge_index, graph);
  const auto vertex_index = boost::get(boost::vertex_index, graph);
  GraphCutResult result;
  result.max_flow = boost::boykov_kolmogorov_max_flow(
      graph, boost::make_iterator_property_map(capacity.begin(), edge_index),
      boost::make_iterator_property_map(residual.begin(), edge_index),
      boost::make_iterator_property_map(reverse_edges.begin(), edge_index),
      boost::make_iterator_property_map(predecessors.begin(), vertex_index),
      boost::make_iterator_property_map(colors.begin(), vertex_index),
      boost::make_iterator_property_map(distances.begin(), vertex_index),
      vertex_index, source, sink);
  // Boost colours the final source tree black, the sink tree white and
  // free nodes gray. The sink tree is every node that still reaches the sink
  // in the residual graph, so "not white" is also a minimum cut: the one
  // with the largest source side. Unconstrained nodes (e.g. infinite cells
  // no ray reached) thus count as outside.
  result.is_source_side.resize(num_nodes);
  for (uint32_t i = 0; i < num_nodes; ++i) {
    result.is_source_side[i] = colors[i] != boost::white_color;
  }
  return result;
}

}  // namespace colmap_lidar
