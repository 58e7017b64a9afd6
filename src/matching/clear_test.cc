#include "src/matching/clear.h"

#include <chrono>
#include <map>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Every cluster holds at most one observation per view.
void ExpectOnePerView(const std::vector<int>& view_ids,
                      const std::vector<int>& cluster_ids) {
  std::set<std::pair<int, int>> seen;
  for (size_t i = 0; i < view_ids.size(); ++i) {
    EXPECT_TRUE(seen.emplace(cluster_ids[i], view_ids[i]).second)
        << "cluster " << cluster_ids[i] << " has two observations of view "
        << view_ids[i];
  }
}

TEST(Clear, RepairsAnInconsistentCycle) {
  // Three views, two objects each: observations 0, 2, 4 are object A and 1,
  // 3, 5 object B. The wrong edge 0-3 closes the cycle 0-3-1 (through 3-1 is
  // not an edge, but 3-5-1 is): 0 and 1, both of view 0, would be joined.
  const std::vector<int> view_ids = {0, 0, 1, 1, 2, 2};
  const std::vector<ClearEdge> edges = {{0, 2}, {2, 4}, {0, 4}, {1, 3},
                                        {3, 5}, {1, 5}, {0, 3}};
  const ClearResult result = RunClear(view_ids, edges, ClearOptions());
  ExpectOnePerView(view_ids, result.cluster_ids);
  EXPECT_EQ(result.num_clusters, 2);
  EXPECT_EQ(result.cluster_ids[0], result.cluster_ids[2]);
  EXPECT_EQ(result.cluster_ids[0], result.cluster_ids[4]);
  EXPECT_EQ(result.cluster_ids[1], result.cluster_ids[3]);
  EXPECT_EQ(result.cluster_ids[1], result.cluster_ids[5]);
  EXPECT_NE(result.cluster_ids[0], result.cluster_ids[1]);
  EXPECT_EQ(result.num_input_edges, 7u);
  EXPECT_EQ(result.num_removed_edges, 1u);
  EXPECT_EQ(result.num_components, 1);
}

TEST(Clear, SplitsAChainThatJoinsTwoObservationsOfOneView) {
  // Views 0..3; object A = {0 (v0), 1 (v1), 2 (v2)}, object B = {3 (v3), 4
  // (v0), 5 (v1)} with B complete; a wrong edge 2-3 links them and puts two
  // view-0 observations in one component.
  const std::vector<int> view_ids = {0, 1, 2, 3, 0, 1};
  const std::vector<ClearEdge> edges = {{0, 1}, {1, 2}, {0, 2}, {3, 4},
                                        {4, 5}, {3, 5}, {2, 3, 0.5}};
  const ClearResult result = RunClear(view_ids, edges, ClearOptions());
  ExpectOnePerView(view_ids, result.cluster_ids);
  EXPECT_EQ(result.cluster_ids[0], result.cluster_ids[1]);
  EXPECT_EQ(result.cluster_ids[0], result.cluster_ids[2]);
  EXPECT_EQ(result.cluster_ids[3], result.cluster_ids[4]);
  EXPECT_EQ(result.cluster_ids[3], result.cluster_ids[5]);
  EXPECT_NE(result.cluster_ids[0], result.cluster_ids[3]);
  EXPECT_EQ(result.num_removed_edges, 1u);
}

TEST(Clear, ConsistentGraphIsUnchanged) {
  // Two complete objects over 4 views and an isolated observation.
  const std::vector<int> view_ids = {0, 1, 2, 3, 0, 1, 2, 3, 2};
  std::vector<ClearEdge> edges;
  for (int object = 0; object < 2; ++object)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        edges.push_back({4 * object + a, 4 * object + b});
  const ClearResult result = RunClear(view_ids, edges, ClearOptions());
  EXPECT_EQ(result.num_clusters, 3);
  EXPECT_EQ(result.num_removed_edges, 0u);
  EXPECT_EQ(result.num_components, 3);
  for (int i = 1; i < 4; ++i) {
    EXPECT_EQ(result.cluster_ids[i], result.cluster_ids[0]);
    EXPECT_EQ(result.cluster_ids[4 + i], result.cluster_ids[4]);
  }
  EXPECT_NE(result.cluster_ids[8], result.cluster_ids[0]);
  EXPECT_NE(result.cluster_ids[8], result.cluster_ids[4]);
}

// Random multi-view data: num_objects universe objects, each view sees a
// random subset; true edges with probability p_edge between observations of
// one object, plus wrong edges.
struct RandomGraph {
  std::vector<int> view_ids;
  std::vector<int> object_ids;
  std::vector<ClearEdge> edges;
  std::vector<bool> edge_is_wrong;
};

