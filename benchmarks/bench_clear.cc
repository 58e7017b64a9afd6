// Time of CLEAR (src/matching/clear.h) on one connected component of line
// observations, the size the association hands it per component (issue 5:
// "CLEAR on a component of 500 observations well under 1 s"). Synthetic
// graph with fixed seeds: objects seen in 60 % of the views, every pair of
// observations of one object matched, and 5 % of the edges wrong (between
// observations of different objects, the inconsistent cycles CLEAR
// repairs). Sizes above ClearOptions::max_component_size (500) exercise the
// split. Run: build/benchmarks/bench_clear.
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "src/matching/clear.h"

namespace colmap_lidar {
namespace {

struct Graph {
  std::vector<int> view_ids;
  std::vector<ClearEdge> edges;
};

// About `num_observations` observations of objects over 30 views.
Graph MakeGraph(int num_observations) {
  constexpr int kNumViews = 30;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Graph graph;
  std::vector<int> object_of;
  for (int object = 0;
       static_cast<int>(graph.view_ids.size()) < num_observations; ++object) {
    std::vector<int> observations;
    for (int view = 0; view < kNumViews; ++view) {
      if (uniform(rng) < 0.6) {
        observations.push_back(static_cast<int>(graph.view_ids.size()));
        graph.view_ids.push_back(view);
        object_of.push_back(object);
      }
    }
    for (size_t a = 0; a < observations.size(); ++a) {
      for (size_t b = a + 1; b < observations.size(); ++b) {
        graph.edges.push_back(
            {observations[a], observations[b], 0.6 + 0.4 * uniform(rng)});
      }
    }
  }
  const size_t num_wrong = graph.edges.size() / 20;
  std::uniform_int_distribution<int> pick(
      0, static_cast<int>(graph.view_ids.size()) - 1);
  for (size_t added = 0; added < num_wrong;) {
    const int a = pick(rng);
    const int b = pick(rng);
    if (object_of[a] != object_of[b] &&
        graph.view_ids[a] != graph.view_ids[b]) {
      graph.edges.push_back({a, b, 0.6 + 0.4 * uniform(rng)});
      ++added;
    }
  }
  return graph;
}

void BM_Clear(benchmark::State& state) {
  const Graph graph = MakeGraph(static_cast<int>(state.range(0)));
  const ClearOptions options;
  ClearResult result;
  for (auto _ : state) {
    result = RunClear(graph.view_ids, graph.edges, options);
    benchmark::DoNotOptimize(result.num_clusters);
  }
  state.counters["observations"] = static_cast<double>(graph.view_ids.size());
  state.counters["edges"] = static_cast<double>(graph.edges.size());
  state.counters["clusters"] = result.num_clusters;
  state.counters["removed_edges"] = static_cast<double>(result.num_removed_edges);
}
BENCHMARK(BM_Clear)->Arg(100)->Arg(250)->Arg(500)->Arg(1000)->Arg(2000)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace colmap_lidar

BENCHMARK_MAIN();
