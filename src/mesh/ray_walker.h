// A straight-line walk through the tetrahedra of the meshing triangulation,
// from one of its vertices towards a point: the visibility integration's
// inner loop (Labatut, Pons, Keriven 2009, Sec. 4), walked twice per ray,
// about 150 cells per ray on the benchmark scenes, millions of rays.
//
// It runs on a compact copy of the triangulation (WalkTopology): 32 bytes
// per cell (4 vertex and 4 neighbour indices, one half cache line), the
// vertices numbered along a Hilbert curve and the cells by their first
// vertex in that order, so that a ray's next cell and the rays of
// neighbouring vertices often find their cells in the cache; CGAL's cells
// (about 90 bytes, in the order the insertions created them, vertices
// behind pointers) cost a miss each.
//
// The walk is a Plücker-style one (Platis and Theoharis 2003, "Fast
// ray-tetrahedron intersection using Plücker coordinates"): the side of the
// line (origin, target) on which each edge of a facet passes is an exact
// orientation test, the line crosses a triangle when its three edges are
// all on one side, and a cell entered through a facet whose edge sides are
// known needs only the three edges from its fourth vertex to tell its exit
// (testing each candidate facet on its own takes 6 to 9 tests). The side
// tests reuse what they share (differences to the origin, 2x2 minors with
// the direction) and decide with CGAL's own static filter and error bound,
// falling back to CGAL's exact predicate. The filter's determinants are
// also the barycentric coordinates of the crossing, which give its position
// along the ray, for the free-space weights and for telling when the target
// is reached, with no further predicate (inexact: a target within rounding
// of a facet may be placed in the cell on its other side). Rays that pass
// exactly through an edge or a vertex take one of the adjacent facets.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "src/mesh/delaunay_triangulation.h"

namespace colmap_lidar {

// The triangulation's cells and vertices, renumbered for the walk. Cell
// facet k and vertex k are CGAL's (facet k is opposite vertex k).
struct WalkTopology {
  static constexpr uint32_t kInfinite = UINT32_MAX;  // The infinite vertex.
  static constexpr uint32_t kNoCell = UINT32_MAX;

  // Walk vertex w: points[w], triangulation vertex vertex_source[w].
  std::vector<MeshPoint> points;
  std::vector<uint32_t> vertex_source;
  // One cell incident to each walk vertex.
  std::vector<uint32_t> vertex_cell;
  // Walk cell c: cells[c].vertices[k] (kInfinite for the infinite vertex),
  // cells[c].neighbors[k] (across facet k), triangulation cell
  // cell_source[c]. One cell per half cache line: a step loads one line.
  struct alignas(32) Cell {
    uint32_t vertices[4];
    uint32_t neighbors[4];
  };
  std::vector<Cell> cells;
  std::vector<uint32_t> cell_source;

  size_t NumVertices() const { return points.size(); }
  size_t NumCells() const { return cell_source.size(); }
  bool IsInfinite(uint32_t cell) const {
    const uint32_t* v = cells[cell].vertices;
    return v[0] == kInfinite || v[1] == kInfinite || v[2] == kInfinite ||
           v[3] == kInfinite;
  }
  uint32_t Vertex(uint32_t cell, int k) const {
    return cells[cell].vertices[k];
  }
  uint32_t Neighbor(uint32_t cell, int k) const {
    return cells[cell].neighbors[k];
  }
  // Index k of `vertex` in `cell` (which must hold it).
  int IndexOfVertex(uint32_t cell, uint32_t vertex) const {
    const uint32_t* v = cells[cell].vertices;
    return v[0] == vertex ? 0 : v[1] == vertex ? 1 : v[2] == vertex ? 2 : 3;
  }
  // Index k of `neighbor` among the neighbours of `cell`.
  int IndexOfNeighbor(uint32_t cell, uint32_t neighbor) const {
    const uint32_t* n = cells[cell].neighbors;
    return n[0] == neighbor ? 0
           : n[1] == neighbor ? 1
           : n[2] == neighbor ? 2
                              : 3;
  }
};

WalkTopology BuildWalkTopology(const MeshingTriangulation& triangulation);

// The cells incident to walk vertex `vertex`, into *star (cleared first).
void CollectStar(const WalkTopology& topology, uint32_t vertex,
                 std::vector<uint32_t>* star);

class RayWalker {
 public:
  explicit RayWalker(const WalkTopology& topology) : topology_(topology) {}

