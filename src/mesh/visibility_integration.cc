#include "src/mesh/visibility_integration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

#include <Eigen/Geometry>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

constexpr int kMaxWalkSteps = 1000000;

// Weights summed by several threads in fixed point: integer additions do
// not depend on their order (float additions in the threads' order differ
// in the last bits, enough to flip near-tied cells of the graph cut).
// Resolution 2^-24 (6e-8) of a ray weight, range 5e11.
class AtomicArray {
 public:
  explicit AtomicArray(size_t size)
      : size_(size), data_(new std::atomic<int64_t>[size]) {
    for (size_t i = 0; i < size; ++i) data_[i].store(0);
  }
  void Add(size_t idx, float value) {
    data_[idx].fetch_add(std::llround(static_cast<double>(value) * kScale),
                         std::memory_order_relaxed);
  }
  std::vector<float> ToVector() const {
    std::vector<float> values(size_);
    for (size_t i = 0; i < size_; ++i) {
      values[i] = static_cast<float>(static_cast<double>(data_[i].load()) /
                                     kScale);
    }
    return values;
  }

 private:
  static constexpr double kScale = 16777216.0;  // 2^24.
  size_t size_;
  std::unique_ptr<std::atomic<int64_t>[]> data_;
};

// The tetrahedron of a finite cell with vertex k replaced by `point`:
// POSITIVE when `point` is strictly on the side of facet k where vertex k is.
CGAL::Orientation OrientationWithReplaced(const MeshCellHandle& cell, int k,
                                          const MeshPoint& point) {
  const MeshPoint* p[4];
  for (int i = 0; i < 4; ++i) p[i] = &cell->vertex(i)->point();
  p[k] = &point;
  return CGAL::orientation(*p[0], *p[1], *p[2], *p[3]);
}

// True when the line through a and b passes through the closed triangle.
bool LineCrossesTriangle(const MeshPoint& a, const MeshPoint& b,
                         const MeshPoint& t0, const MeshPoint& t1,
                         const MeshPoint& t2) {
  const CGAL::Orientation s0 = CGAL::orientation(a, b, t0, t1);
  const CGAL::Orientation s1 = CGAL::orientation(a, b, t1, t2);
  const CGAL::Orientation s2 = CGAL::orientation(a, b, t2, t0);
  const bool any_positive = s0 == CGAL::POSITIVE || s1 == CGAL::POSITIVE ||
                            s2 == CGAL::POSITIVE;
  const bool any_negative = s0 == CGAL::NEGATIVE || s1 == CGAL::NEGATIVE ||
                            s2 == CGAL::NEGATIVE;
  return !(any_positive && any_negative) && (any_positive || any_negative);
}

// Parameter in [0, 1] of the crossing of segment a->b with the plane of
// facet k of `cell` (inexact; used only for weights).
double CrossingParameter(const MeshCellHandle& cell, int k,
                         const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Eigen::Vector3d t[3];
  for (int i = 0, j = 0; i < 4; ++i) {
    if (i != k) t[j++] = ToEigen(cell->vertex(i)->point());
  }
  const Eigen::Vector3d normal = (t[1] - t[0]).cross(t[2] - t[0]);
  const double denominator = normal.dot(b - a);
  if (denominator == 0) return 0;
  return std::clamp(normal.dot(t[0] - a) / denominator, 0.0, 1.0);
}

class RayWalker {
 public:
  RayWalker(const MeshingTriangulation& triangulation, double distance_sigma,
            double behind_distance)
      : delaunay_(triangulation.delaunay),
        distance_normalization_(-0.5 / (distance_sigma * distance_sigma)),
        behind_distance_(behind_distance) {}

  // The cells incident to `vertex`.
  void CollectStar(const MeshVertexHandle& vertex) {
    star_.clear();
    star_.push_back(vertex->cell());
    for (size_t i = 0; i < star_.size(); ++i) {
      const MeshCellHandle cell = star_[i];
      for (int k = 0; k < 4; ++k) {
        if (cell->vertex(k) == vertex) continue;
        const MeshCellHandle neighbor = cell->neighbor(k);
        if (std::find(star_.begin(), star_.end(), neighbor) == star_.end()) {
          star_.push_back(neighbor);
        }
      }
    }
  }

