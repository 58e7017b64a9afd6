#include "src/lines/lidar_edges.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "src/lines/synthetic_view.h"

namespace colmap_lidar {
namespace {

// Ranges along one ring that sweeps a convex corner: a wall x = 5 for
// azimuths below the corner, a wall y = 5 - (x - 5)... modelled directly as
// two planes meeting at azimuth 0 (the corner point is the nearest).
std::vector<double> CornerRing(int n, double step_rad, int* corner_idx) {
  std::vector<double> ranges(n);
  *corner_idx = n / 2;
  for (int i = 0; i < n; ++i) {
    const double azimuth = (i - n / 2) * step_rad;
    // Two planes with normals at +-45 deg through the point (5, 0): the
    // range to a plane with normal (cos a, sin a) and offset d is
    // d / cos(azimuth - a).
    const double a = azimuth < 0 ? -M_PI / 4 : M_PI / 4;
    const double d = 5.0 * std::cos(a);
    ranges[i] = d / std::cos(azimuth - a);
  }
  return ranges;
}

TEST(LidarEdges, CornerPointHasTheHighestSmoothness) {
  int corner = 0;
  const std::vector<double> ranges = CornerRing(101, 0.006, &corner);
  const std::vector<double> smoothness =
      ComputeRingSmoothness(ranges, std::vector<bool>(100, true), 5);
  const int best = static_cast<int>(
      std::max_element(smoothness.begin(), smoothness.end()) -
      smoothness.begin());
  EXPECT_EQ(best, corner);
  EXPECT_GT(smoothness[corner], 0.004);  // the default threshold
  // Far from the corner the walls are smooth.
  EXPECT_LT(smoothness[20], 1e-3);
  EXPECT_LT(smoothness[80], 1e-3);
  // Incomplete windows at the ends are not scored.
  EXPECT_EQ(smoothness[0], -1.0);
  EXPECT_EQ(smoothness[100], -1.0);
}

TEST(LidarEdges, WindowAcrossAGapIsNotScoredUnlessAtTheGap) {
  std::vector<double> ranges(40, 10.0);
  std::vector<bool> contiguous(39, true);
  contiguous[19] = false;  // missing returns between 19 and 20
  const std::vector<double> plain =
      ComputeRingSmoothness(ranges, contiguous, 5, false);
  EXPECT_EQ(plain[17], -1.0);
  EXPECT_EQ(plain[19], -1.0);
  EXPECT_DOUBLE_EQ(plain[10], 0.0);
  const std::vector<double> at_gaps =
      ComputeRingSmoothness(ranges, contiguous, 5, true);
  EXPECT_EQ(at_gaps[19], 1.0);
  EXPECT_EQ(at_gaps[20], 1.0);
  EXPECT_EQ(at_gaps[18], -1.0);
}

TEST(LidarEdges, SelectsTheCornerAndRespectsSectorLimits) {
  LidarEdgeOptions options;
  options.num_sectors = 1;
  int corner = 0;
  const std::vector<double> ranges = CornerRing(101, 0.006, &corner);
  const std::vector<bool> contiguous(100, true);
  const std::vector<int> edges = SelectRingEdges(ranges, contiguous, options);
  ASSERT_FALSE(edges.empty());
  EXPECT_NE(std::find(edges.begin(), edges.end(), corner), edges.end());
  // Neighbours of a selected point are never selected.
  for (size_t i = 1; i < edges.size(); ++i) {
    EXPECT_GT(edges[i] - edges[i - 1], options.num_neighbors);
  }

  // A zig-zag ring has many corners: the per-sector count limit holds.
  std::vector<double> zigzag(600);
  for (int i = 0; i < 600; ++i) {
    zigzag[i] = 10.0 + 0.3 * std::abs((i % 20) - 10) / 10.0;
  }
  options.num_sectors = 6;
  options.max_edges_per_sector = 3;
  options.occlusion_range_gap = 10.0;
  const std::vector<int> limited =
      SelectRingEdges(zigzag, std::vector<bool>(599, true), options);
  EXPECT_EQ(limited.size(), 18u);
  std::vector<int> per_sector(6, 0);
  for (const int idx : limited) {
    ++per_sector[std::min(5, (idx - 5) * 6 / 590)];
  }
  for (const int count : per_sector) {
    EXPECT_EQ(count, 3);
  }
  options.max_edges_per_sector = 100;
  const std::vector<int> unlimited =
      SelectRingEdges(zigzag, std::vector<bool>(599, true), options);
  // One corner every 10 points (peaks and valleys), minus the ends.
  EXPECT_GE(unlimited.size(), 50u);
}

TEST(LidarEdges, FarSideOfAnOcclusionIsExcluded) {
  // Near wall at 5 m for points 0..29, far wall at 9 m for 30..59.
  std::vector<double> ranges(60, 9.0);
  std::fill(ranges.begin(), ranges.begin() + 30, 5.0);
  LidarEdgeOptions options;
  options.num_sectors = 1;
  const std::vector<int> edges =
      SelectRingEdges(ranges, std::vector<bool>(59, true), options);
  ASSERT_FALSE(edges.empty());
  for (const int idx : edges) {
    EXPECT_LT(idx, 30) << "far-side point selected";
  }
  EXPECT_NE(std::find(edges.begin(), edges.end(), 29), edges.end());
}

TEST(LidarEdges, FarSideOfAShallowRecessIsExcludedAtShortRange) {
  // A wall seen obliquely (range growing by 3 cm a point) up to its lip at
  // point 29, then the glass of a 16 cm deep window recess at 5.86 m. The
  // recessed points next to the lip score higher than the lip itself.
  std::vector<double> ranges(60, 5.86);
  for (int i = 0; i < 30; ++i) {
    ranges[i] = 5.7 - 0.03 * (29 - i);
  }
  LidarEdgeOptions options;
  options.num_sectors = 1;
  EXPECT_NEAR(OcclusionRangeGap(options, 5.7), 0.114, 1e-9);
  EXPECT_NEAR(OcclusionRangeGap(options, 50.0), 0.3, 1e-9);
  const std::vector<int> edges =
      SelectRingEdges(ranges, std::vector<bool>(59, true), options);
  ASSERT_FALSE(edges.empty());
  for (const int idx : edges) {
    EXPECT_LT(idx, 30) << "recessed point selected";
  }
  // With LeGO-LOAM's fixed 0.3 m alone the step is no occlusion and the
  // recessed point next to the lip is taken.
  options.occlusion_range_ratio = 0.0;
  const std::vector<int> fixed_gap_edges =
      SelectRingEdges(ranges, std::vector<bool>(59, true), options);
  EXPECT_NE(std::find(fixed_gap_edges.begin(), fixed_gap_edges.end(), 30),
            fixed_gap_edges.end());
}

TEST(LidarEdges, ScanEdgesLieOnBoxEdges) {
  SyntheticViewOptions view_options;
  view_options.boxes = DefaultSyntheticBoxes();
  const SyntheticView view = MakeSyntheticView(view_options);
  LidarEdgeOptions options;
  const std::vector<int> edges = DetectLidarEdges(view.scan, options);
  ASSERT_GT(edges.size(), 50u);
  int near_box_edge = 0;
  for (const int idx : edges) {
    const Eigen::Vector3d point_in_cam =
        view.cam_from_lidar * view.scan.points[idx].cast<double>();
    double best = 1e9;
    for (const auto& edge : view.edges_in_cam) {
      best = std::min(best,
                      DistanceToSegment3D(edge.first, edge.second, point_in_cam));
    }
    near_box_edge += best < 0.1 ? 1 : 0;
  }
  // Edge points come from box edges and silhouettes (and the ground's far
  // border at 40 m); most lie within 10 cm of a box edge.
  EXPECT_GT(near_box_edge, static_cast<int>(edges.size()) / 2)
      << near_box_edge << " of " << edges.size();
}

TEST(LidarEdges, RingsAreEstimatedWhenMissing) {
  SyntheticViewOptions view_options;
  view_options.boxes = DefaultSyntheticBoxes();
  SyntheticView view = MakeSyntheticView(view_options);
  const std::vector<int> with_rings = DetectLidarEdges(view.scan, {});
  view.scan.rings.clear();
  const std::vector<int> without_rings = DetectLidarEdges(view.scan, {});
  // Same organised scan: the estimated rings give (nearly) the same edges.
  std::vector<int> common;
  std::set_intersection(with_rings.begin(), with_rings.end(),
                        without_rings.begin(), without_rings.end(),
                        std::back_inserter(common));
  EXPECT_GT(common.size(), with_rings.size() * 9 / 10);
}

TEST(LidarEdges, PcaFallbackFindsTheCreaseOfTwoPlanes) {
  // An unorganised cloud: two perpendicular planes (floor z = 0 for y > 0,
  // wall y = 0 for z > 0) on a 2 cm grid, shuffled.
  LidarScan scan;
  for (int i = 0; i < 100; ++i) {
    for (int j = 1; j < 30; ++j) {
      scan.points.emplace_back(5.0f + 0.02f * i, 0.02f * j, 0.0f);
      scan.points.emplace_back(5.0f + 0.02f * i, 0.0f, 0.02f * j);
    }
  }
  LidarEdgeOptions options;
  options.method = "pca";
  options.pca_radius = 0.08;
  const std::vector<int> edges = DetectLidarEdges(scan, options);
  ASSERT_FALSE(edges.empty());
  for (const int idx : edges) {
    const Eigen::Vector3f& p = scan.points[idx];
    EXPECT_LT(std::max(p.y(), p.z()), 0.1) << "edge far from the crease";
  }
  // The whole crease (points at 2 cm from it on both planes) is found.
  EXPECT_GT(edges.size(), 150u);
}

TEST(LidarEdges, AutoSwitchesToPcaForUnorganisedClouds) {
  // Random points on a floor (z = -1) and a wall (x = 8) meeting in a
  // crease: along any "ring" the azimuth neighbours are at random ranges.
  LidarScan scan;
  uint32_t state = 1;
  auto uniform = [&state]() {
    state = state * 1664525u + 1013904223u;
    return (state >> 8) / 16777216.0f;
  };
  for (int i = 0; i < 3000; ++i) {
    scan.points.emplace_back(3 + 5 * uniform(), 4 * uniform() - 2, -1.0f);
    scan.points.emplace_back(8.0f, 4 * uniform() - 2, 2.5f * uniform() - 1);
  }
  LidarEdgeOptions pca_options;
  pca_options.method = "pca";
  const std::vector<int> pca_edges = DetectLidarEdges(scan, pca_options);
  ASSERT_FALSE(pca_edges.empty());
  int near_crease = 0;
  for (const int idx : pca_edges) {
    const Eigen::Vector3f& p = scan.points[idx];
    near_crease += (8.0f - p.x() < 0.35f && p.z() + 1.0f < 0.35f) ? 1 : 0;
  }
  EXPECT_GT(near_crease, static_cast<int>(pca_edges.size()) * 8 / 10);
  EXPECT_EQ(DetectLidarEdges(scan, LidarEdgeOptions()), pca_edges);
}

TEST(LidarEdges, OptionsCheck) {
  LidarEdgeOptions options;
  EXPECT_TRUE(options.Check());
  options.method = "loam";
  EXPECT_FALSE(options.Check());
  options = LidarEdgeOptions();
  options.num_sectors = 0;
  EXPECT_FALSE(options.Check());
  options = LidarEdgeOptions();
  options.occlusion_range_ratio = -0.01;
  EXPECT_FALSE(options.Check());
}

}  // namespace
}  // namespace colmap_lidar
