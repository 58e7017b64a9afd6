// CLEAR (Fathian et al., "CLEAR: a consistent lifting, embedding, and
// alignment rectification algorithm for multiview data association", 2020)
// on a generic observation graph: the multi-view consistency step of the
// paper's section III-C (Fig. 6).
//
// Input: per observation the id of the view it belongs to, and undirected
// pairwise matches (edges) with weights in (0, 1]. Output: a cluster
// ("universe object") id per observation such that
//   - a cluster holds at most one observation per view, and
//   - the association is cycle-consistent by construction (two
//     observations are associated iff they share a cluster).
//
// Per connected component of the match graph (N observations):
//   1. The aggregate association matrix A = I + W (N x N, symmetric, unit
//      diagonal blocks per view, w_ab on matched pairs).
//   2. The normalised Laplacian L = I - D^-1/2 A D^-1/2 (D: row sums). The
//      number of objects m is the eigengap of L's spectrum,
//      m = argmax_k (lambda_{k+1} - lambda_k) over k >= the largest number of
//      observations one view has in the component (they must be distinct
//      objects).
//   3. Lifting / embedding: the m eigenvectors of L with the smallest
//      eigenvalues, one row per observation, rows normalised.
//   4. Alignment: m pivot rows (first the observations of the most crowded
//      view, then repeatedly the row least similar to the chosen pivots);
//      the similarity of every observation to every pivot; per view a
//      linear assignment (Hungarian) of its observations to distinct
//      objects maximising the similarity. Observations whose similarity to
//      their object is below min_assignment_similarity become objects of
//      their own.
// Components larger than max_component_size are first split with a
// size-capped maximum spanning forest (edges by decreasing weight, a union
// only while the merged part stays within the cap), so that the dense
// O(N^3) eigendecomposition never runs on more than the cap.
#pragma once

#include <cstddef>
#include <vector>

namespace colmap_lidar {

struct ClearOptions {
  // Largest component handed to the eigendecomposition, >= 2.
  int max_component_size = 500;
  // An observation whose embedding has a smaller cosine similarity with its
  // object's pivot is left on its own, [-1, 1].
  double min_assignment_similarity = 0.5;

  bool Check() const;
};

struct ClearEdge {
  int observation1 = -1;
  int observation2 = -1;
  // In (0, 1]; the strongest edges survive a split.
  double weight = 1.0;
};

struct ClearResult {
  // Per observation, in 0..num_clusters-1. Unmatched observations are
  // clusters of their own.
  std::vector<int> cluster_ids;
  int num_clusters = 0;
  // Connected components of the input graph, and how many exceeded the cap.
  int num_components = 0;
  int num_split_components = 0;
  int largest_component_size = 0;
  // Distinct input edges (self and same-view edges ignored), and those whose
  // observations ended in different clusters (removed by CLEAR or by a
  // split).
  size_t num_input_edges = 0;
  size_t num_removed_edges = 0;
  size_t num_removed_by_split = 0;
};

// view_ids[i] is the view of observation i (any integers). Edges refer to
// observations by index; an edge between two observations of the same
// view is ignored (counted as removed). Throws on an index out of range or
// a weight outside (0, 1].
ClearResult RunClear(const std::vector<int>& view_ids,
                     const std::vector<ClearEdge>& edges,
                     const ClearOptions& options);

// CLEAR on one connected component, without the size cap: local
// observation indices 0..N-1, returns local cluster ids 0..k-1. Exposed for
// tests and benchmarks.
std::vector<int> ClearComponent(const std::vector<int>& view_ids,
                                const std::vector<ClearEdge>& edges,
                                const ClearOptions& options);

}  // namespace colmap_lidar
