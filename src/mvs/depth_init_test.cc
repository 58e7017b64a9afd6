#include "src/mvs/depth_init.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <vector>

#include <gtest/gtest.h>

#include "src/mvs/interpolation.h"
#include "src/mvs/lidar_patch_match_stereo.h"
#include "src/mvs/mvs_test_scene.h"

namespace colmap_lidar {
namespace {

// A foreground plane at z = 2 with a square hole, a wall at z = 4 behind.
PlaneScene HoleScene() {
  PlaneScene scene;
  TexturedPlane wall;
  wall.origin = Eigen::Vector3d(0, 0, 4.0);
  scene.planes.push_back(wall);
  TexturedPlane front;
  front.origin = Eigen::Vector3d(0, 0, 2.0);
  front.has_hole = true;
  front.hole_u_min = -0.3;
  front.hole_u_max = 0.3;
  front.hole_v_min = -0.3;
  front.hole_v_max = 0.3;
  scene.planes.push_back(front);
  return scene;
}

struct Counts {
  size_t kept = 0;
  size_t wrong = 0;  // Depth off the visible surface by more than 10 cm.
  size_t occluded = 0;
};

Counts CountWrong(double tolerance) {
  const PlaneScene scene = HoleScene();
  const int width = 160, height = 120;
  const Eigen::Matrix3d K = TestCalibration(width, height);
  std::vector<float> gt;
  const MvsView view =
      scene.Render("ref", K, Rigid3d(), width, height, &gt);
  // The scanner sits 40 cm to the right of the camera: through the hole it
  // sees parts of the wall that the camera sees covered by the front plane.
  std::vector<Eigen::Vector3f> points, normals;
  scene.Scan(Eigen::Vector3d(0.4, 0, 0), Eigen::Vector3d::UnitZ(), 50, 150,
             0.8, 0.6, &points, &normals);
  LidarPatchMatchOptions options;
  options.occlusion_relative_tolerance = tolerance;
  DepthInitStats stats;
  const std::vector<DepthSample> samples =
      ProjectLidarSamples(view, points, normals, options, &stats);
  Counts counts;
  counts.kept = samples.size();
  counts.occluded = stats.num_lidar_occluded;
  for (const DepthSample& sample : samples) {
    const float truth = gt[sample.row * width + sample.col];
    if (std::abs(sample.depth - truth) > 0.1f) ++counts.wrong;
    // Normals face the camera: the planes' normal is -z in the camera.
    EXPECT_LT(sample.normal.z(), -0.99f);
  }
  return counts;
}

TEST(DepthInit, NeighbourhoodCheckDropsLidarSeenThroughAGap) {
  const Counts without_check = CountWrong(1e6);
  const Counts with_check = CountWrong(0.05);
  std::cout << "without check: " << without_check.kept << " kept, "
            << without_check.wrong << " wrong; with check: " << with_check.kept
            << " kept, " << with_check.wrong << " wrong, "
            << with_check.occluded << " dropped" << std::endl;
  EXPECT_GT(without_check.wrong, 20u);
  EXPECT_LE(with_check.wrong, without_check.wrong / 20);
  // Most samples survive.
  EXPECT_GT(with_check.kept, without_check.kept * 8 / 10);
}

TEST(DepthInit, FeaturesOverrideLidarAndInterpolationFillsThePlane) {
  const int width = 80, height = 60;
  const Eigen::Matrix3d K = TestCalibration(width, height);
  const MvsView view = MakeMvsView("v", K, Rigid3d(), width, height,
                                   std::vector<float>(width * height, 0.5f));
  // LIDAR points on the slanted plane z = 3 + 0.5 x.
  std::vector<Eigen::Vector3f> points, normals;
  const Eigen::Vector3f normal = Eigen::Vector3f(0.5f, 0, -1).normalized();
  for (int r = 0; r < height; r += 6) {
    for (int c = 0; c < width; c += 6) {
      const Eigen::Vector3d ray = K.inverse() * Eigen::Vector3d(c, r, 1);
      const double z = 3.0 / (1.0 - 0.5 * ray.x());
      points.push_back((z * ray).cast<float>());
      normals.push_back(-normal);  // Wrong side: must be flipped.
    }
  }
  LidarPatchMatchOptions options;
  const std::vector<DepthSample> lidar =
      ProjectLidarSamples(view, points, normals, options);
  ASSERT_EQ(lidar.size(), points.size());
  const Eigen::Vector3f feature = points[12] * 1.01f;
  const std::vector<DepthSample> merged =
      MergeFeatureSamples(view, {feature}, lidar, options);
  ASSERT_EQ(merged.size(), lidar.size());
  size_t num_features = 0;
  for (const DepthSample& sample : merged) {
    if (sample.from_feature) {
      ++num_features;
      EXPECT_NEAR(sample.depth, feature.z(), 1e-5);
      EXPECT_GT(sample.normal.dot(normal), 0.999f);
    }
  }
  EXPECT_EQ(num_features, 1u);
  const PlaneMap map = InterpolateSamples(view, lidar, options);
  size_t num_checked = 0;
  for (int r = 0; r <= 54; ++r) {
    for (int c = 0; c <= 78; ++c) {
      const size_t i = map.Index(r, c);
      ASSERT_GT(map.depth[i], 0) << r << " " << c;
      const Eigen::Vector3d ray = K.inverse() * Eigen::Vector3d(c, r, 1);
      EXPECT_NEAR(map.depth[i], 3.0 / (1.0 - 0.5 * ray.x()), 1e-3);
      EXPECT_GT(map.normal[i].dot(normal), 0.999f);
      ++num_checked;
    }
  }
  EXPECT_GT(num_checked, 4000u);
}

// LIDAR samples every 4 px on two blocks of the plane z = 3 (columns 0-20
// and 60-79), nothing between (sky between two walls): the hull's triangles
// across the 40 px gap subtend ten times the sampling and are left
// uninterpolated; with interpolation_max_edge_factor 0 they bridge it.
TEST(DepthInit, InterpolationDoesNotBridgeUnsampledSpace) {
  const int width = 80, height = 60;
  const Eigen::Matrix3d K = TestCalibration(width, height);
  const MvsView view = MakeMvsView("v", K, Rigid3d(), width, height,
                                   std::vector<float>(width * height, 0.5f));
  std::vector<Eigen::Vector3f> points, normals;
  for (int r = 0; r < height; r += 4) {
    for (int c = 0; c < width; c += 4) {
      if (c > 20 && c < 60) continue;
      const Eigen::Vector3d ray = K.inverse() * Eigen::Vector3d(c, r, 1);
      points.push_back((3.0 * ray).cast<float>());
      normals.emplace_back(0, 0, -1);
    }
  }
  LidarPatchMatchOptions options;
  const std::vector<DepthSample> lidar =
      ProjectLidarSamples(view, points, normals, options);
  ASSERT_EQ(lidar.size(), points.size());
  auto count_valid = [&](const PlaneMap& map, int col_begin, int col_end) {
    size_t num_valid = 0;
    for (int r = 0; r <= 56; ++r) {
      for (int c = col_begin; c <= col_end; ++c) {
        const size_t i = map.Index(r, c);
        if (map.depth[i] > 0) {
          ++num_valid;
          EXPECT_NEAR(map.depth[i], 3.0, 1e-3);
        }
      }
    }
    return num_valid;
  };
  const PlaneMap cut = InterpolateSamples(view, lidar, options);
  EXPECT_EQ(count_valid(cut, 0, 20), 57u * 21u);  // Inside the blocks.
  EXPECT_EQ(count_valid(cut, 25, 55), 0u);       // The gap stays open.
  options.interpolation_max_edge_factor = 0;
  const PlaneMap bridged = InterpolateSamples(view, lidar, options);
  EXPECT_EQ(count_valid(bridged, 25, 55), 57u * 31u);
  options.interpolation_max_edge_factor = -1;
  EXPECT_FALSE(options.Check());
}

// A slanted wall z = 3 + 0.5 x interpolated only in the lower half of the
// image (the LIDAR's vertical field): the upper half starts on the same
// plane. A level ground 1.5 m below the camera, known up to 30 m: the rows
// at and above the horizon, where its plane is edge-on or behind the
// camera, stay empty (random), and every pixel filled lies on the ground.
TEST(DepthInit, ExtrapolationContinuesTheNearestPlane) {
  const int width = 80, height = 60;
  const Eigen::Matrix3d K = TestCalibration(width, height);
  const MvsView view = MakeMvsView("v", K, Rigid3d(), width, height,
                                   std::vector<float>(width * height, 0.5f));
  const Eigen::Vector3f normal = Eigen::Vector3f(0.5f, 0, -1).normalized();
  auto wall_depth = [&](int r, int c) {
    const Eigen::Vector3d ray = K.inverse() * Eigen::Vector3d(c, r, 1);
    return 3.0 / (1.0 - 0.5 * ray.x());
  };
  PlaneMap wall(width, height);
  for (int r = height / 2; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      wall.depth[wall.Index(r, c)] = static_cast<float>(wall_depth(r, c));
      wall.normal[wall.Index(r, c)] = normal;
    }
  }
  EXPECT_EQ(ExtrapolateToEmptyPixels(view, &wall),
            static_cast<size_t>(width * height / 2));
  for (int r = 0; r < height / 2; ++r) {
    for (int c = 0; c < width; ++c) {
      EXPECT_NEAR(wall.depth[wall.Index(r, c)], wall_depth(r, c), 1e-4)
          << r << " " << c;
      EXPECT_GT(wall.normal[wall.Index(r, c)].dot(normal), 0.9999f);
    }
  }

