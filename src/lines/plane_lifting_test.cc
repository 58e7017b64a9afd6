#include "src/lines/plane_lifting.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <glog/logging.h>
#include <gtest/gtest.h>

#include "src/lidar/sensor_estimation.h"
#include "src/lines/lsd_detector.h"
#include "src/lines/synthetic_view.h"

namespace colmap_lidar {
namespace {

struct Outcome {
  std::vector<ViewLineSegment> lifted;
  std::vector<PlaneLiftResult> results;
  // "crease 3, occlusion 1, ..." for failure messages.
  std::string Counts() const {
    std::string text;
    for (int r = 0; r <= static_cast<int>(PlaneLiftResult::kNotTried); ++r) {
      const auto result = static_cast<PlaneLiftResult>(r);
      text += std::string(r > 0 ? ", " : "") + PlaneLiftResultName(result) +
              " " +
              std::to_string(
                  std::count(results.begin(), results.end(), result));
    }
    return text;
  }
};

// Plane lifting of every LSD segment of the view.
Outcome LiftAll(const SyntheticView& view, const PlaneLiftingOptions& options,
                double range_noise_m) {
  const std::vector<LineSegment2D> segments =
      DetectLineSegments(view.image, LsdOptions());
  const ProjectedScan projected = ProjectScan(
      view.scan, view.camera, view.cam_from_lidar, ScanProjectionOptions());
  Outcome outcome;
  for (const LineSegment2D& segment : segments) {
    ViewLineSegment lifted;
    const PlaneLiftResult result = LiftSegmentByPlanes(
        segment, view.camera, projected, options, range_noise_m,
        /*max_reprojection_angle_deg=*/3.0,
        /*max_reprojection_distance_px=*/4.0,
        /*min_ray_line_angle_deg=*/5.0, &lifted);
    outcome.results.push_back(result);
    if (result == PlaneLiftResult::kCrease ||
        result == PlaneLiftResult::kOcclusion) {
      outcome.lifted.push_back(lifted);
    }
  }
  return outcome;
}

// A VLP-16-like scan: 16 rings 2 deg apart, 2 cm range noise. Its rings
// cross a box's horizontal edges rarely, so edge points leave them unlifted.
SyntheticViewOptions SparseNoisyView() {
  SyntheticViewOptions options;
  options.boxes = DefaultSyntheticBoxes();
  options.paint_stripe = true;
  options.num_rings = 16;
  options.min_elevation_deg = -15.0;
  options.max_elevation_deg = 15.0;
  options.num_columns = 1800;
  options.range_noise = 0.02;
  options.seed = 7;
  return options;
}

PlaneLiftingOptions WithOcclusions() {
  PlaneLiftingOptions options;
  options.keep_occlusions = true;
  return options;
}

TEST(PlaneLifting, LiftsCreasesAndHorizontalEdgesOfASparseNoisyScan) {
  const SyntheticView view = MakeSyntheticView(SparseNoisyView());
  const Outcome outcome = LiftAll(view, WithOcclusions(), 0.02);
  ASSERT_GE(outcome.lifted.size(), 6u) << outcome.Counts();
  int num_within_5cm = 0;
  int num_horizontal = 0;
  int num_creases = 0;
  for (size_t i = 0; i < outcome.lifted.size(); ++i) {
    const ViewLineSegment& segment = outcome.lifted[i];
    const bool within =
        DistanceToNearestEdge(view, segment.start3D_in_cam) < 0.05 &&
        DistanceToNearestEdge(view, segment.end3D_in_cam) < 0.05;
    VLOG(1) << segment.segment2D.start.transpose() << " -> "
            << segment.segment2D.end.transpose() << ": direction "
            << segment.Direction3D().transpose() << ", edge distances "
            << DistanceToNearestEdge(view, segment.start3D_in_cam) << " / "
            << DistanceToNearestEdge(view, segment.end3D_in_cam);
    num_within_5cm += within ? 1 : 0;
    // Camera frame: y points down; a horizontal 3D edge has a small y.
    if (std::abs(segment.Direction3D().y()) < 0.3) {
      ++num_horizontal;
    }
    // The 3D endpoints reproject onto the (clipped) 2D endpoints.
    EXPECT_LT((view.camera.ImgFromCam(segment.start3D_in_cam) -
               segment.segment2D.start)
                  .norm(),
              1e-6);
  }
  for (const PlaneLiftResult result : outcome.results) {
    num_creases += result == PlaneLiftResult::kCrease ? 1 : 0;
  }
  EXPECT_GE(num_within_5cm, 0.9 * outcome.lifted.size());
  // The boxes' bottom creases: the 16 rings cross them rarely, so edge
  // points alone lift none of them.
  EXPECT_GE(num_horizontal, 1);
  EXPECT_GE(num_creases, 2);
}

TEST(PlaneLifting, CreasesOnlyByDefault) {
  const SyntheticView view = MakeSyntheticView(SparseNoisyView());
  const Outcome with = LiftAll(view, WithOcclusions(), 0.02);
  const Outcome without = LiftAll(view, PlaneLiftingOptions(), 0.02);
  EXPECT_EQ(std::count(without.results.begin(), without.results.end(),
                       PlaneLiftResult::kOcclusion),
            0);
  EXPECT_EQ(std::count(with.results.begin(), with.results.end(),
                       PlaneLiftResult::kCrease),
            std::count(without.results.begin(), without.results.end(),
                       PlaneLiftResult::kCrease));
  EXPECT_LT(without.lifted.size(), with.lifted.size());
  for (const ViewLineSegment& segment : without.lifted) {
    EXPECT_LT(DistanceToNearestEdge(view, segment.start3D_in_cam), 0.05);
    EXPECT_LT(DistanceToNearestEdge(view, segment.end3D_in_cam), 0.05);
  }
}

TEST(PlaneLifting, PaintedStripeIsTextureNotAnEdge) {
  const SyntheticView view = MakeSyntheticView(SparseNoisyView());
  const Outcome outcome = LiftAll(view, PlaneLiftingOptions(), 0.02);
  for (const ViewLineSegment& segment : outcome.lifted) {
    // The stripe's image lines are the long horizontal ones below the boxes.
    EXPECT_FALSE(segment.segment2D.Length() > 400 &&
                 segment.segment2D.start.y() > 340)
        << segment.segment2D.start.transpose() << " -> "
        << segment.segment2D.end.transpose();
  }
  int num_texture = 0;
  for (const PlaneLiftResult result : outcome.results) {
    num_texture += result == PlaneLiftResult::kTexture ? 1 : 0;
  }
  EXPECT_GE(num_texture, 2) << outcome.Counts();
}

TEST(PlaneLifting, SameInputSameSegments) {
  const SyntheticView view = MakeSyntheticView(SparseNoisyView());
  const Outcome first = LiftAll(view, PlaneLiftingOptions(), 0.02);
  const Outcome second = LiftAll(view, PlaneLiftingOptions(), 0.02);
  ASSERT_EQ(first.lifted.size(), second.lifted.size());
  for (size_t i = 0; i < first.lifted.size(); ++i) {
    EXPECT_EQ(first.lifted[i].start3D_in_cam, second.lifted[i].start3D_in_cam);
    EXPECT_EQ(first.lifted[i].end3D_in_cam, second.lifted[i].end3D_in_cam);
  }
}

TEST(PlaneLifting, NoiseEstimatedFromTheScanFindsTheEdges) {
  // The thresholds come from the data: lifting with the noise that the scan
  // shows finds the edges as with the simulated 2 cm.
  const SyntheticView view = MakeSyntheticView(SparseNoisyView());
  const RangeNoiseEstimate noise =
      EstimateRangeNoise({view.scan}, RangeNoiseOptions());
  ASSERT_GT(noise.num_voxels, 0);
  // The boxes leave few planar voxels (the estimator's own tests hold it
  // within 30 % on a street): here within a factor of two.
  EXPECT_GT(noise.sigma_m, 0.01);
  EXPECT_LT(noise.sigma_m, 0.04);
  const Outcome outcome = LiftAll(view, WithOcclusions(), noise.sigma_m);
  EXPECT_GE(outcome.lifted.size(), 6u) << outcome.Counts();
}

// A wall at depth 5 m left of the optical axis (x < 0) in front of a wall
// at 6 m on its right: one step edge, straight down the image's centre
// column. Points on a regular grid of directions (0.2 deg x 1 deg), camera
// frame = LIDAR frame, no noise.
ProjectedScan StepScan(const Camera& camera) {
  LidarScan scan;
  for (double azimuth = -20.0; azimuth <= 20.0; azimuth += 0.2) {
    for (double elevation = -15.0; elevation <= 15.0; elevation += 1.0) {
      const double a = azimuth * M_PI / 180.0;
      const double e = elevation * M_PI / 180.0;
      const Eigen::Vector3d direction(std::sin(a) * std::cos(e), -std::sin(e),
                                      std::cos(a) * std::cos(e));
      const double depth = direction.x() < 0.0 ? 5.0 : 6.0;
      scan.points.push_back(
          (direction * depth / direction.z()).cast<float>());
    }
  }
  return ProjectScan(scan, camera, Rigid3d(), ScanProjectionOptions());
}

TEST(PlaneLifting, OccludingEdgeOnlyWhereTheStepIs) {
  const Camera camera = Camera::FromModelName("PINHOLE", 640, 480,
                                              {250.0, 250.0, 320.0, 240.0});
  const ProjectedScan projected = StepScan(camera);
  PlaneLiftingOptions options = WithOcclusions();
  options.max_band_fraction = 0.1;  // 80 px; the narrowest band is 10 px.
  auto lift = [&](double column, ViewLineSegment* lifted) {
    LineSegment2D segment;
    segment.start = Eigen::Vector2d(column, 170.0);
    segment.end = Eigen::Vector2d(column, 310.0);
    return LiftSegmentByPlanes(segment, camera, projected, options,
                               /*range_noise_m=*/0.01, 3.0, 4.0, 5.0, lifted);
  };
  // At the step: the near wall's boundary, on the near wall.
  ViewLineSegment lifted;
  ASSERT_EQ(lift(320.0, &lifted), PlaneLiftResult::kOcclusion);
  EXPECT_NEAR(lifted.start3D_in_cam.z(), 5.0, 0.01);
  EXPECT_NEAR(lifted.end3D_in_cam.z(), 5.0, 0.01);
  // A line on the far wall 3 px right of the step (6 cm at 5 m): its near
  // band is mostly the near wall, and the two planes make a step, but the
  // far wall's points between the step and the line show that the near
  // wall ends before the line. Lifted, it would hang in the air 6 cm off
  // the near wall's edge.
  EXPECT_EQ(lift(323.0, &lifted), PlaneLiftResult::kBoundary);
  // Farther out on either wall: one surface on both sides.
  EXPECT_EQ(lift(340.0, &lifted), PlaneLiftResult::kTexture);
  EXPECT_EQ(lift(300.0, &lifted), PlaneLiftResult::kTexture);
}

TEST(PlaneLifting, OptionsCheck) {
  EXPECT_TRUE(PlaneLiftingOptions().Check());
  PlaneLiftingOptions options;
  options.min_side_points = 2;
  EXPECT_FALSE(options.Check());
  options = PlaneLiftingOptions();
  options.max_band_fraction = 0.0;
  EXPECT_FALSE(options.Check());
  options = PlaneLiftingOptions();
  options.min_crease_angle_deg = 120.0;
  EXPECT_FALSE(options.Check());
  options = PlaneLiftingOptions();
  options.range_noise_m = -0.01;
  EXPECT_FALSE(options.Check());
  options = PlaneLiftingOptions();
  options.boundary_band_fraction = 0.0;
  EXPECT_FALSE(options.Check());
  options = PlaneLiftingOptions();
  options.max_boundary_violations = 1.0;
  EXPECT_FALSE(options.Check());
}

}  // namespace
}  // namespace colmap_lidar
