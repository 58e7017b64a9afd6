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

TEST(Renderer, RejectsNonPinholeCameras) {
  SceneBuilder builder;
  builder.AddBox({0, 0, 0}, {1, 1, 1}, Material::kConcrete, 0, false);
  const RayTracer tracer(builder.mesh());
  const Camera camera =
      Camera::FromModelName("SIMPLE_RADIAL", 32, 32, {30, 16, 16, 0.1});
  EXPECT_THROW(RenderFrame(tracer, camera, Rigid3d(), SynthesisOptions(), 0,
                           false),
               Error);
}

}  // namespace
}  // namespace colmap_lidar