  const float ground_height = 1.5f;
  PlaneMap ground = GroundPlaneMap(view, ground_height, 30.0f);
  const size_t num_known = ground.NumValid();
  const size_t num_filled = ExtrapolateToEmptyPixels(view, &ground);
  EXPECT_GT(num_filled, 0u);
  EXPECT_EQ(ground.NumValid(), num_known + num_filled);
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      const Eigen::Vector3f ray =
          view.Ray(static_cast<float>(r), static_cast<float>(c));
      const float depth = ground.depth[ground.Index(r, c)];
      if (!(ray.y() > 0)) {
        EXPECT_EQ(depth, 0.0f) << r << " " << c;
      } else if (depth > 0) {
        EXPECT_NEAR(depth, ground_height / ray.y(), 1e-3f * depth);
      }
    }
  }
}

// LIDAR samples every 6 px on a wall at z = 2 (columns < 40) and one at
// z = 2.5 behind it (columns >= 40; a step of 25 %, more than
// interpolation_max_depth_ratio, within the edge test's sampling ratio, as a
// window recess's lip): the triangles across the step take their
// nearest vertex's plane and are marked as guesses; the samples and the
// triangles on one wall are not. InitializeReference keeps the guesses as
// starting planes but out of the soft prior, unless
// lidar_prior_across_depth_edges is set.
TEST(DepthInit, GuessesAcrossADepthEdgeStayOutOfThePrior) {
  const int width = 80, height = 60;
  const Eigen::Matrix3d K = TestCalibration(width, height);
  const MvsView view = MakeMvsView("v", K, Rigid3d(), width, height,
                                   std::vector<float>(width * height, 0.5f));
  FusedLidarCloud cloud;
  for (int r = 0; r < height; r += 6) {
    for (int c = 0; c < width; c += 6) {
      const Eigen::Vector3d ray = K.inverse() * Eigen::Vector3d(c, r, 1);
      cloud.points.push_back(((c < 40 ? 2.0 : 2.5) * ray).cast<float>());
      cloud.normals.emplace_back(0, 0, -1);
    }
  }
  LidarPatchMatchOptions options;
  options.occlusion_relative_tolerance = 10.0;  // Keep the far wall's samples.
  const std::vector<DepthSample> samples =
      ProjectLidarSamples(view, cloud.points, cloud.normals, options);
  ASSERT_EQ(samples.size(), cloud.points.size());
  std::vector<uint8_t> guessed;
  const PlaneMap map = InterpolateSamples(view, samples, options, &guessed);
  ASSERT_EQ(guessed.size(), map.depth.size());
  size_t num_guessed = 0;
  for (int r = 0; r <= 54; ++r) {
    for (int c = 0; c <= 78; ++c) {
      const size_t i = map.Index(r, c);
      ASSERT_GT(map.depth[i], 0) << r << " " << c;
      if (c < 36 || c > 42) {  // Off the step triangles and their edges.
        EXPECT_EQ(guessed[i], 0) << r << " " << c;
        EXPECT_NEAR(map.depth[i], c < 36 ? 2.0 : 2.5, 1e-3);
      }
      num_guessed += guessed[i];
    }
  }
  EXPECT_GT(num_guessed, 55u * 4u);
  for (const DepthSample& sample : samples) {
    EXPECT_EQ(guessed[map.Index(sample.row, sample.col)], 0);
  }

  const ReferenceInit init = InitializeReference(view, {}, &cloud, -1, options);
  options.lidar_prior_across_depth_edges = true;
  const ReferenceInit held = InitializeReference(view, {}, &cloud, -1, options);
  for (size_t i = 0; i < guessed.size(); ++i) {
    EXPECT_EQ(init.state.depth[i], map.depth[i]);  // Same starting planes.
    EXPECT_EQ(held.prior_depth[i], map.depth[i]);
    EXPECT_EQ(init.prior_depth[i], guessed[i] ? 0.0f : map.depth[i]);
  }
}