  // Walks from walk vertex `vertex`, whose incident cells are `star`
  // (CollectStar), towards `target`. Calls on_crossing(cell, k, t) for each facet k of `cell`
  // crossed when leaving `cell` towards the target, in order, t being the
  // crossing's parameter along vertex -> target (inexact; NaN where
  // unknown), and returns the cell
  // that contains the target or, when the segment leaves the convex hull,
  // the first infinite cell reached (or, with stay_finite, the last finite
  // cell, if there was one). Returns kNoCell when max_steps cells were
  // crossed (numerical trouble).
  //
  // first_cell_hint (optional): a cell of `star` tried first as the cell
  // the walk starts in (kNoCell: none); set to the one found. Rays of one
  // vertex to neighbouring sensors mostly start in the same cell, which
  // spares scanning the star (about 25 cells); where the direction lies
  // exactly on the boundary of two cells' cones the hint wins.
  template <typename OnCrossing>
  uint32_t Walk(uint32_t vertex, const std::vector<uint32_t>& star,
                const MeshPoint& target, bool stay_finite,
                OnCrossing&& on_crossing, uint32_t* first_cell_hint = nullptr,
                int max_steps = 1000000);

  // POSITIVE when `point` is strictly on the side of facet k of finite
  // `cell` where vertex k is (the cell with vertex k replaced by `point`
  // is positively oriented).
  CGAL::Orientation OrientationWithReplaced(uint32_t cell, int k,
                                            const MeshPoint& point) const {
    const MeshPoint* p[4];
    for (int i = 0; i < 4; ++i) {
      p[i] = i == k ? &point : &Point(topology_.Vertex(cell, i));
    }
    return CGAL::orientation(*p[0], *p[1], *p[2], *p[3]);
  }

 private:
  // A vertex relative to the walk's origin, with what the side tests reuse
  // across the edges that share it.
  struct Relative {
    double x, y, z;              // vertex - origin, rounded as CGAL does.
    double abs_x, abs_y, abs_z;  // |x|, |y|, |z|.
    double minor;                // direction.x * y - x * direction.y.
  };

  const MeshPoint& Point(uint32_t vertex) const {
    return topology_.points[vertex];
  }
  Relative MakeRelative(uint32_t vertex) const;
  // Side of the line (origin_, target_) relative to the directed edge
  // u -> v, i.e. CGAL::orientation(origin, target, u, v): its static filter
  // (CGAL's Orientation_3: the same differences, the same determinant
  // expansion, the same error bound) on the cached differences and minors,
  // and the exact predicate where the filter cannot decide.
  // *value is the filter's determinant (the Plücker product of the line
  // and the edge, up to a constant), NaN where the exact predicate decided.
  CGAL::Orientation Side(uint32_t u, const Relative& a, uint32_t v,
                         const Relative& b, double* value) const;
  // Parameter along origin -> target of the line's crossing with the facet
  // being crossed: each vertex's barycentric coordinate of the crossing is
  // the determinant of its opposite edge (Platis and Theoharis), and no
  // predicate is evaluated. NaN when a side came from the exact predicate
  // or the determinants sum to 0.
  double FacetParameter() const;
  // The finite star cell whose cone at `vertex` holds the direction to the
  // target, else kNoCell.
  uint32_t FirstCell(uint32_t vertex, const std::vector<uint32_t>& star,
                     uint32_t hint) const;
  // True when `cell` (finite, incident to `vertex`) has the direction to
  // the target in its cone at `vertex`.
  bool InCone(uint32_t cell, uint32_t vertex) const;
  // The infinite star cell whose hull facet faces the target.
  uint32_t HullCell(const std::vector<uint32_t>& star) const;
  // Sets facet_ to the vertices of facet k of `cell` and facet_side_ to the
  // sides of its edges.
  void SetFacet(uint32_t cell, int k);