  // Walks from `vertex` (whose star was collected) towards `target`. Calls
  // on_crossing(cell, k, distance_from_vertex) for each facet k of `cell`
  // crossed when leaving `cell` towards the target, and returns the cell
  // that contains the target or, when the segment leaves the convex hull,
  // the first infinite cell reached (or, with stay_finite, the last finite
  // cell, if there was one). Returns a null handle when the step limit is
  // hit.
  template <typename OnCrossing>
  MeshCellHandle Walk(const MeshVertexHandle& vertex, const MeshPoint& target,
                      bool stay_finite, OnCrossing&& on_crossing) {
    const MeshPoint& origin = vertex->point();
    const Eigen::Vector3d origin_e = ToEigen(origin);
    const Eigen::Vector3d target_e = ToEigen(target);
    const double length = (target_e - origin_e).norm();

    // The cell of the star whose cone at the vertex holds the direction.
    MeshCellHandle cell;
    for (const MeshCellHandle& candidate : star_) {
      if (delaunay_.is_infinite(candidate)) continue;
      const int vertex_idx = candidate->index(vertex);
      bool inside_cone = true;
      for (int j = 0; j < 4 && inside_cone; ++j) {
        if (j != vertex_idx && OrientationWithReplaced(candidate, j, target) ==
                                   CGAL::NEGATIVE) {
          inside_cone = false;
        }
      }
      if (inside_cone) {
        cell = candidate;
        break;
      }
    }
    if (cell == MeshCellHandle()) {
      // The direction leaves the convex hull at the vertex: the infinite cell
      // whose hull facet faces the target.
      MeshCellHandle fallback;
      for (const MeshCellHandle& candidate : star_) {
        if (!delaunay_.is_infinite(candidate)) continue;
        fallback = candidate;
        const int infinite_idx = candidate->index(delaunay_.infinite_vertex());
        if (OrientationWithReplaced(candidate, infinite_idx, target) ==
            CGAL::POSITIVE) {
          return candidate;
        }
      }
      return fallback;
    }

    // First step: the exit is the facet opposite the vertex.
    int exit_idx = cell->index(vertex);
    for (int step = 0; step < kMaxWalkSteps; ++step) {
      if (OrientationWithReplaced(cell, exit_idx, target) != CGAL::NEGATIVE) {
        return cell;  // The target is on the inner side of the exit facet.
      }
      on_crossing(cell, exit_idx,
                  length * CrossingParameter(cell, exit_idx, origin_e,
                                             target_e));
      const MeshCellHandle next = cell->neighbor(exit_idx);
      if (delaunay_.is_infinite(next)) return stay_finite ? cell : next;
      const int entry_idx = next->index(cell);
      cell = next;
      // The exit is the other facet the line crosses.
      exit_idx = -1;
      for (int k = 0; k < 4; ++k) {
        if (k == entry_idx) continue;
        const MeshPoint* t[3];
        for (int i = 0, j = 0; i < 4; ++i) {
          if (i != k) t[j++] = &cell->vertex(i)->point();
        }
        if (LineCrossesTriangle(origin, target, *t[0], *t[1], *t[2])) {
          exit_idx = k;
          break;
        }
      }
      if (exit_idx < 0) {
        // Degenerate (the line runs within a facet): leave through the facet
        // the target lies beyond, if any.
        for (int k = 0; k < 4; ++k) {
          if (k != entry_idx &&
              OrientationWithReplaced(cell, k, target) == CGAL::NEGATIVE) {
            exit_idx = k;
            break;
          }
        }
        if (exit_idx < 0) return cell;
      }
    }
    return MeshCellHandle();
  }

  double DistanceProb(double distance) const {
    return 1.0 - std::exp(distance * distance * distance_normalization_);
  }
  double BehindDistance() const { return behind_distance_; }

 private:
  const MeshDelaunay& delaunay_;
  const double distance_normalization_;
  const double behind_distance_;
  std::vector<MeshCellHandle> star_;
};

}  // namespace