// A wall seen at grazing incidence 15-30 m away (its depth changing by 19
// to 75 cm per pixel), sampled by 20 noisy LIDAR points per pixel: the
// samples carried to their pixel's centre along the wall's plane, the
// median of the front surface, stay within the noise of the true depth;
// the nearest sample's own depth does not (rounding to the pixel, and the
// nearest of several noisy samples lies in front).
TEST(DepthInit, SamplesAtPixelCentresFollowAGrazingWall) {
  // The wall with 4 cm of range noise along the points' rays (the scanner at
  // the camera).
  const GrazingWall wall = MakeGrazingWall();
  const int height = wall.view.height;
  const Eigen::Matrix3d& K = wall.K;
  const MvsView& view = wall.view;
  const Eigen::Vector3f& normal = wall.normal;
  auto wall_depth = [&wall](const Eigen::Vector3d& ray) {
    return wall.Depth(ray);
  };
  UniformStream stream(12345);
  auto uniform = [&stream]() { return stream.Next(); };
  std::vector<Eigen::Vector3f> points, normals;
  const int min_col = 215, max_col = 265;
  for (int k = 0; k < 20 * (max_col - min_col) * height; ++k) {
    const double col = min_col + (max_col - min_col) * uniform();
    const double row = height * uniform() - 0.5;
    const Eigen::Vector3d ray = K.inverse() * Eigen::Vector3d(col, row, 1);
    const double depth = wall_depth(ray);
    if (depth < 15.0 || depth > 30.0) continue;
    const Eigen::Vector3d point = depth * ray;
    const double noise = 0.04 * std::sqrt(3.0) * (2.0 * uniform() - 1.0);
    points.push_back((point + noise * point.normalized()).cast<float>());
    normals.push_back(normal);
  }
  LidarPatchMatchOptions options;
  auto share_within_5cm = [&](bool at_centres) {
    options.lidar_samples_at_pixel_centres = at_centres;
    const std::vector<DepthSample> samples =
        ProjectLidarSamples(view, points, normals, options);
    EXPECT_GT(samples.size(), 4000u);
    size_t within = 0;
    for (const DepthSample& sample : samples) {
      const double truth =
          wall_depth(K.inverse() * Eigen::Vector3d(sample.col, sample.row, 1));
      within += std::abs(sample.depth - truth) <= 0.05 ? 1 : 0;
    }
    return static_cast<double>(within) / std::max<size_t>(samples.size(), 1);
  };
  const double nearest = share_within_5cm(false);
  const double centres = share_within_5cm(true);
  std::cout << "within 5 cm: nearest " << nearest << ", at centres " << centres
            << std::endl;
  EXPECT_LT(nearest, 0.3);
  EXPECT_GT(centres, 0.95);
}

}  // namespace
}  // namespace colmap_lidar
