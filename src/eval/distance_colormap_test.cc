#include "src/eval/distance_colormap.h"

#include <cmath>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

TEST(DistanceColormap, BlueGreenYellowRed) {
  EXPECT_EQ(DistanceColor(0.0, 0.3), Vector3ub(0, 0, 255));
  EXPECT_EQ(DistanceColor(0.1, 0.3), Vector3ub(0, 255, 0));
  EXPECT_EQ(DistanceColor(0.2, 0.3), Vector3ub(255, 255, 0));
  EXPECT_EQ(DistanceColor(0.3, 0.3), Vector3ub(255, 0, 0));
  EXPECT_EQ(DistanceColor(7.0, 0.3), Vector3ub(255, 0, 0));
  EXPECT_EQ(DistanceColor(INFINITY, 0.3), Vector3ub(255, 0, 0));
  // Halfway from blue to green (rounding may go either way).
  const Vector3ub half = DistanceColor(0.05, 0.3);
  EXPECT_EQ(half[0], 0);
  EXPECT_NEAR(half[1], 127.5, 0.5);
  EXPECT_NEAR(half[2], 127.5, 0.5);
  EXPECT_THROW(DistanceColor(0.1, 0.0), Error);
}

TEST(DistanceColormap, WritesPlyWithGreyExcludedPoints) {
  const std::string path =
      JoinPaths(testing::CreateTestDir(), "colored.ply");
  WriteDistanceColoredPly(path, {{1, 2, 3}, {4, 5, 6}}, {0.0, 0.0},
                          {true, false}, 0.1);
  const PlyData data = ReadPly(path);
  ASSERT_EQ(data.NumVertices(), 2u);
  EXPECT_EQ(data.FindColumn("blue")->values[0], 255);
  EXPECT_EQ(data.FindColumn("red")->values[1], 128);
  EXPECT_EQ(data.FindColumn("green")->values[1], 128);
  EXPECT_EQ(data.FindColumn("x")->values[1], 4.0);
}

}  // namespace
}  // namespace colmap_lidar
