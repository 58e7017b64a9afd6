#include "src/synth/renderer.h"

#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "colmap_ext/mvs/dense_maps.h"
#include "src/synth/scene_presets.h"
#include "src/synth/synthesize.h"
#include "src/synth/trajectory.h"

namespace colmap_lidar {
namespace {

SynthesisOptions SmallOptions() {
  SynthesisOptions options;
  options.image_width = 212;
  options.image_height = 120;
  options.supersampling = 2;
  options.num_threads = 2;
  return options;
}

double MeanGradientEnergy(const cv::Mat& grey, const cv::Rect& roi) {
  cv::Mat gx, gy;
  cv::Sobel(grey(roi), gx, CV_64F, 1, 0);
  cv::Sobel(grey(roi), gy, CV_64F, 0, 1);
  return cv::mean(gx.mul(gx) + gy.mul(gy))[0];
}

TEST(Renderer, DepthMapsAreConsistentBetweenFrames) {
  const SynthesisOptions options = SmallOptions();
  const SynthScene scene = BuildQuadScene();
  const RayTracer tracer(scene.mesh);
  const Camera camera = SynthCamera(options);
  const std::vector<Rigid3d> poses = GenerateTrajectory(scene.path, 60, 0);
  const RenderedFrame frame0 =
      RenderFrame(tracer, camera, poses[10], options, 10, true);
  const RenderedFrame frame1 =
      RenderFrame(tracer, camera, poses[11], options, 11, true);
  const Eigen::Matrix3d K = camera.CalibrationMatrix();
  const Rigid3d cam1_from_cam0 = poses[11].Inverse() * poses[10];
  int num_compared = 0;
  int num_consistent = 0;
  int num_occluded = 0;
  int num_on_surface = 0;
  int num_checked_surface = 0;
  for (int row = 0; row < frame0.depth.rows; row += 3) {
    for (int col = 0; col < frame0.depth.cols; col += 3) {
      const float depth = frame0.depth.at<float>(row, col);
      if (depth <= 0.0f) continue;
      // MVS convention: the ray through (col, row), no +0.5.
      const Eigen::Vector3d point_in_cam0 =
          depth * MvsPixelRay(K, row, col);
      if (num_checked_surface < 300 && (row * 7 + col) % 11 == 0) {
        ++num_checked_surface;
        const Eigen::Vector3d point_in_world = poses[10] * point_in_cam0;
        if (tracer.DistanceToSurface(point_in_world) < 1e-4) ++num_on_surface;
      }
      const Eigen::Vector3d point_in_cam1 = cam1_from_cam0 * point_in_cam0;
      if (point_in_cam1.z() <= 0.1) continue;
      const Eigen::Vector3d projected = K * (point_in_cam1 / point_in_cam1.z());
      const double u = projected.x();
      const double v = projected.y();
      const int c0 = static_cast<int>(std::floor(u));
      const int r0 = static_cast<int>(std::floor(v));
      if (c0 < 0 || r0 < 0 || c0 + 1 >= frame1.depth.cols ||
          r0 + 1 >= frame1.depth.rows) {
        continue;
      }
      // Inverse depth is affine in the pixel coordinates on a plane, so
      // bilinear interpolation of 1/depth is exact inside a planar patch.
      double inv[4];
      bool valid = true;
      for (int k = 0; k < 4; ++k) {
        const float d1 = frame1.depth.at<float>(r0 + k / 2, c0 + k % 2);
        valid = valid && d1 > 0.0f;
        inv[k] = 1.0 / d1;
      }
      if (!valid) continue;
      const double a = u - c0;
      const double b = v - r0;
      const double interpolated =
          1.0 / ((1 - b) * ((1 - a) * inv[0] + a * inv[1]) +
                 b * ((1 - a) * inv[2] + a * inv[3]));
      ++num_compared;
      const double relative = (interpolated - point_in_cam1.z()) /
                              point_in_cam1.z();
      if (std::abs(relative) < 1e-4) {
        ++num_consistent;
      } else if (relative < 0) {
        ++num_occluded;  // Something in front in frame 1, or a crease.
      }
    }
  }
  ASSERT_GT(num_compared, 1000);
  EXPECT_GT(num_consistent, 0.85 * num_compared)
      << num_consistent << " of " << num_compared << ", occluded "
      << num_occluded;
  ASSERT_GT(num_checked_surface, 100);
  EXPECT_EQ(num_on_surface, num_checked_surface);
}

TEST(Renderer, ImagesAreTexturedAndPlasterIsSmooth) {
  // A brick wall (left) and a plaster wall (right), 6 m in front, lit.
  SceneBuilder builder;
  builder.AddQuadFacing({-10, -50, 0}, {50, -50, 0}, {50, 50, 0},
                        {-10, 50, 0}, Eigen::Vector3d::UnitZ(),
                        Material::kPaving, 1);
  builder.AddFacade({6, 6, 0}, -Eigen::Vector3d::UnitY(),
                    -Eigen::Vector3d::UnitX(), 6.0, 8.0, Material::kBrick, 2,
                    {});
  builder.AddFacade({6, 0, 0}, -Eigen::Vector3d::UnitY(),
                    -Eigen::Vector3d::UnitX(), 6.0, 8.0, Material::kPlaster, 3,
                    {});
  const RayTracer tracer(builder.mesh());
  SynthesisOptions options = SmallOptions();
  options.image_noise_stddev = 0.0;
  options.sun_azimuth_deg = 180.0;  // The sun lights the walls' fronts.
  const Camera camera = SynthCamera(options);
  const Rigid3d pose = CameraPoseFromYawPitchRoll({0, 0, 2.5}, 0, 0, 0);
  const RenderedFrame frame =
      RenderFrame(tracer, camera, pose, options, 0, false);
  cv::Mat grey;
  cv::cvtColor(frame.image, grey, cv::COLOR_BGR2GRAY);
  // Upper half, away from the corner between the walls: the left third
  // sees brick (y > 0), the right third plaster.
  const int w = grey.cols;
  const int h = grey.rows;
  const double brick =
      MeanGradientEnergy(grey, cv::Rect(5, 5, w / 3 - 10, h / 3));
  const double plaster =
      MeanGradientEnergy(grey, cv::Rect(2 * w / 3 + 5, 5, w / 3 - 10, h / 3));
  EXPECT_GT(brick, 50.0 * std::max(plaster, 1.0))
      << "brick " << brick << " plaster " << plaster;
  cv::Scalar mean, stddev;
  cv::meanStdDev(grey, mean, stddev);
  EXPECT_GT(stddev[0], 10.0);
  EXPECT_GT(mean[0], 40.0);
  EXPECT_LT(mean[0], 220.0);
  EXPECT_LT(cv::countNonZero(grey >= 255), grey.total() / 100);
}

TEST(Renderer, QuadFramesAreNonUniformAndDeterministic) {
  SynthesisOptions options = SmallOptions();
  const SynthScene scene = BuildQuadScene();
  const RayTracer tracer(scene.mesh);
  const Camera camera = SynthCamera(options);
  const std::vector<Rigid3d> poses = GenerateTrajectory(scene.path, 60, 0);
  const RenderedFrame a = RenderFrame(tracer, camera, poses[3], options, 3,
                                      false);
  options.num_threads = 1;
  const RenderedFrame b = RenderFrame(tracer, camera, poses[3], options, 3,
                                      false);
  EXPECT_EQ(cv::norm(a.image, b.image, cv::NORM_INF), 0.0);
  options.seed = 5;
  const RenderedFrame c = RenderFrame(tracer, camera, poses[3], options, 3,
                                      false);
  EXPECT_GT(cv::norm(a.image, c.image, cv::NORM_L1), 0.0);
  cv::Mat grey;
  cv::cvtColor(a.image, grey, cv::COLOR_BGR2GRAY);
  cv::Scalar mean, stddev;
  cv::meanStdDev(grey, mean, stddev);
  EXPECT_GT(stddev[0], 15.0);
  EXPECT_GT(MeanGradientEnergy(grey, cv::Rect(0, 0, grey.cols, grey.rows)),
            500.0);
}

TEST(Renderer, RejectsInvalidCameras) {
  SceneBuilder builder;
  builder.AddBox({0, 0, 0}, {1, 1, 1}, Material::kConcrete, 0, false);
  const RayTracer tracer(builder.mesh());
  Camera camera = Camera::FromModelName("PINHOLE", 32, 32, {30, 30, 16, 16});
  camera.params.pop_back();
  EXPECT_THROW(RenderFrame(tracer, camera, Rigid3d(), SynthesisOptions(), 0,
                           false),
               Error);
}

// The PINHOLE path is the renderer's original arithmetic: the depth map is
// bit-identical to rays ((col - cx) / fx, (row - cy) / fy, 1).
TEST(Renderer, PinholeDepthUsesTheOriginalRays) {
  const SynthesisOptions options = SmallOptions();
  const SynthScene scene = BuildQuadScene();
  const RayTracer tracer(scene.mesh);
  const Camera camera = SynthCamera(options);
  ASSERT_EQ(camera.ModelName(), "PINHOLE");
  const Rigid3d pose = GenerateTrajectory(scene.path, 60, 0)[7];
  const RenderedFrame frame =
      RenderFrame(tracer, camera, pose, options, 7, true);
  const Eigen::Matrix3d rotation = pose.rotation.toRotationMatrix();
  const double fx = camera.params[0], fy = camera.params[1];
  const double cx = camera.params[2], cy = camera.params[3];
  int num_hits = 0;
  for (int row = 0; row < frame.depth.rows; row += 5) {
    for (int col = 0; col < frame.depth.cols; col += 5) {
      const RayHit hit = tracer.Intersect(
          pose.translation,
          rotation * Eigen::Vector3d((col - cx) / fx, (row - cy) / fy, 1.0));
      const float expected =
          hit.Valid() ? static_cast<float>(hit.distance) : 0.0f;
      ASSERT_EQ(frame.depth.at<float>(row, col), expected) << row << " " << col;
      num_hits += hit.Valid() ? 1 : 0;
    }
  }
  EXPECT_GT(num_hits, 100);
}

// A camera at the origin looking along +z at a light plaster panel (z = 5,
// x in [2, 4], y in [1.5, 3]; a flat box face without visible sides) before
// a dark glass wall at z = 10. Both face -z, away from the sun (whose z is
// positive), so both are lit by the sky only: a sharp albedo edge, no
// shadows.
struct DistortedFixture {
  SceneMesh mesh = [] {
    SceneBuilder builder;
    builder.AddQuadFacing({2.0, 1.5, 5.0}, {4.0, 1.5, 5.0}, {4.0, 3.0, 5.0},
                          {2.0, 3.0, 5.0}, {0, 0, -1}, Material::kPlaster, 1);
    builder.AddQuadFacing({-30, -30, 10}, {30, -30, 10}, {30, 30, 10},
                          {-30, 30, 10}, {0, 0, -1}, Material::kGlass, 2);
    return builder.mesh();
  }();
  RayTracer tracer{mesh};
};

SynthesisOptions DistortedOptions() {
  SynthesisOptions options;
  options.image_width = 320;
  options.image_height = 240;
  options.horizontal_fov_deg = 60.0;
  options.camera_model = "SIMPLE_RADIAL";
  options.camera_k1 = -0.2;
  options.supersampling = 2;
  options.image_noise_stddev = 0.0;
  options.num_threads = 2;
  return options;
}

// Panel or wall seen along the camera-frame ray (u, v, 1).
double ExpectedDepth(double u, double v) {
  const bool on_box = 5.0 * u >= 2.0 && 5.0 * u <= 4.0 && 5.0 * v >= 1.5 &&
                      5.0 * v <= 3.0;
  return on_box ? 5.0 : 10.0;
}

TEST(Renderer, SimpleRadialDepthMapFollowsTheCameraModel) {
  DistortedFixture fixture;
  const SynthesisOptions options = DistortedOptions();
  ASSERT_TRUE(options.Check());
  const Camera camera = SynthCamera(options);
  ASSERT_EQ(camera.ModelName(), "SIMPLE_RADIAL");
  const RenderedFrame frame =
      RenderFrame(fixture.tracer, camera, Rigid3d(), options, 0, true);
  ASSERT_EQ(frame.depth.cols, 320);
  ASSERT_EQ(frame.depth.rows, 240);
  const Eigen::Matrix3d K = camera.CalibrationMatrix();
  int num_box = 0, num_mismatch = 0, num_pinhole_mismatch = 0;
  for (int row = 0; row < frame.depth.rows; ++row) {
    for (int col = 0; col < frame.depth.cols; ++col) {
      const double depth = frame.depth.at<float>(row, col);
      // MVS convention for the distorted camera: X = depth * CamFromImg.
      const Eigen::Vector2d ray = camera.CamFromImg(Eigen::Vector2d(col, row));
      const double expected = ExpectedDepth(ray.x(), ray.y());
      num_box += expected == 5.0 ? 1 : 0;
      // Exactly on an edge the two can disagree by rounding.
      if (std::abs(depth - expected) > 1e-4) ++num_mismatch;
      const Eigen::Vector3d pinhole_ray = MvsPixelRay(K, row, col);
      if (ExpectedDepth(pinhole_ray.x() / pinhole_ray.z(),
                        pinhole_ray.y() / pinhole_ray.z()) != expected) {
        ++num_pinhole_mismatch;
      }
    }
  }
  EXPECT_GT(num_box, 1500);
  EXPECT_LE(num_mismatch, 2);
  // The distortion matters: ignoring it would misplace many pixels.
  EXPECT_GT(num_pinhole_mismatch, 500);
}

TEST(Renderer, SimpleRadialImageShowsTheBoxCornerWhereTheModelProjectsIt) {
  DistortedFixture fixture;
  const SynthesisOptions options = DistortedOptions();
  const Camera camera = SynthCamera(options);
  const RenderedFrame frame =
      RenderFrame(fixture.tracer, camera, Rigid3d(), options, 0, true);
  cv::Mat grey;
  cv::cvtColor(frame.image, grey, cv::COLOR_BGR2GRAY);
  // The panel's upper-left corner, SfM pixel convention.
  const Eigen::Vector2d corner =
      camera.ImgFromCam(Eigen::Vector3d(2.0, 1.5, 5.0));
  const Eigen::Vector2d pinhole_corner(
      camera.params[0] * 0.4 + camera.params[1],
      camera.params[0] * 0.3 + camera.params[2]);
  ASSERT_GT((corner - pinhole_corner).norm(), 5.0);
  ASSERT_GT(corner.x(), 20.0);
  ASSERT_GT(corner.y(), 20.0);
  const int col = static_cast<int>(std::floor(corner.x()));
  const int row = static_cast<int>(std::floor(corner.y()));
  const auto mean = [&grey](int c, int r) {
    return cv::mean(grey(cv::Rect(c - 1, r - 1, 3, 3)))[0];
  };
  const double box = mean(col + 12, row + 12);
  const double wall = mean(col - 12, row - 12);
  ASSERT_GT(box - wall, 15.0);
  const double threshold = 0.5 * (box + wall);
  // Inside the corner (1.5 px away diagonally) the box, outside the wall.
  EXPECT_GT(grey.at<uint8_t>(row + 2, col + 2), threshold);
  EXPECT_LT(grey.at<uint8_t>(row + 2, col - 2), threshold);
  EXPECT_LT(grey.at<uint8_t>(row - 2, col + 2), threshold);
  EXPECT_LT(grey.at<uint8_t>(row - 2, col - 2), threshold);
  // Along the row 6 px below the corner the image's edge crossing lies
  // within a pixel of the model's projection of the box's left edge.
  const int test_row = row + 6;
  int crossing = -1;
  for (int c = col - 10; c < col + 10; ++c) {
    if (grey.at<uint8_t>(test_row, c) < threshold &&
        grey.at<uint8_t>(test_row, c + 1) >= threshold) {
      crossing = c + 1;
      break;
    }
  }
  ASSERT_GE(crossing, 0);
  // The left edge x = 2, z = 5 at the height whose projection is the
  // centre of test_row (bisection on y: the projection is monotonic here).
  double lo = 1.5, hi = 3.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (camera.ImgFromCam(Eigen::Vector3d(2.0, mid, 5.0)).y() < test_row + 0.5
         ? lo
         : hi) = mid;
  }
  const double edge_x = camera.ImgFromCam(Eigen::Vector3d(2.0, lo, 5.0)).x();
  // Pixel `crossing` is the first whose centre (crossing + 0.5) is mostly
  // box: the edge lies in [crossing - 0.5, crossing + 1].
  EXPECT_NEAR(crossing + 0.25, edge_x, 1.0);
}

// Benchmark sizes: 640 x 480 .. 1280 x 720 (depth maps at the same size).
TEST(Renderer, RendersBenchmarkImageSizes) {
  DistortedFixture fixture;
  for (const auto& [width, height] :
       std::vector<std::pair<int, int>>{{640, 480}, {1280, 720}}) {
    SynthesisOptions options = DistortedOptions();
    options.image_width = width;
    options.image_height = height;
    options.supersampling = 1;
    options.camera_model = "OPENCV";
    options.camera_k1 = -0.1;
    options.camera_k2 = 0.01;
    options.camera_p1 = 0.001;
    ASSERT_TRUE(options.Check());
    const Camera camera = SynthCamera(options);
    const RenderedFrame frame =
        RenderFrame(fixture.tracer, camera, Rigid3d(), options, 0, true);
    EXPECT_EQ(frame.image.cols, width);
    EXPECT_EQ(frame.image.rows, height);
    EXPECT_EQ(frame.depth.cols, width);
    EXPECT_EQ(frame.depth.rows, height);
    // Spot checks of the depth map against the model.
    for (int row = 0; row < height; row += 37) {
      for (int col = 0; col < width; col += 41) {
        const Eigen::Vector2d ray =
            camera.CamFromImg(Eigen::Vector2d(col, row));
        const double expected = ExpectedDepth(ray.x(), ray.y());
        EXPECT_NEAR(frame.depth.at<float>(row, col), expected, 1e-4);
      }
    }
  }
}

TEST(Renderer, CameraOptionsAreChecked) {
  SynthesisOptions options = DistortedOptions();
  EXPECT_TRUE(options.Check());
  options.camera_k2 = 0.01;  // SIMPLE_RADIAL has no k2.
  EXPECT_FALSE(options.Check());
  options.camera_model = "RADIAL";
  EXPECT_TRUE(options.Check());
  options.camera_p1 = 0.001;  // RADIAL has no p1.
  EXPECT_FALSE(options.Check());
  options.camera_model = "OPENCV";
  EXPECT_TRUE(options.Check());
  options.camera_model = "FISHEYE";
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(SynthCamera(options), Error);
  options = SynthesisOptions();
  options.camera_k1 = -0.1;  // PINHOLE has no k1.
  EXPECT_FALSE(options.Check());
  // Strong barrel distortion over a 90 deg field folds over: refused.
  options.camera_model = "SIMPLE_RADIAL";
  EXPECT_TRUE(options.Check());
  options.camera_k1 = -0.4;
  EXPECT_FALSE(options.Check());
  EXPECT_NE(SynthCameraProblem(options).find("not invertible"),
            std::string::npos);
}

}  // namespace
}  // namespace colmap_lidar
