#include "src/mesh/graph_cut.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

TEST(GraphCut, ChainCutsAtTheWeakestEdge) {
  // source -> 0 -> 1 -> 2 -> 3 -> sink; the 1 -> 2 edge is the weakest.
  const std::vector<float> source = {10, 0, 0, 0};
  const std::vector<float> sink = {0, 0, 0, 10};
  const std::vector<GraphCutEdge> edges = {
      {0, 1, 5, 0}, {1, 2, 2, 0}, {2, 3, 7, 0}};
  const GraphCutResult result = ComputeMinStCut(source, sink, edges);
  EXPECT_NEAR(result.max_flow, 2.0, 1e-6);
  EXPECT_EQ(result.is_source_side, (std::vector<bool>{true, true, false, false}));
}

TEST(GraphCut, DirectedCapacitiesMatter) {
  // Only the reverse direction has capacity: no flow from 0 to 1.
  const GraphCutResult result =
      ComputeMinStCut({3, 0}, {0, 3}, {{0, 1, 0, 100}});
  EXPECT_NEAR(result.max_flow, 0.0, 1e-6);
  EXPECT_TRUE(result.is_source_side[0]);
  EXPECT_FALSE(result.is_source_side[1]);
}

TEST(GraphCut, TerminalWeightsDecideIsolatedNodesAndFreeNodesAreSource) {
  // Node 0 prefers sink (cost 1 to be source vs 4 to be sink)... node 2 has
  // no constraints at all and counts as source side.
  const GraphCutResult result =
      ComputeMinStCut({1, 4, 0}, {4, 1, 0}, {});
  EXPECT_NEAR(result.max_flow, 2.0, 1e-6);
  EXPECT_FALSE(result.is_source_side[0]);
  EXPECT_TRUE(result.is_source_side[1]);
  EXPECT_TRUE(result.is_source_side[2]);
}

TEST(GraphCut, RejectsBadInput) {
  EXPECT_THROW(ComputeMinStCut({1}, {1, 2}, {}), Error);
  EXPECT_THROW(ComputeMinStCut({1, 1}, {1, 1}, {{0, 2, 1, 1}}), Error);
  EXPECT_THROW(ComputeMinStCut({-1, 1}, {1, 1}, {}), Error);
}

}  // namespace
}  // namespace colmap_lidar
