#include "src/mesh/tiled_meshing.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <glog/logging.h>

#include "colmap_ext/util/byte_stream.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/process_group.h"
#include "src/mesh/tile_merger.h"

namespace colmap_lidar {
namespace {

// Bytes per point of the whole input that stays in memory while the tiles
// are meshed (position, source, weight, the visibility list and its
// allocation): the tiles' budget is what remains.
constexpr double kHeldInputBytesPerPoint = 150.0;
// Points sampled for the principal axes.
constexpr size_t kMaxAxisSamples = 200000;
// The tiles get no smaller than this many margins: below it the overlap
// costs more than the decimation it avoids (measured on the square cell at a
// 1 GiB budget: 360 tiles of one margin, 10 m, took 195 s against 18.7 s in
// one piece).
constexpr double kMinTileMargins = 2.0;

int Clamp(int value, int low, int high) {
  return std::max(low, std::min(value, high));
}

// Adds the 8 corners of a box around the tile's points and the sensors that
// see them, widened by a tenth of its diagonal (at least 1 m), as points
// without rays; returns them. Why: the convex hull of one tile's points is
// often a flat sheet (the ground of an open square), with no finite cell
// above it, so every free-space ray leaves the hull at its own point and the
// graph cut has no evidence to put the surface there (measured: 55 faces from
// 1,339 ground points); in the whole scene the hull of the buildings holds
// that space. The corners make it finite cells that the rays cross.
std::vector<Eigen::Vector3d> AddEnclosingCorners(MeshingInput* input) {
  Eigen::Vector3d low = input->positions.front();
  Eigen::Vector3d high = low;
  std::vector<bool> seen(input->sensors.size(), false);
  for (size_t i = 0; i < input->NumPoints(); ++i) {
    low = low.cwiseMin(input->positions[i]);
    high = high.cwiseMax(input->positions[i]);
    for (const uint32_t sensor : input->visibility[i]) seen[sensor] = true;
  }
  for (size_t sensor = 0; sensor < seen.size(); ++sensor) {
    if (!seen[sensor]) continue;
    low = low.cwiseMin(input->sensors[sensor].position_in_world);
    high = high.cwiseMax(input->sensors[sensor].position_in_world);
  }
  const double pad = std::max(1.0, 0.1 * (high - low).norm());
  low.array() -= pad;
  high.array() += pad;
  std::vector<Eigen::Vector3d> corners;
  for (int k = 0; k < 8; ++k) {
    corners.emplace_back(k & 1 ? high.x() : low.x(), k & 2 ? high.y() : low.y(),
                         k & 4 ? high.z() : low.z());
    input->AddPoint(corners.back(), MeshingPointSource::kLidar, 0.0f, {});
  }
  return corners;
}

}  // namespace

int MeshingTiles::TileOf(const Eigen::Vector3d& position) const {
  const Eigen::Vector3d offset = position - origin;
  const int i = Clamp(
      static_cast<int>(std::floor((axis_u.dot(offset) - u_min) / size_m)), 0,
      num_u - 1);
  const int j = Clamp(
      static_cast<int>(std::floor((axis_v.dot(offset) - v_min) / size_m)), 0,
      num_v - 1);
  return i * num_v + j;
}

bool MeshingTiles::Contains(int tile, const Eigen::Vector3d& position,
                            double margin) const {
  const int i = tile / num_v;
  const int j = tile % num_v;
  const Eigen::Vector3d offset = position - origin;
  const double u = axis_u.dot(offset) - u_min;
  const double v = axis_v.dot(offset) - v_min;
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const double u0 = i == 0 ? -kInfinity : i * size_m - margin;
  const double u1 = i == num_u - 1 ? kInfinity : (i + 1) * size_m + margin;
  const double v0 = j == 0 ? -kInfinity : j * size_m - margin;
  const double v1 = j == num_v - 1 ? kInfinity : (j + 1) * size_m + margin;
  return u >= u0 && u < u1 && v >= v0 && v < v1;
}

template <typename Visit>
void MeshingTiles::ForEachTileOf(const Eigen::Vector3d& position,
                                 Visit&& visit) const {
  // The tiles i with i * size - margin <= w < (i + 1) * size + margin.
  const auto range = [&](double w, int n) {
    return std::make_pair(
        Clamp(static_cast<int>(std::floor((w - margin_m) / size_m)), 0, n - 1),
        Clamp(static_cast<int>(std::floor((w + margin_m) / size_m)), 0,
              n - 1));
  };
  const Eigen::Vector3d offset = position - origin;
  const auto [i0, i1] = range(axis_u.dot(offset) - u_min, num_u);
  const auto [j0, j1] = range(axis_v.dot(offset) - v_min, num_v);
  for (int i = i0; i <= i1; ++i) {
    for (int j = j0; j <= j1; ++j) visit(i * num_v + j);
  }
}

std::vector<size_t> MeshingTiles::CountPoints(
    const std::vector<Eigen::Vector3d>& positions) const {
  std::vector<size_t> counts(NumTiles(), 0);
  for (const Eigen::Vector3d& position : positions) {
    ForEachTileOf(position, [&](int tile) { ++counts[tile]; });
  }
  return counts;
}

std::vector<std::vector<uint32_t>> MeshingTiles::PointsPerTile(
    const std::vector<Eigen::Vector3d>& positions) const {
  std::vector<std::vector<uint32_t>> points(NumTiles());
  for (uint32_t i = 0; i < positions.size(); ++i) {
    ForEachTileOf(positions[i], [&](int tile) { points[tile].push_back(i); });
  }
  return points;
}

MeshingTiles ChooseMeshingTiles(const MeshingInput& input,
                                size_t max_tile_points, double margin_m) {
  THROW_CHECK(input.NumPoints() > 0, "Meshing tiles of an empty input");
  THROW_CHECK(max_tile_points > 0 && margin_m >= 0,
              "Meshing tiles: invalid budget or margin");
  MeshingTiles tiles;
  tiles.margin_m = margin_m;
  tiles.max_tile_points = input.NumPoints();
  if (input.NumPoints() <= max_tile_points) {
    return tiles;
  }
  // Principal axes of a regular sample of the points.
  const size_t stride =
      std::max<size_t>(1, input.NumPoints() / kMaxAxisSamples);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  size_t num_samples = 0;
  for (size_t i = 0; i < input.NumPoints(); i += stride) {
    mean += input.positions[i];
    ++num_samples;
  }
  mean /= static_cast<double>(num_samples);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < input.NumPoints(); i += stride) {
    const Eigen::Vector3d offset = input.positions[i] - mean;
    covariance += offset * offset.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  tiles.origin = mean;
  tiles.axis_u = solver.eigenvectors().col(2);
  tiles.axis_v = solver.eigenvectors().col(1);

  double u_max = -std::numeric_limits<double>::infinity();
  double v_max = u_max;
  tiles.u_min = std::numeric_limits<double>::infinity();
  tiles.v_min = tiles.u_min;
  for (const Eigen::Vector3d& position : input.positions) {
    const Eigen::Vector3d offset = position - mean;
    const double u = tiles.axis_u.dot(offset);
    const double v = tiles.axis_v.dot(offset);
    tiles.u_min = std::min(tiles.u_min, u);
    tiles.v_min = std::min(tiles.v_min, v);
    u_max = std::max(u_max, u);
    v_max = std::max(v_max, v);
  }
  const double extent = std::max(u_max - tiles.u_min, v_max - tiles.v_min);
  const double min_size = std::max(kMinTileMargins * margin_m, 1e-3 * extent);
  // From half the extent down by 20 % steps: the largest tiles that fit
  // (the fewest seams).
  for (double size = std::max(extent / 2.0, min_size);;
       size = std::max(0.8 * size, min_size)) {
    tiles.size_m = size;
    tiles.num_u = std::max(
        1, static_cast<int>(std::ceil((u_max - tiles.u_min) / size)));
    tiles.num_v = std::max(
        1, static_cast<int>(std::ceil((v_max - tiles.v_min) / size)));
    const std::vector<size_t> counts = tiles.CountPoints(input.positions);
    tiles.max_tile_points = *std::max_element(counts.begin(), counts.end());
    if (tiles.max_tile_points <= max_tile_points || size <= min_size) {
      return tiles;
    }
  }
}

size_t MaxTilePointsForBudget(const DelaunayMeshingOptions& options,
                              size_t num_points) {
  // The whole input stays in memory: the tiles get the rest, and at least
  // a tenth of the budget (below that the guard decimates each tile).
  const double budget_points = static_cast<double>(options.MaxNumPoints());
  return static_cast<size_t>(std::max(
      0.1 * budget_points,
      budget_points -
          num_points * kHeldInputBytesPerPoint / kEstimatedBytesPerPoint));
}

MeshingInput TileMeshingInput(const MeshingInput& input,
                              const std::vector<uint32_t>& points,
                              const MeshingTiles& tiles, int tile) {
  MeshingInput output;
  output.sensors = input.sensors;
  output.crease_spacing_m = input.crease_spacing_m;
  output.positions.reserve(points.size());
  output.sources.reserve(points.size());
  output.ray_weights.reserve(points.size());
  output.visibility.reserve(points.size());
  for (const uint32_t i : points) {
    output.positions.push_back(input.positions[i]);
    output.sources.push_back(input.sources[i]);
    output.ray_weights.push_back(input.ray_weights[i]);
    output.visibility.push_back(input.visibility[i]);
  }
  for (const MeshCrease& crease : input.creases) {
    if (tiles.Contains(tile, crease.start, tiles.margin_m) ||
        tiles.Contains(tile, crease.end, tiles.margin_m)) {
      output.creases.push_back(crease);
    }
  }
  return output;
}

namespace {

// Meshes tile `tile` of `tiles` from its points (PointsPerTile; released
// here once its input is built).
MeshedTile MeshTile(const DelaunayMeshingOptions& tile_options,
                    const MeshingInput& input, const MeshingTiles& tiles,
                    int tile, std::vector<uint32_t>* points) {
  MeshingInput tile_input = TileMeshingInput(input, *points, tiles, tile);
  std::vector<uint32_t>().swap(*points);
  const std::vector<Eigen::Vector3d> corners =
      AddEnclosingCorners(&tile_input);
  MeshedTile result;
  result.meshed = true;
  result.num_points = tile_input.NumPoints();
  TriangleMesh tile_mesh =
      DelaunayMeshing(tile_options, tile_input, &result.summary);
  tile_input = MeshingInput();  // Released before the crop.
  result.num_faces = tile_mesh.faces.size();
  std::vector<bool> is_corner(tile_mesh.vertices.size(), false);
  for (size_t v = 0; v < tile_mesh.vertices.size(); ++v) {
    is_corner[v] = std::find(corners.begin(), corners.end(),
                             tile_mesh.vertices[v]) != corners.end();
  }
  constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> kept_index(tile_mesh.vertices.size(), kUnused);
  for (const std::array<uint32_t, 3>& face : tile_mesh.faces) {
    if (is_corner[face[0]] || is_corner[face[1]] || is_corner[face[2]]) {
      continue;
    }
    const Eigen::Vector3d centroid =
        (tile_mesh.vertices[face[0]] + tile_mesh.vertices[face[1]] +
         tile_mesh.vertices[face[2]]) /
        3.0;
    if (tiles.TileOf(centroid) != tile) continue;
    std::array<uint32_t, 3> kept_face;
    for (int k = 0; k < 3; ++k) {
      uint32_t& index = kept_index[face[k]];
      if (index == kUnused) {
        index = static_cast<uint32_t>(result.kept.vertices.size());
        result.kept.vertices.push_back(tile_mesh.vertices[face[k]]);
      }
      kept_face[k] = index;
    }
    result.kept.faces.push_back(kept_face);
  }
  return result;
}

}  // namespace

TriangleMesh TiledDelaunayMeshing(const DelaunayMeshingOptions& options,
                                  const MeshingInput& input,
                                  DelaunayMeshingSummary* summary_out) {
  THROW_CHECK(options.Check(), "Invalid Delaunay meshing options");
  const ProcessGroup& group = ProcessGroup::World();
  const size_t budget_points = options.MaxNumPoints();
  if (input.NumPoints() <= budget_points) {
    // One piece: rank 0 alone (the other ranks of a job have nothing to do).
    if (!group.IsRoot()) return TriangleMesh();
    return DelaunayMeshing(options, input, summary_out);
  }
  const size_t max_tile_points =
      MaxTilePointsForBudget(options, input.NumPoints());
  const MeshingTiles tiles =
      ChooseMeshingTiles(input, max_tile_points, options.tile_margin_m);
  LOG_IF(INFO, group.IsRoot())
      << "Meshing by tiles: " << input.NumPoints()
      << " points exceed the memory budget (" << options.max_memory_gb
      << " GiB, " << budget_points << " points); " << tiles.NumTiles()
      << " tiles (" << tiles.num_u << " x " << tiles.num_v << ") of "
      << tiles.size_m << " m with a margin of " << tiles.margin_m
      << " m, at most " << tiles.max_tile_points << " points each (budget "
      << max_tile_points << ")"
      << (group.Distributed()
              ? " on " + std::to_string(group.Size()) + " ranks"
              : std::string());

  // Each tile's points, found once; and those of its core.
  std::vector<std::vector<uint32_t>> tile_points =
      tiles.PointsPerTile(input.positions);
  std::vector<size_t> num_core_points(tiles.NumTiles(), 0);
  for (const Eigen::Vector3d& position : input.positions) {
    ++num_core_points[tiles.TileOf(position)];
  }
  // Both sides of a seam must build the same faces there: the points merge
  // in a world grid's order, and every tile takes the free-space sigma and
  // the clean-up's median edge length of the reference tile: the fullest
  // with a point in its core, meshed first. The tiles are merged in this
  // order (fullest first) whatever the number of ranks, so that a vertex
  // shared by a seam keeps the same index.
  std::vector<int> order(tiles.NumTiles());
  for (int tile = 0; tile < tiles.NumTiles(); ++tile) order[tile] = tile;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return tile_points[a].size() > tile_points[b].size();
  });
  // Decided once: a tile's points are released when it is meshed.
  std::vector<bool> is_meshable(tiles.NumTiles());
  for (int tile = 0; tile < tiles.NumTiles(); ++tile) {
    is_meshable[tile] =
        num_core_points[tile] > 0 && tile_points[tile].size() >= 4;
  }
  size_t reference = 0;
  while (reference < order.size() && !is_meshable[order[reference]]) {
    ++reference;
  }
  THROW_CHECK(reference < order.size(), "No tile has points to mesh");

  TileMerger merger;
  DelaunayMeshingOptions tile_options = options;
  tile_options.world_grid_order = true;
  const auto mesh_tile = [&](size_t index) {
    const int tile = order[index];
    if (!is_meshable[tile]) {
      LOG(INFO) << "Tile " << index + 1 << " / " << tiles.NumTiles()
                << ": no point in its core";
      return MeshedTile();
    }
    MeshedTile result = MeshTile(tile_options, input, tiles, tile,
                                 &tile_points[tile]);
    LOG(INFO) << "Tile " << index + 1 << " / " << tiles.NumTiles() << ": "
              << result.num_points << " points (" << num_core_points[tile]
              << " in its core), " << result.kept.faces.size() << " of "
              << result.num_faces << " faces kept, "
              << result.summary.total_seconds << " s, peak memory so far "
              << PeakResidentMemoryBytes() / (1024.0 * 1024.0) << " MiB";
    return result;
  };

  // The reference tile on rank 0; its sigma and edge length to every rank.
  {
    std::exception_ptr error;
    std::string shared;
    if (group.IsRoot()) {
      try {
        MeshedTile result = mesh_tile(reference);
        ByteWriter writer(&shared);
        writer.Value(result.summary.distance_sigma_m);
        writer.Value(result.summary.cleanup.median_edge_length_m);
        merger.Add(std::move(result));
      } catch (...) {
        error = std::current_exception();
      }
    }
    group.CheckAllOk(error, "meshing the reference tile");
    group.Broadcast(&shared);
    ByteReader reader(shared);
    tile_options.distance_sigma_m = reader.Value<double>();
    tile_options.cleanup_median_edge_length_m = reader.Value<double>();
  }
  // The other tiles, each on one rank: the fullest first, to the rank with
  // the fewest points so far (a tile's time grows with its points), the same
  // assignment on every rank. One process merges each tile as it is done;
  // ranks keep theirs until all are done, then rank 0 gathers and merges
  // them in the order, one tile at a time.
  std::vector<int> owner(order.size(), 0);
  std::vector<size_t> load(group.Size(), 0);
  for (size_t index = reference + 1; index < order.size(); ++index) {
    if (!is_meshable[order[index]]) continue;
    owner[index] = static_cast<int>(
        std::min_element(load.begin(), load.end()) - load.begin());
    load[owner[index]] += tile_points[order[index]].size();
  }
  std::map<size_t, MeshedTile> own_tiles;
  std::exception_ptr error;
  for (size_t index = reference + 1; index < order.size(); ++index) {
    if (owner[index] != group.Rank()) continue;
    try {
      MeshedTile result = mesh_tile(index);
      if (!group.Distributed()) {
        merger.Add(std::move(result));
      } else if (result.meshed) {
        own_tiles[index] = std::move(result);
      }
    } catch (...) {
      error = std::current_exception();
      break;
    }
  }
  group.CheckAllOk(error, "meshing the tiles");
  if (group.Distributed()) {
    for (size_t index = reference + 1; index < order.size(); ++index) {
      if (!is_meshable[order[index]]) continue;
      std::string bytes;
      if (owner[index] == group.Rank()) {
        bytes = SerializeMeshedTile(own_tiles.at(index));
        own_tiles.erase(index);
      }
      for (const std::string& part : group.GatherToRoot(bytes)) {
        if (!part.empty()) merger.Add(DeserializeMeshedTile(part));
      }
    }
  }
  if (!group.IsRoot()) return TriangleMesh();

  DelaunayMeshingSummary summary = merger.Summary();
  summary.num_input_points = input.NumPoints();
  summary.num_tiles = tiles.NumTiles();
  summary.tile_size_m = tiles.size_m;
  TriangleMesh mesh = merger.Release();
  summary.num_faces = mesh.faces.size();
  summary.num_mesh_vertices = mesh.vertices.size();
  summary.peak_memory_bytes = PeakResidentMemoryBytes();
  if (summary_out != nullptr) *summary_out = summary;
  return mesh;
}

}  // namespace colmap_lidar