bool VisibilityIntegrationOptions::Check() const {
  if (!(distance_sigma_factor > 0)) {
    LOG(ERROR) << "DelaunayMeshing.distance_sigma_factor must be > 0";
    return false;
  }
  if (!(behind_distance_factor > 0)) {
    LOG(ERROR) << "DelaunayMeshing.behind_distance_factor must be > 0";
    return false;
  }
  if (!(max_free_space_length_factor >= 0) ||
      !std::isfinite(max_free_space_length_factor)) {
    LOG(ERROR) << "DelaunayMeshing.max_free_space_length_factor must be "
                  "finite and >= 0";
    return false;
  }
  return true;
}

int EffectiveNumThreads(int num_threads) {
  if (num_threads > 0) return num_threads;
  return std::max(1u, std::thread::hardware_concurrency());
}

double LowerQuartileEdgeLength(const MeshingTriangulation& triangulation) {
  // Each finite edge once, sampled in an order that does not depend on
  // memory addresses: CGAL's edge iterator picks an edge's representative
  // cell by comparing cell handles (addresses), so a strided sample of it
  // changed with the heap's layout, and with it sigma and the mesh (two
  // surfaces 0.04 % of the faces apart on the same input). Here an edge
  // belongs to its finite incident cell of the smallest index.
  const MeshDelaunay& delaunay = triangulation.delaunay;
  const size_t num_edges = delaunay.number_of_finite_edges();
  const size_t stride = std::max<size_t>(1, num_edges / 1000000);
  std::vector<double> lengths;
  lengths.reserve(num_edges / stride + 1);
  size_t edge_idx = 0;
  for (const MeshCellHandle& cell : triangulation.cells) {
    if (delaunay.is_infinite(cell)) continue;
    for (int i = 0; i < 3; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        bool owner = true;
        MeshDelaunay::Cell_circulator circulator =
            delaunay.incident_cells(cell, i, j);
        const MeshDelaunay::Cell_circulator done = circulator;
        do {
          if (!delaunay.is_infinite(circulator) &&
              circulator->info() < cell->info()) {
            owner = false;
            break;
          }
        } while (++circulator != done);
        if (!owner || edge_idx++ % stride != 0) continue;
        lengths.push_back(std::sqrt(CGAL::squared_distance(
            cell->vertex(i)->point(), cell->vertex(j)->point())));
      }
    }
  }
  if (lengths.empty()) return 0;
  auto quartile = lengths.begin() + lengths.size() / 4;
  std::nth_element(lengths.begin(), quartile, lengths.end());
  return *quartile;
}

