#include "src/mesh/visibility_integration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

#include <Eigen/Geometry>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/parallel.h"
#include "src/mesh/ray_walker.h"

namespace colmap_lidar {
namespace {

// Weights summed by several threads in fixed point: integer additions do
// not depend on their order (float additions in the threads' order differ
// in the last bits, enough to flip near-tied cells of the graph cut).
// Resolution 2^-24 (6e-8) of a ray weight, range 5e11.
constexpr double kFixedPointScale = 16777216.0;  // 2^24.

// Rounded half away from zero, as std::llround (inline: one call per facet
// crossed otherwise).
inline int64_t ToFixedPoint(float value) {
  const double scaled = static_cast<double>(value) * kFixedPointScale;
  return static_cast<int64_t>(scaled >= 0 ? scaled + 0.5 : scaled - 0.5);
}

// The per-cell sums (two per ray), shared by the threads.
class AtomicArray {
 public:
  explicit AtomicArray(size_t size)
      : size_(size), data_(new std::atomic<int64_t>[size]) {
    for (size_t i = 0; i < size; ++i) data_[i].store(0);
  }
  void Add(size_t idx, float value) {
    data_[idx].fetch_add(ToFixedPoint(value), std::memory_order_relaxed);
  }
  // The sums of walk cell c at cell_source[c] (one per cell).
  std::vector<float> ToCellOrder(
      const std::vector<uint32_t>& cell_source) const {
    std::vector<float> values(size_);
    for (size_t c = 0; c < size_; ++c) {
      values[cell_source[c]] = static_cast<float>(
          static_cast<double>(data_[c].load()) / kFixedPointScale);
    }
    return values;
  }

 private:
  size_t size_;
  std::unique_ptr<std::atomic<int64_t>[]> data_;
};

// The per-facet sums (one per facet crossed, hundreds per ray), one array
// per thread, added up at the end: an atomic add on an array of this size
// misses the cache and, being a locked instruction, stalls the walk until
// the miss is served (on the 60-frame quad it took a third of the
// integration's time); a plain add lets the walk go on meanwhile. Costs
// 32 bytes per cell and thread.
class FixedPointArray {
 public:
  explicit FixedPointArray(size_t size) : data_(size, 0) {}
  void Add(size_t idx, float value) { data_[idx] += ToFixedPoint(value); }
  void AddTo(FixedPointArray* sum) const {
    for (size_t i = 0; i < data_.size(); ++i) sum->data_[i] += data_[i];
  }
  // The sums of facet k of walk cell c at 4 cell_source[c] + k.
  std::vector<float> ToFacetOrder(
      const std::vector<uint32_t>& cell_source) const {
    std::vector<float> values(data_.size());
    for (size_t i = 0; i < data_.size(); ++i) {
      values[4 * static_cast<size_t>(cell_source[i / 4]) + i % 4] =
          static_cast<float>(static_cast<double>(data_[i]) / kFixedPointScale);
    }
    return values;
  }

 private:
  std::vector<int64_t> data_;
};

// Parameter in [0, 1] of the crossing of segment a->b with the plane of
// facet k of `cell` (inexact; used only for weights).
double CrossingParameter(const WalkTopology& topology, uint32_t cell, int k,
                         const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Eigen::Vector3d t[3];
  for (int i = 0, j = 0; i < 4; ++i) {
    if (i != k) t[j++] = ToEigen(topology.points[topology.Vertex(cell, i)]);
  }
  const Eigen::Vector3d normal = (t[1] - t[0]).cross(t[2] - t[0]);
  const double denominator = normal.dot(b - a);
  if (denominator == 0) return 0;
  return std::clamp(normal.dot(t[0] - a) / denominator, 0.0, 1.0);
}

// The free-space weight of a facet crossed `distance` in front of the
// point: 1 - exp(-d^2 / (2 sigma^2)). Beyond 8 sigma it is 1 within 1e-14,
// and as the crossings move away from the point along the walk, the
// crossing's position (CrossingParameter) is only computed until then.
class FreeSpaceWeight {
 public:
  FreeSpaceWeight(const WalkTopology& topology, double distance_sigma)
      : topology_(topology),
        normalization_(-0.5 / (distance_sigma * distance_sigma)),
        saturation_distance_(8 * distance_sigma) {}

  // Weight of the next facet crossed by the ray a -> b (a at the point),
  // at parameter t along it (NaN: computed here).
  double Next(uint32_t cell, int k, double t, const Eigen::Vector3d& a,
              const Eigen::Vector3d& b, double length) {
    if (saturated_) return 1.0;
    const double distance =
        length * (std::isnan(t) ? CrossingParameter(topology_, cell, k, a, b)
                                : std::clamp(t, 0.0, 1.0));
    if (distance >= saturation_distance_) {
      saturated_ = true;
      return 1.0;
    }
    return 1.0 - std::exp(distance * distance * normalization_);
  }
  void Reset() { saturated_ = false; }

