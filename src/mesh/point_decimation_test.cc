#include "src/mesh/point_decimation.h"

#include <set>

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

TEST(PointDecimation, KeepsHeaviestPointPerVoxelWithSensorUnion) {
  MeshingInput input;
  input.sensors.resize(3);
  // A 100 x 100 grid of 1 cm on the plane z = 0.
  for (int i = 0; i < 100; ++i) {
    for (int j = 0; j < 100; ++j) {
      input.AddPoint(Eigen::Vector3d(0.01 * i, 0.01 * j, 0),
                     MeshingPointSource::kVisual, 1.0f + (i + j) % 3,
                     {static_cast<uint32_t>((i + j) % 3)});
    }
  }
  EXPECT_EQ(DecimateMeshingInput(20000, &input), 0.0);
  EXPECT_EQ(input.NumPoints(), 10000u);
  const double voxel_size = DecimateMeshingInput(500, &input);
  EXPECT_GT(voxel_size, 0.0);
  EXPECT_LE(input.NumPoints(), 500u);
  EXPECT_GT(input.NumPoints(), 100u);
  input.Check();
  // Voxels span several grid points, so the kept points are the heaviest
  // (weight 3) and see the union of the sensors.
  size_t num_full_union = 0;
  for (size_t i = 0; i < input.NumPoints(); ++i) {
    num_full_union += input.visibility[i].size() == 3 ? 1 : 0;
    EXPECT_EQ(input.ray_weights[i], 3.0f);
  }
  EXPECT_GT(num_full_union, input.NumPoints() / 2);
}

}  // namespace
}  // namespace colmap_lidar