CellGraphWeights IntegrateVisibility(
    const VisibilityIntegrationOptions& options, const MeshingInput& input,
    const MeshingTriangulation& triangulation) {
  THROW_CHECK(options.Check(), "Invalid visibility integration options");
  THROW_CHECK(triangulation.point_to_vertex.size() == input.NumPoints(),
              "Triangulation and input do not match");
  const size_t num_vertices = triangulation.NumVertices();
  const size_t num_cells = triangulation.NumCells();

  // Rays grouped by vertex, one per (vertex, sensor), weights summed.
  struct Ray {
    uint32_t vertex;
    uint32_t sensor;
    float weight;
  };
  std::vector<Ray> rays;
  rays.reserve(input.NumRays());
  for (size_t i = 0; i < input.NumPoints(); ++i) {
    for (const uint32_t sensor : input.visibility[i]) {
      rays.push_back({triangulation.point_to_vertex[i], sensor,
                      input.ray_weights[i]});
    }
  }
  std::sort(rays.begin(), rays.end(), [](const Ray& a, const Ray& b) {
    return a.vertex != b.vertex ? a.vertex < b.vertex : a.sensor < b.sensor;
  });
  size_t num_unique = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    if (num_unique > 0 && rays[num_unique - 1].vertex == rays[i].vertex &&
        rays[num_unique - 1].sensor == rays[i].sensor) {
      rays[num_unique - 1].weight += rays[i].weight;
    } else {
      rays[num_unique++] = rays[i];
    }
  }
  rays.resize(num_unique);
  rays.shrink_to_fit();
  std::vector<size_t> vertex_begin(num_vertices + 1, 0);
  for (const Ray& ray : rays) ++vertex_begin[ray.vertex + 1];
  for (size_t v = 0; v < num_vertices; ++v) {
    vertex_begin[v + 1] += vertex_begin[v];
  }

  CellGraphWeights weights;
  weights.num_rays = rays.size();
  weights.distance_sigma = options.distance_sigma_factor *
                           std::max(LowerQuartileEdgeLength(triangulation),
                                    1e-9);
  const double behind_distance =
      options.behind_distance_factor * weights.distance_sigma;
  const double max_free_space_length =
      options.max_free_space_length_factor > 0
          ? options.max_free_space_length_factor * weights.distance_sigma
          : std::numeric_limits<double>::infinity();

  AtomicArray source(num_cells);
  AtomicArray sink(num_cells);
  AtomicArray facet_in(4 * num_cells);
  std::atomic<size_t> next_vertex(0);
  std::atomic<size_t> num_failed(0);
  constexpr size_t kChunk = 256;

  auto worker = [&] {
    RayWalker walker(triangulation, weights.distance_sigma, behind_distance);
    size_t failed = 0;
    while (true) {
      const size_t chunk_begin = next_vertex.fetch_add(kChunk);
      if (chunk_begin >= num_vertices) break;
      const size_t chunk_end = std::min(num_vertices, chunk_begin + kChunk);
      for (size_t v = chunk_begin; v < chunk_end; ++v) {
        if (vertex_begin[v] == vertex_begin[v + 1]) continue;
        const MeshVertexHandle vertex = triangulation.vertices[v];
        walker.CollectStar(vertex);
        const Eigen::Vector3d position = ToEigen(vertex->point());
        for (size_t r = vertex_begin[v]; r < vertex_begin[v + 1]; ++r) {
          const float alpha = rays[r].weight;
          const Eigen::Vector3d& sensor_position =
              input.sensors[rays[r].sensor].position_in_world;
          const Eigen::Vector3d direction = position - sensor_position;
          const double length = direction.norm();
          if (length == 0) continue;
          // Free space from the point to the sensor, or to the length cap.
          const Eigen::Vector3d free_space_end =
              length > max_free_space_length
                  ? Eigen::Vector3d(position - direction *
                                                   (max_free_space_length /
                                                    length))
                  : sensor_position;
          const MeshCellHandle sensor_cell = walker.Walk(
              vertex, ToCgal(free_space_end), /*stay_finite=*/false,
              [&](const MeshCellHandle& cell, int k, double distance) {
                facet_in.Add(4 * static_cast<size_t>(cell->info()) + k,
                             alpha * walker.DistanceProb(distance));
              });
          if (sensor_cell == MeshCellHandle()) {
            ++failed;
          } else {
            source.Add(sensor_cell->info(), alpha);
          }
          // Inside evidence behind the point. A behind segment that leaves
          // the convex hull after some finite cells (grazing views over an
          // edge) stays in the last finite cell; one that leaves the hull
          // right at the point (a flat sheet such as the ground, which has
          // no finite cells behind it) marks the infinite cell there.
          const Eigen::Vector3d behind =
              position + direction * (walker.BehindDistance() / length);
          const MeshCellHandle behind_cell = walker.Walk(
              vertex, ToCgal(behind), /*stay_finite=*/true,
              [](const MeshCellHandle&, int, double) {});
          if (behind_cell == MeshCellHandle()) {
            ++failed;
          } else {
            sink.Add(behind_cell->info(), alpha);
          }
        }
      }
    }
    num_failed += failed;
  };
  const int num_threads = EffectiveNumThreads(options.num_threads);
  std::vector<std::thread> threads;
  for (int t = 1; t < num_threads; ++t) threads.emplace_back(worker);
  worker();
  for (std::thread& thread : threads) thread.join();

  weights.source = source.ToVector();
  weights.sink = sink.ToVector();
  weights.facet_in = facet_in.ToVector();
  weights.num_failed_walks = num_failed;
  LOG(INFO) << "Visibility: " << weights.num_rays << " rays (of "
            << input.NumRays() << " observations), sigma "
            << weights.distance_sigma << " m, free space carved "
            << (std::isfinite(max_free_space_length)
                    ? "up to " + std::to_string(max_free_space_length) +
                          " m in front of the points"
                    : std::string("along whole rays"))
            << ", " << weights.num_failed_walks
            << " failed walks";
  if (weights.num_failed_walks > 0) {
    LOG(WARNING) << weights.num_failed_walks
                 << " ray walks hit the step limit";
  }
  return weights;
}

}  // namespace colmap_lidar
