#include "src/matching/clear.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <unordered_map>
#include <utility>

#include <Eigen/Dense>

#include "colmap_ext/util/logging.h"
#include "src/matching/linear_assignment.h"

namespace colmap_lidar {

bool ClearOptions::Check() const {
  if (max_component_size < 2) {
    LOG(ERROR) << "max_component_size must be >= 2, got "
               << max_component_size;
    return false;
  }
  if (!(min_assignment_similarity >= -1.0 &&
        min_assignment_similarity <= 1.0)) {
    LOG(ERROR) << "min_assignment_similarity must be in [-1, 1], got "
               << min_assignment_similarity;
    return false;
  }
  return true;
}

namespace {

class UnionFind {
 public:
  explicit UnionFind(int n) : parent_(n), size_(n, 1) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int Find(int x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  int Size(int x) { return size_[Find(x)]; }
  void Union(int a, int b) {
    a = Find(a);
    b = Find(b);
    if (a == b) return;
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
  }

 private:
  std::vector<int> parent_;
  std::vector<int> size_;
};

// The number of objects from the eigengap of the ascending spectrum `lambda`
// of the normalised Laplacian, at least `min_objects`.
int EstimateNumObjects(const Eigen::VectorXd& lambda, int min_objects) {
  const int n = static_cast<int>(lambda.size());
  if (min_objects >= n) return n;
  int best_k = min_objects;
  double best_gap = -1.0;
  for (int k = min_objects; k < n; ++k) {
    const double gap = lambda(k) - lambda(k - 1);
    if (gap > best_gap + 1e-12) {
      best_gap = gap;
      best_k = k;
    }
  }
  return best_k;
}

}  // namespace

std::vector<int> ClearComponent(const std::vector<int>& view_ids,
                                const std::vector<ClearEdge>& edges,
                                const ClearOptions& options) {
  const int n = static_cast<int>(view_ids.size());
  if (n == 0) return {};
  if (n == 1) return {0};

  // Observations per view; the most crowded view bounds m from below.
  std::map<int, std::vector<int>> view_observations;
  for (int i = 0; i < n; ++i) view_observations[view_ids[i]].push_back(i);
  int min_objects = 0;
  const std::vector<int>* crowded_view = nullptr;
  for (const auto& [view_id, observations] : view_observations) {
    if (static_cast<int>(observations.size()) > min_objects) {
      min_objects = static_cast<int>(observations.size());
      crowded_view = &observations;
    }
  }

  // 1. Aggregate association matrix; same-view pairs stay 0 (the diagonal
  // blocks are identities).
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n);
  for (const ClearEdge& edge : edges) {
    const int a = edge.observation1;
    const int b = edge.observation2;
    if (a == b || view_ids[a] == view_ids[b]) continue;
    A(a, b) = A(b, a) = std::max(A(a, b), edge.weight);
  }

  // 2. Normalised Laplacian and its spectrum (ascending).
  const Eigen::VectorXd inv_sqrt_degree =
      A.rowwise().sum().cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd laplacian =
      Eigen::MatrixXd::Identity(n, n) -
      inv_sqrt_degree.asDiagonal() * A * inv_sqrt_degree.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(laplacian);
  THROW_CHECK(solver.info() == Eigen::Success,
              "CLEAR: eigendecomposition failed on a component of " << n
                                                                    << " observations");
  const int m = EstimateNumObjects(solver.eigenvalues(), min_objects);

  // 3. Embedding: rows of the m leading eigenvectors, normalised.
  Eigen::MatrixXd embedding = solver.eigenvectors().leftCols(m);
  for (int i = 0; i < n; ++i) {
    const double norm = embedding.row(i).norm();
    if (norm > 1e-12) embedding.row(i) /= norm;
  }

  // 4a. Pivots: the crowded view's observations are distinct objects; then
  // farthest-first on cosine similarity.
  std::vector<int> pivots = *crowded_view;
  std::vector<double> max_similarity(n, -2.0);
  auto add_pivot_similarities = [&](int pivot) {
    const Eigen::VectorXd similarity = embedding * embedding.row(pivot).transpose();
    for (int i = 0; i < n; ++i) {
      max_similarity[i] = std::max(max_similarity[i], similarity(i));
    }
  };
  for (const int pivot : pivots) add_pivot_similarities(pivot);
  while (static_cast<int>(pivots.size()) < m) {
    int next = -1;
    for (int i = 0; i < n; ++i) {
      if (std::find(pivots.begin(), pivots.end(), i) != pivots.end()) continue;
      if (next < 0 || max_similarity[i] < max_similarity[next]) next = i;
    }
    pivots.push_back(next);
    add_pivot_similarities(next);
  }
  Eigen::MatrixXd pivot_rows(m, m);
  for (int k = 0; k < m; ++k) pivot_rows.row(k) = embedding.row(pivots[k]);
  const Eigen::MatrixXd similarity = embedding * pivot_rows.transpose();

  // 4b. Per view, distinct objects by maximum total similarity.
  std::vector<int> object_of(n, -1);
  for (const auto& [view_id, observations] : view_observations) {
    Eigen::MatrixXd cost(observations.size(), m);
    for (size_t r = 0; r < observations.size(); ++r) {
      cost.row(r) = -similarity.row(observations[r]);
    }
    const std::vector<int> assignment = SolveLinearAssignment(cost);
    for (size_t r = 0; r < observations.size(); ++r) {
      object_of[observations[r]] = assignment[r];
    }
  }

