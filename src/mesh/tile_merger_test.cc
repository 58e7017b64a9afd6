#include "src/mesh/tile_merger.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Two triangles of a unit square in tile A, one more beside it in tile B,
// sharing the edge x = 1 (B's copy of (1, 0, 0) has z = -0).
MeshedTile TileA() {
  MeshedTile tile;
  tile.meshed = true;
  tile.kept.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  tile.kept.faces = {{0, 1, 2}, {0, 2, 3}};
  tile.summary.num_vertices = 10;
  tile.summary.num_cells = 20;
  tile.summary.num_rays = 30;
  tile.summary.num_failed_walks = 1;
  tile.summary.num_surface_faces = 4;
  tile.summary.decimation_voxel_size_m = 0.02;
  tile.summary.distance_sigma_m = 0.05;
  tile.summary.max_flow = 1.5;
  tile.summary.triangulation_seconds = 1;
  tile.summary.visibility_seconds = 2;
  tile.summary.graph_cut_seconds = 3;
  tile.summary.total_seconds = 6;
  return tile;
}

MeshedTile TileB() {
  MeshedTile tile;
  tile.meshed = true;
  tile.kept.vertices = {{1, 1, 0}, {1, 0, -0.0}, {2, 0, 0}};
  tile.kept.faces = {{1, 2, 0}};
  tile.summary.num_vertices = 5;
  tile.summary.decimation_voxel_size_m = 0.01;
  tile.summary.distance_sigma_m = 0.05;
  tile.summary.total_seconds = 4;
  return tile;
}

TEST(TileMerger, SerializationRoundTrips) {
  const MeshedTile tile = TileA();
  const MeshedTile copy = DeserializeMeshedTile(SerializeMeshedTile(tile));
  EXPECT_TRUE(copy.meshed);
  EXPECT_EQ(copy.kept.vertices, tile.kept.vertices);
  EXPECT_EQ(copy.kept.faces, tile.kept.faces);
  EXPECT_EQ(copy.summary.num_vertices, 10u);
  EXPECT_EQ(copy.summary.num_cells, 20u);
  EXPECT_EQ(copy.summary.num_rays, 30u);
  EXPECT_EQ(copy.summary.num_failed_walks, 1u);
  EXPECT_EQ(copy.summary.num_surface_faces, 4u);
  EXPECT_EQ(copy.summary.decimation_voxel_size_m, 0.02);
  EXPECT_EQ(copy.summary.distance_sigma_m, 0.05);
  EXPECT_EQ(copy.summary.max_flow, 1.5);
  EXPECT_EQ(copy.summary.triangulation_seconds, 1);
  EXPECT_EQ(copy.summary.visibility_seconds, 2);
  EXPECT_EQ(copy.summary.graph_cut_seconds, 3);
  EXPECT_EQ(copy.summary.total_seconds, 6);
  // A tile that was not meshed travels as nothing and adds nothing.
  EXPECT_TRUE(SerializeMeshedTile(MeshedTile()).empty());
  TileMerger merger;
  merger.Add(MeshedTile());
  EXPECT_TRUE(merger.Release().faces.empty());
}

TEST(TileMerger, BadBytesThrowBeforeAllocating) {
  const std::string bytes = SerializeMeshedTile(TileA());
  EXPECT_THROW(DeserializeMeshedTile(bytes.substr(0, bytes.size() - 1)),
               Error);
  EXPECT_THROW(DeserializeMeshedTile(bytes + "x"), Error);
  EXPECT_THROW(DeserializeMeshedTile(bytes.substr(0, 10)), Error);
  // A vertex count near 2^64: refused from the sizes, nothing allocated.
  std::string huge = bytes;
  const uint64_t count = ~uint64_t{0} / 2;
  std::memcpy(&huge[5 * sizeof(uint64_t)], &count, sizeof(count));
  EXPECT_THROW(DeserializeMeshedTile(huge), Error);
  // A face that refers to a missing vertex.
  MeshedTile bad = TileA();
  bad.kept.faces.push_back({0, 1, 7});
  EXPECT_THROW(DeserializeMeshedTile(SerializeMeshedTile(bad)), Error);
}

TEST(TileMerger, MergesSeamVerticesInTheOrderOfTheTiles) {
  TileMerger merger;
  merger.Add(TileA());
  merger.Add(TileB());
  const DelaunayMeshingSummary summary = merger.Summary();
  EXPECT_EQ(summary.num_vertices, 15u);
  EXPECT_EQ(summary.decimation_voxel_size_m, 0.02);
  EXPECT_EQ(summary.distance_sigma_m, 0.05);
  EXPECT_EQ(summary.total_seconds, 10);
  const TriangleMesh mesh = merger.Release();
  // (1, 0, 0) and (1, 0, -0) are one vertex; so are both (1, 1, 0).
  ASSERT_EQ(mesh.vertices.size(), 5u);
  ASSERT_EQ(mesh.faces.size(), 3u);
  // The vertices keep the index of their first tile: A's, then B's new one.
  EXPECT_EQ(mesh.vertices[1], Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(mesh.vertices[4], Eigen::Vector3d(2, 0, 0));
  std::vector<std::array<uint32_t, 3>> faces = mesh.faces;
  TriangleMesh sorted = mesh;
  SortFacesCanonically(&sorted);
  EXPECT_EQ(faces, sorted.faces);
  // B's face over the merged vertices.
  bool found = false;
  for (const std::array<uint32_t, 3>& face : mesh.faces) {
    std::array<uint32_t, 3> copy = face;
    std::sort(copy.begin(), copy.end());
    found |= copy == std::array<uint32_t, 3>{1, 2, 4};
  }
  EXPECT_TRUE(found);
  // Released: the merger starts again empty.
  EXPECT_TRUE(merger.Release().vertices.empty());
}

}  // namespace
}  // namespace colmap_lidar