 private:
  const WalkTopology& topology_;
  const double normalization_;
  const double saturation_distance_;
  bool saturated_ = false;
};

}  // namespace

bool VisibilityIntegrationOptions::Check() const {
  if (!(distance_sigma_factor > 0)) {
    LOG(ERROR) << "DelaunayMeshing.distance_sigma_factor must be > 0";
    return false;
  }
  if (!(distance_sigma_m >= 0) || !std::isfinite(distance_sigma_m)) {
    LOG(ERROR) << "Visibility integration: distance_sigma_m must be finite "
                  "and >= 0";
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

double LowerQuartileEdgeLength(const MeshingTriangulation& triangulation,
                               int num_threads) {
  // Each finite edge once, sampled by a hash of its two vertex indices, so
  // that the sample depends neither on memory addresses (CGAL's edge
  // iterator picks an edge's representative cell by comparing cell
  // addresses: a strided sample of it changed with the heap's layout, and
  // with it sigma and the mesh) nor on the cells' numbering. About one
  // edge in (vertices / 150000) is sampled: ~1M of the ~7 edges per vertex
  // of a 3D Delaunay triangulation. A sampled edge is counted by its finite
  // incident cell of the smallest index (a walk around the edge).
  const MeshDelaunay& delaunay = triangulation.delaunay;
  const size_t num_cells = triangulation.NumCells();
  const uint64_t stride =
      std::max<uint64_t>(1, triangulation.NumVertices() / 150000);
  auto sampled = [stride](uint32_t a, uint32_t b) {
    // splitmix64's finaliser.
    uint64_t z = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return (z ^ (z >> 31)) % stride == 0;
  };
  constexpr size_t kChunk = 4096;
  const size_t num_chunks = (num_cells + kChunk - 1) / kChunk;
  std::vector<std::vector<double>> chunk_lengths(num_chunks);
  ParallelFor(0, static_cast<int>(num_chunks), num_threads, [&](int chunk) {
    std::vector<double>& lengths = chunk_lengths[chunk];
    const size_t chunk_begin = static_cast<size_t>(chunk) * kChunk;
    const size_t chunk_end = std::min(num_cells, chunk_begin + kChunk);
    for (size_t c = chunk_begin; c < chunk_end; ++c) {
      const MeshCellHandle& cell = triangulation.cells[c];
      if (delaunay.is_infinite(cell)) continue;
      for (int i = 0; i < 3; ++i) {
        for (int j = i + 1; j < 4; ++j) {
          if (!sampled(cell->vertex(i)->info(), cell->vertex(j)->info())) {
            continue;
          }
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
          if (owner) {
            lengths.push_back(std::sqrt(CGAL::squared_distance(
                cell->vertex(i)->point(), cell->vertex(j)->point())));
          }
        }
      }
    }
  });
  // The same multiset of lengths whichever order the chunks ran in: the
  // quartile does not depend on it.
  std::vector<double> lengths;
  for (std::vector<double>& part : chunk_lengths) {
    lengths.insert(lengths.end(), part.begin(), part.end());
    std::vector<double>().swap(part);
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
  weights.distance_sigma =
      options.distance_sigma_m > 0
          ? options.distance_sigma_m
          : options.distance_sigma_factor *
                std::max(LowerQuartileEdgeLength(triangulation,
                                                 options.num_threads),
                         1e-9);
  const double behind_distance =
      options.behind_distance_factor * weights.distance_sigma;
  const double max_free_space_length =
      options.max_free_space_length_factor > 0
          ? options.max_free_space_length_factor * weights.distance_sigma
          : std::numeric_limits<double>::infinity();

  const WalkTopology topology = BuildWalkTopology(triangulation);
  AtomicArray source(num_cells);
  AtomicArray sink(num_cells);
  const int num_threads = EffectiveNumThreads(options.num_threads);
  std::vector<std::unique_ptr<FixedPointArray>> thread_facet_in(num_threads);
  std::atomic<size_t> next_vertex(0);
  std::atomic<size_t> num_failed(0);
  constexpr size_t kChunk = 256;

  auto worker = [&](int thread_idx) {
    thread_facet_in[thread_idx] =
        std::make_unique<FixedPointArray>(4 * num_cells);
    FixedPointArray& facet_in = *thread_facet_in[thread_idx];
    RayWalker walker(topology);
    FreeSpaceWeight free_space_weight(topology, weights.distance_sigma);
    size_t failed = 0;
    // A chunk's stars, and its rays in sensor-major order: the rays from
    // neighbouring vertices (in Hilbert order) to one sensor are nearly
    // parallel and cross mostly the same cells, which are then still in the
    // cache; the rays of one vertex go to all its sensors.
    std::vector<std::vector<uint32_t>> stars(kChunk);
    // Per chunk vertex, the cells its last free-space and behind walks
    // started in.
    std::vector<uint32_t> free_hints(kChunk);
    std::vector<uint32_t> behind_hints(kChunk);
    struct ChunkRay {
      uint32_t sensor;
      uint32_t vertex;  // Walk vertex.
      size_t ray;       // Index into rays.
    };
    std::vector<ChunkRay> chunk_rays;
    while (true) {
      const size_t chunk_begin = next_vertex.fetch_add(kChunk);
      if (chunk_begin >= num_vertices) break;
      const size_t chunk_end = std::min(num_vertices, chunk_begin + kChunk);
      chunk_rays.clear();
      std::fill(free_hints.begin(), free_hints.end(), WalkTopology::kNoCell);
      std::fill(behind_hints.begin(), behind_hints.end(),
                WalkTopology::kNoCell);
      for (size_t w = chunk_begin; w < chunk_end; ++w) {
        const size_t v = topology.vertex_source[w];
        if (vertex_begin[v] == vertex_begin[v + 1]) continue;
        CollectStar(topology, static_cast<uint32_t>(w),
                    &stars[w - chunk_begin]);
        for (size_t r = vertex_begin[v]; r < vertex_begin[v + 1]; ++r) {
          chunk_rays.push_back({rays[r].sensor, static_cast<uint32_t>(w), r});
        }
      }
      std::sort(chunk_rays.begin(), chunk_rays.end(),
                [](const ChunkRay& a, const ChunkRay& b) {
                  return a.sensor != b.sensor ? a.sensor < b.sensor
                                              : a.vertex < b.vertex;
                });
      for (const ChunkRay& chunk_ray : chunk_rays) {
        const uint32_t vertex = chunk_ray.vertex;
        const std::vector<uint32_t>& star = stars[vertex - chunk_begin];
        const Eigen::Vector3d position = ToEigen(topology.points[vertex]);
        const float alpha = rays[chunk_ray.ray].weight;
        const Eigen::Vector3d& sensor_position =
            input.sensors[chunk_ray.sensor].position_in_world;
        const Eigen::Vector3d direction = position - sensor_position;
        const double length = direction.norm();
        if (length == 0) continue;
        // Free space from the point to the sensor, or to the length cap.
        const double free_length = std::min(length, max_free_space_length);
        const Eigen::Vector3d free_space_end =
            length > max_free_space_length
                ? Eigen::Vector3d(position -
                                  direction * (max_free_space_length / length))
                : sensor_position;
        free_space_weight.Reset();
        const uint32_t sensor_cell = walker.Walk(
            vertex, star, ToCgal(free_space_end), /*stay_finite=*/false,
            [&](uint32_t cell, int k, double t) {
              facet_in.Add(4 * static_cast<size_t>(cell) + k,
                           alpha * free_space_weight.Next(
                                       cell, k, t, position, free_space_end,
                                       free_length));
            },
            &free_hints[vertex - chunk_begin]);
        if (sensor_cell == WalkTopology::kNoCell) {
          ++failed;
        } else {
          source.Add(sensor_cell, alpha);
        }
        // Inside evidence behind the point. A behind segment that leaves
        // the convex hull after some finite cells (grazing views over an
        // edge) stays in the last finite cell; one that leaves the hull
        // right at the point (a flat sheet such as the ground, which has
        // no finite cells behind it) marks the infinite cell there.
        const Eigen::Vector3d behind =
            position + direction * (behind_distance / length);
        const uint32_t behind_cell =
            walker.Walk(vertex, star, ToCgal(behind), /*stay_finite=*/true,
                        [](uint32_t, int, double) {},
                        &behind_hints[vertex - chunk_begin]);
        if (behind_cell == WalkTopology::kNoCell) {
          ++failed;
        } else {
          sink.Add(behind_cell, alpha);
        }
      }
    }
    num_failed += failed;
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < num_threads; ++t) threads.emplace_back(worker, t);
  worker(0);
  for (std::thread& thread : threads) thread.join();
  for (int t = 1; t < num_threads; ++t) {
    thread_facet_in[t]->AddTo(thread_facet_in[0].get());
    thread_facet_in[t].reset();
  }

  weights.source = source.ToCellOrder(topology.cell_source);
  weights.sink = sink.ToCellOrder(topology.cell_source);
  weights.facet_in = thread_facet_in[0]->ToFacetOrder(topology.cell_source);
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