  const WalkTopology& topology_;
  const MeshPoint* origin_ = nullptr;
  const MeshPoint* target_ = nullptr;
  Relative direction_{};  // target - origin.
  // The facet being crossed: its vertices, their Relative, and the side of
  // each edge facet_[i] -> facet_[(i + 1) % 3].
  uint32_t facet_[3] = {0, 0, 0};
  Relative facet_relative_[3]{};
  CGAL::Orientation facet_side_[3] = {CGAL::ZERO, CGAL::ZERO, CGAL::ZERO};
  double facet_value_[3] = {0, 0, 0};
  double inverse_squared_length_ = 0;  // 1 / |target - origin|^2.
};

inline RayWalker::Relative RayWalker::MakeRelative(uint32_t vertex) const {
  const MeshPoint& p = Point(vertex);
  Relative r;
  r.x = p.x() - origin_->x();
  r.y = p.y() - origin_->y();
  r.z = p.z() - origin_->z();
  r.abs_x = std::abs(r.x);
  r.abs_y = std::abs(r.y);
  r.abs_z = std::abs(r.z);
  r.minor = direction_.x * r.y - r.x * direction_.y;
  return r;
}

inline CGAL::Orientation RayWalker::Side(uint32_t u, const Relative& a,
                                         uint32_t v, const Relative& b,
                                         double* value) const {
  // Rows (direction, a, b): minors m01 = a.minor, m02 = b.minor, m12.
  const double m12 = a.x * b.y - b.x * a.y;
  const double det = a.minor * b.z - b.minor * a.z + m12 * direction_.z;
  const double max_x = std::max(direction_.abs_x, std::max(a.abs_x, b.abs_x));
  const double max_y = std::max(direction_.abs_y, std::max(a.abs_y, b.abs_y));
  const double max_z = std::max(direction_.abs_z, std::max(a.abs_z, b.abs_z));
  const double eps = 5.1107127829973299e-15 * max_x * max_y * max_z;
  // CGAL's guards against underflow of eps and overflow of det.
  if (std::min(max_x, std::min(max_y, max_z)) >= 1e-97 &&
      std::max(max_x, std::max(max_y, max_z)) < 1e102) {
    *value = det;
    if (det > eps) return CGAL::POSITIVE;
    if (det < -eps) return CGAL::NEGATIVE;
  }
  *value = std::numeric_limits<double>::quiet_NaN();
  return CGAL::orientation(*origin_, *target_, Point(u), Point(v));
}

inline double RayWalker::FacetParameter() const {
  const double w0 = facet_value_[1];  // Edge 1 -> 2, opposite vertex 0.
  const double w1 = facet_value_[2];
  const double w2 = facet_value_[0];
  const double sum = w0 + w1 + w2;
  if (!std::isfinite(sum) || sum == 0) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const Relative* r = facet_relative_;
  const double x = (w0 * r[0].x + w1 * r[1].x + w2 * r[2].x) / sum;
  const double y = (w0 * r[0].y + w1 * r[1].y + w2 * r[2].y) / sum;
  const double z = (w0 * r[0].z + w1 * r[1].z + w2 * r[2].z) / sum;
  return (x * direction_.x + y * direction_.y + z * direction_.z) *
         inverse_squared_length_;
}

// True when edge sides a, b, c (of a triangle's three edges, cyclically)
// say that the line passes through the closed triangle.
inline bool CrossesTriangle(CGAL::Orientation a, CGAL::Orientation b,
                            CGAL::Orientation c) {
  const bool any_positive =
      a == CGAL::POSITIVE || b == CGAL::POSITIVE || c == CGAL::POSITIVE;
  const bool any_negative =
      a == CGAL::NEGATIVE || b == CGAL::NEGATIVE || c == CGAL::NEGATIVE;
  return any_positive != any_negative;
}

template <typename OnCrossing>
uint32_t RayWalker::Walk(uint32_t vertex, const std::vector<uint32_t>& star,
                         const MeshPoint& target, bool stay_finite,
                         OnCrossing&& on_crossing, uint32_t* first_cell_hint,
                         int max_steps) {
  origin_ = &Point(vertex);
  target_ = &target;
  uint32_t cell = FirstCell(
      vertex, star,
      first_cell_hint != nullptr ? *first_cell_hint : WalkTopology::kNoCell);
  if (first_cell_hint != nullptr && cell != WalkTopology::kNoCell) {
    *first_cell_hint = cell;
  }
  direction_.x = target.x() - origin_->x();
  direction_.y = target.y() - origin_->y();
  direction_.z = target.z() - origin_->z();
  direction_.abs_x = std::abs(direction_.x);
  direction_.abs_y = std::abs(direction_.y);
  direction_.abs_z = std::abs(direction_.z);
  inverse_squared_length_ =
      1.0 / (direction_.x * direction_.x + direction_.y * direction_.y +
             direction_.z * direction_.z);
  if (cell == WalkTopology::kNoCell) return HullCell(star);

  // First step: the exit is the facet opposite the vertex.
  int exit_idx = topology_.IndexOfVertex(cell, vertex);
  SetFacet(cell, exit_idx);
  for (int step = 0; step < max_steps; ++step) {
    // The target is in this cell when it is on the inner side of the exit
    // facet, i.e. the line crosses that facet at or beyond the target
    // (where the crossing's parameter is unknown: the exact predicate).
    const double parameter = FacetParameter();
    if (std::isnan(parameter)
            ? OrientationWithReplaced(cell, exit_idx, target) !=
                  CGAL::NEGATIVE
            : parameter >= 1) {
      return cell;
    }
    on_crossing(cell, exit_idx, parameter);
    const uint32_t next = topology_.Neighbor(cell, exit_idx);
    if (topology_.IsInfinite(next)) return stay_finite ? cell : next;
    const int entry_idx = topology_.IndexOfNeighbor(next, cell);
    cell = next;
    // The exit is one of the three facets through the apex (the vertex
    // opposite the entry facet): facet (apex, facet_[i], facet_[i + 1]) is
    // crossed when its edges apex -> facet_[i], facet_[i] -> facet_[i + 1]
    // (known) and facet_[i + 1] -> apex are on one side of the line.
    const uint32_t apex = topology_.Vertex(cell, entry_idx);
    const Relative apex_relative = MakeRelative(apex);
    CGAL::Orientation apex_side[3];
    double apex_value[3];
    for (int i = 0; i < 3; ++i) {
      apex_side[i] = Side(apex, apex_relative, facet_[i], facet_relative_[i],
                          &apex_value[i]);
    }
    int crossed = -1;
    for (int i = 0; i < 3 && crossed < 0; ++i) {
      if (CrossesTriangle(apex_side[i], facet_side_[i],
                          -apex_side[(i + 1) % 3])) {
        crossed = i;
      }
    }
    if (crossed >= 0) {
      exit_idx = topology_.IndexOfVertex(cell, facet_[(crossed + 2) % 3]);
      const uint32_t second = facet_[crossed];
      const uint32_t third = facet_[(crossed + 1) % 3];
      const Relative second_relative = facet_relative_[crossed];
      const Relative third_relative = facet_relative_[(crossed + 1) % 3];
      const CGAL::Orientation second_side = facet_side_[crossed];
      const double second_value = facet_value_[crossed];
      facet_[0] = apex;
      facet_[1] = second;
      facet_[2] = third;
      facet_relative_[0] = apex_relative;
      facet_relative_[1] = second_relative;
      facet_relative_[2] = third_relative;
      facet_side_[0] = apex_side[crossed];
      facet_side_[1] = second_side;
      facet_side_[2] = -apex_side[(crossed + 1) % 3];
      facet_value_[0] = apex_value[crossed];
      facet_value_[1] = second_value;
      facet_value_[2] = -apex_value[(crossed + 1) % 3];
      continue;
    }
    // Degenerate (the line runs within a facet): leave through the facet
    // the target lies beyond, if any.
    exit_idx = -1;
    for (int k = 0; k < 4 && exit_idx < 0; ++k) {
      if (k != entry_idx &&
          OrientationWithReplaced(cell, k, target) == CGAL::NEGATIVE) {
        exit_idx = k;
      }
    }
    if (exit_idx < 0) return cell;
    SetFacet(cell, exit_idx);
  }
  return WalkTopology::kNoCell;
}

}  // namespace colmap_lidar