RandomGraph MakeRandomGraph(int num_views, int num_objects, double p_seen,
                            double p_edge, int num_wrong_edges, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  RandomGraph graph;
  for (int v = 0; v < num_views; ++v) {
    for (int o = 0; o < num_objects; ++o) {
      if (uniform(rng) < p_seen) {
        graph.view_ids.push_back(v);
        graph.object_ids.push_back(o);
      }
    }
  }
  const int n = static_cast<int>(graph.view_ids.size());
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      if (graph.view_ids[a] != graph.view_ids[b] &&
          graph.object_ids[a] == graph.object_ids[b] && uniform(rng) < p_edge) {
        graph.edges.push_back({a, b, 0.5 + 0.5 * uniform(rng)});
        graph.edge_is_wrong.push_back(false);
      }
    }
  }
  for (int k = 0; k < num_wrong_edges;) {
    const int a = static_cast<int>(rng() % n);
    const int b = static_cast<int>(rng() % n);
    if (graph.view_ids[a] == graph.view_ids[b] ||
        graph.object_ids[a] == graph.object_ids[b]) {
      continue;
    }
    graph.edges.push_back({a, b, 0.3 + 0.4 * uniform(rng)});
    graph.edge_is_wrong.push_back(true);
    ++k;
  }
  return graph;
}

TEST(Clear, RemovesWrongEdgesOfRandomMultiViewGraphs) {
  // Over 5 random graphs (10 views, 15 objects, 60% of the true edges, 12
  // wrong edges each): clusters pure, wrong edges removed, true edges kept.
  int num_clusters = 0, num_pure = 0;
  int num_wrong = 0, wrong_kept = 0, num_true = 0, true_removed = 0;
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    const RandomGraph graph = MakeRandomGraph(/*num_views=*/10,
                                              /*num_objects=*/15, 0.8, 0.6,
                                              /*num_wrong_edges=*/12, seed);
    const ClearResult result =
        RunClear(graph.view_ids, graph.edges, ClearOptions());
    ExpectOnePerView(graph.view_ids, result.cluster_ids);
    std::map<int, std::set<int>> objects;
    std::map<int, int> sizes;
    for (size_t i = 0; i < graph.view_ids.size(); ++i) {
      objects[result.cluster_ids[i]].insert(graph.object_ids[i]);
      ++sizes[result.cluster_ids[i]];
    }
    for (const auto& [cluster, members] : objects) {
      if (sizes[cluster] < 2) continue;
      ++num_clusters;
      num_pure += members.size() == 1 ? 1 : 0;
    }
    for (size_t e = 0; e < graph.edges.size(); ++e) {
      const bool same = result.cluster_ids[graph.edges[e].observation1] ==
                        result.cluster_ids[graph.edges[e].observation2];
      if (graph.edge_is_wrong[e]) {
        ++num_wrong;
        wrong_kept += same ? 1 : 0;
      } else {
        ++num_true;
        true_removed += same ? 0 : 1;
      }
    }
  }
  std::cout << num_pure << " of " << num_clusters << " clusters pure, "
            << wrong_kept << " of " << num_wrong << " wrong edges kept, "
            << true_removed << " of " << num_true << " true edges removed"
            << std::endl;
  EXPECT_GE(num_pure, 0.97 * num_clusters);
  EXPECT_LE(wrong_kept, 0.05 * num_wrong);
  EXPECT_LE(true_removed, 0.1 * num_true);
}

TEST(Clear, CapsComponentSizeAndStaysConsistent) {
  // ~1000 observations in one component (wrong edges link all objects).
  const RandomGraph graph = MakeRandomGraph(/*num_views=*/40,
                                            /*num_objects=*/30, 0.85, 0.3,
                                            /*num_wrong_edges=*/200, 9);
  ClearOptions options;
  options.max_component_size = 300;
  const auto start = std::chrono::steady_clock::now();
  const ClearResult result = RunClear(graph.view_ids, graph.edges, options);
  const double seconds = std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - start)
                             .count();
  ASSERT_GT(graph.view_ids.size(), 900u);
  EXPECT_EQ(result.num_split_components, 1);
  EXPECT_GT(result.largest_component_size, 900);
  EXPECT_GT(result.num_removed_by_split, 0u);
  ExpectOnePerView(graph.view_ids, result.cluster_ids);
  std::map<int, int> sizes;
  for (const int cluster : result.cluster_ids) ++sizes[cluster];
  for (const auto& [cluster, size] : sizes) EXPECT_LE(size, 40);
  EXPECT_LT(seconds, 5.0);
}

TEST(Clear, ComponentOf500ObservationsIsFast) {
  const RandomGraph graph = MakeRandomGraph(/*num_views=*/25,
                                            /*num_objects=*/20, 1.0, 0.5,
                                            /*num_wrong_edges=*/60, 4);
  ASSERT_EQ(graph.view_ids.size(), 500u);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<int> clusters =
      ClearComponent(graph.view_ids, graph.edges, ClearOptions());
  const double seconds = std::chrono::duration<double>(
                             std::chrono::steady_clock::now() - start)
                             .count();
  ExpectOnePerView(graph.view_ids, clusters);
  EXPECT_LT(seconds, 1.0);
  std::cout << "CLEAR on 500 observations: " << seconds << " s" << std::endl;
}

TEST(Clear, RejectsBadInput) {
  EXPECT_THROW(RunClear({0, 1}, {{0, 2}}, ClearOptions()), Error);
  EXPECT_THROW(RunClear({0, 1}, {{0, 1, 1.5}}, ClearOptions()), Error);
  ClearOptions options;
  options.max_component_size = 1;
  EXPECT_FALSE(options.Check());
  // Same-view edges are ignored.
  const ClearResult result = RunClear({0, 0}, {{0, 1}}, ClearOptions());
  EXPECT_NE(result.cluster_ids[0], result.cluster_ids[1]);
}

}  // namespace
}  // namespace colmap_lidar