  // Weakly assigned observations become their own objects; then relabel
  // densely in order of first appearance.
  int next_object = m;
  for (int i = 0; i < n; ++i) {
    if (similarity(i, object_of[i]) < options.min_assignment_similarity) {
      object_of[i] = next_object++;
    }
  }
  std::unordered_map<int, int> relabel;
  std::vector<int> cluster_ids(n);
  for (int i = 0; i < n; ++i) {
    const auto [it, inserted] =
        relabel.emplace(object_of[i], static_cast<int>(relabel.size()));
    cluster_ids[i] = it->second;
  }
  return cluster_ids;
}

ClearResult RunClear(const std::vector<int>& view_ids,
                     const std::vector<ClearEdge>& edges,
                     const ClearOptions& options) {
  THROW_CHECK(options.Check(), "Invalid ClearOptions");
  const int n = static_cast<int>(view_ids.size());
  ClearResult result;

  // Distinct undirected edges, strongest weight per pair.
  std::map<std::pair<int, int>, double> edge_weights;
  for (const ClearEdge& edge : edges) {
    THROW_CHECK(edge.observation1 >= 0 && edge.observation1 < n &&
                    edge.observation2 >= 0 && edge.observation2 < n,
                "CLEAR: edge (" << edge.observation1 << ", "
                                << edge.observation2
                                << ") out of range for " << n
                                << " observations");
    THROW_CHECK(edge.weight > 0.0 && edge.weight <= 1.0,
                "CLEAR: edge weight " << edge.weight << " not in (0, 1]");
    if (edge.observation1 == edge.observation2) continue;
    const std::pair<int, int> key(std::min(edge.observation1, edge.observation2),
                                  std::max(edge.observation1, edge.observation2));
    double& weight = edge_weights[key];
    weight = std::max(weight, edge.weight);
  }
  result.num_input_edges = edge_weights.size();
  std::vector<ClearEdge> unique_edges;
  unique_edges.reserve(edge_weights.size());
  for (const auto& [key, weight] : edge_weights) {
    if (view_ids[key.first] == view_ids[key.second]) continue;
    unique_edges.push_back({key.first, key.second, weight});
  }

  // Connected components.
  UnionFind components(n);
  for (const ClearEdge& edge : unique_edges) {
    components.Union(edge.observation1, edge.observation2);
  }
  // Parts handed to CLEAR: components within the cap as they are; larger
  // ones through the size-capped maximum spanning forest.
  std::vector<ClearEdge> sorted_edges = unique_edges;
  std::stable_sort(sorted_edges.begin(), sorted_edges.end(),
                   [](const ClearEdge& a, const ClearEdge& b) {
                     return a.weight > b.weight;
                   });
  UnionFind parts(n);
  std::map<int, bool> component_is_split;
  for (int i = 0; i < n; ++i) {
    const int root = components.Find(i);
    if (component_is_split.count(root)) continue;
    const int size = components.Size(root);
    component_is_split[root] = size > options.max_component_size;
    result.largest_component_size = std::max(result.largest_component_size, size);
  }
  result.num_components = static_cast<int>(component_is_split.size());
  for (const auto& [root, split] : component_is_split) {
    result.num_split_components += split ? 1 : 0;
  }
  for (const ClearEdge& edge : sorted_edges) {
    const int a = edge.observation1;
    const int b = edge.observation2;
    if (component_is_split[components.Find(a)]) {
      if (parts.Find(a) == parts.Find(b) ||
          parts.Size(a) + parts.Size(b) > options.max_component_size) {
        continue;
      }
    }
    parts.Union(a, b);
  }

  // Group observations and edges by part.
  std::unordered_map<int, int> part_index;
  std::vector<std::vector<int>> part_observations;
  std::vector<int> local_index(n, -1);
  for (int i = 0; i < n; ++i) {
    const auto [it, inserted] = part_index.emplace(
        parts.Find(i), static_cast<int>(part_observations.size()));
    if (inserted) part_observations.emplace_back();
    local_index[i] = static_cast<int>(part_observations[it->second].size());
    part_observations[it->second].push_back(i);
  }
  std::vector<std::vector<ClearEdge>> part_edges(part_observations.size());
  for (const ClearEdge& edge : unique_edges) {
    const int part1 = part_index.at(parts.Find(edge.observation1));
    const int part2 = part_index.at(parts.Find(edge.observation2));
    if (part1 != part2) {
      ++result.num_removed_by_split;
      continue;
    }
    part_edges[part1].push_back({local_index[edge.observation1],
                                 local_index[edge.observation2], edge.weight});
  }

  result.cluster_ids.assign(n, -1);
  for (size_t p = 0; p < part_observations.size(); ++p) {
    const std::vector<int>& observations = part_observations[p];
    std::vector<int> local_view_ids(observations.size());
    for (size_t i = 0; i < observations.size(); ++i) {
      local_view_ids[i] = view_ids[observations[i]];
    }
    const std::vector<int> local_clusters =
        ClearComponent(local_view_ids, part_edges[p], options);
    const int offset = result.num_clusters;
    int num_local = 0;
    for (size_t i = 0; i < observations.size(); ++i) {
      result.cluster_ids[observations[i]] = offset + local_clusters[i];
      num_local = std::max(num_local, local_clusters[i] + 1);
    }
    result.num_clusters += num_local;
  }

  for (const auto& [key, weight] : edge_weights) {
    if (result.cluster_ids[key.first] != result.cluster_ids[key.second]) {
      ++result.num_removed_edges;
    }
  }
  return result;
}

}  // namespace colmap_lidar
