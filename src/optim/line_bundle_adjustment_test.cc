#include "src/optim/line_bundle_adjustment.h"

#include <algorithm>
#include <chrono>
#include <random>

#include <Eigen/SVD>
#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"
#include "src/optim/line_geometry.h"

namespace colmap_lidar {
namespace {

constexpr double kPixelNoise = 0.5;     // pixels
constexpr double kLidarNoiseM = 0.015;  // metres, per axis
constexpr double kPositionNoiseM = 0.5;
constexpr double kRotationNoiseDeg = 5.0;

// Projection that must fall inside the 640 x 480 image (the scene is built
// so that everything is in view).
Eigen::Vector2d ProjectInside(const Camera& camera,
                              const Eigen::Vector3d& point_in_cam) {
  const Eigen::Vector2d pixel = camera.ImgFromCam(point_in_cam);
  THROW_CHECK(point_in_cam.z() > 0.0 && pixel.x() > 0.0 && pixel.y() > 0.0 &&
                  pixel.x() < camera.width && pixel.y() < camera.height,
              "Synthetic scene out of view: " << pixel.transpose());
  return pixel;
}

// A box-shaped set of 3D lines (the 12 edges of a 4 x 3 x 2.5 m box and 6
// lines on its faces) with points on its faces, seen by 10 PINHOLE 640x480
// cameras on an arc of radius 7 m. Visibility is not simulated (all lines
// and points project inside every image). Observations carry 0.5 px noise,
// LIDAR segments 1.5 cm noise; poses except the first (the gauge) are
// perturbed by 0.5 m / 5 deg, points are triangulated and lines initialised
// from LIDAR with the perturbed poses.
struct SyntheticProblem {
  Reconstruction reconstruction;
  std::vector<LineTrack> line_tracks;
  std::vector<Rigid3d> true_cam_from_world;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> true_lines;
  std::map<point3D_t, Eigen::Vector3d> true_points;
};

Rigid3d LookAt(const Eigen::Vector3d& center, const Eigen::Vector3d& target) {
  const Eigen::Vector3d up(0, 0, 1);
  const Eigen::Vector3d z = (target - center).normalized();
  const Eigen::Vector3d x = z.cross(up).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d world_from_cam;
  world_from_cam << x, y, z;
  const Eigen::Quaterniond rotation(world_from_cam.transpose());
  return Rigid3d(rotation, -(rotation * center));
}

Eigen::Vector3d Triangulate(const Reconstruction& reconstruction,
                            const Point3D& point3D) {
  Eigen::MatrixXd a(2 * point3D.track.size(), 4);
  int row = 0;
  for (const TrackElement& element : point3D.track) {
    const Image& image = *reconstruction.FindImage(element.image_id);
    const Camera& camera = reconstruction.cameras.at(image.camera_id);
    const Eigen::Vector2d normalized =
        camera.CamFromImg(image.points2D[element.point2D_idx].xy);
    const Eigen::Matrix3x4d p = image.cam_from_world.ToMatrix();
    a.row(row++) = normalized.x() * p.row(2) - p.row(0);
    a.row(row++) = normalized.y() * p.row(2) - p.row(1);
  }
  const Eigen::Vector4d x =
      Eigen::JacobiSVD<Eigen::MatrixXd>(a, Eigen::ComputeFullV).matrixV().col(3);
  return x.hnormalized();
}

SyntheticProblem MakeSyntheticProblem(unsigned seed, int num_points = 150,
                                      int num_images = 10,
                                      bool distorted = false) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  SyntheticProblem problem;
  Reconstruction& reconstruction = problem.reconstruction;
  Camera camera =
      distorted ? Camera::FromModelName("OPENCV", 640, 480,
                                        {500, 500, 320, 240, -0.08, 0.01, 0.0005, -0.0003})
                : Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
  camera.camera_id = 1;
  reconstruction.cameras[1] = camera;

  // Box [-2, 2] x [-1.5, 1.5] x [0, 2.5].
  const Eigen::Vector3d lo(-2.0, -1.5, 0.0), hi(2.0, 1.5, 2.5);
  const auto corner = [&](int i) {
    return Eigen::Vector3d(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                           i & 4 ? hi.z() : lo.z());
  };
  for (int i = 0; i < 8; ++i) {
    for (int bit : {1, 2, 4}) {
      if (!(i & bit)) problem.true_lines.emplace_back(corner(i), corner(i | bit));
    }
  }
  // Window-like lines on the faces x = lo.x (the arc's side) and y = lo.y.
  problem.true_lines.emplace_back(Eigen::Vector3d(-2, -1, 0.8), Eigen::Vector3d(-2, 1, 0.8));
  problem.true_lines.emplace_back(Eigen::Vector3d(-2, -1, 1.8), Eigen::Vector3d(-2, 1, 1.8));
  problem.true_lines.emplace_back(Eigen::Vector3d(-2, -0.5, 0.3), Eigen::Vector3d(-2, -0.5, 2.2));
  problem.true_lines.emplace_back(Eigen::Vector3d(-2, 0.7, 0.3), Eigen::Vector3d(-2, 0.7, 2.2));
  problem.true_lines.emplace_back(Eigen::Vector3d(-1.5, -1.5, 1.2), Eigen::Vector3d(1.5, -1.5, 1.2));
  problem.true_lines.emplace_back(Eigen::Vector3d(0.3, -1.5, 0.2), Eigen::Vector3d(0.3, -1.5, 2.3));

  // Cameras on an arc around the box, looking at its centre.
  const Eigen::Vector3d target(0.0, 0.0, 1.25);
  constexpr double kRadiusM = 7.0;
  constexpr double kArcDeg = 108.0;
  for (int i = 0; i < num_images; ++i) {
    const double angle = (-150.0 + kArcDeg * i / num_images) * M_PI / 180.0;
    const Eigen::Vector3d center(kRadiusM * std::cos(angle), kRadiusM * std::sin(angle),
                                 1.5 + 0.2 * std::sin(3.0 * i));
    Image image;
    image.image_id = static_cast<image_t>(i + 1);
    image.camera_id = 1;
    image.name = "frame" + std::to_string(i) + ".png";
    image.cam_from_world = LookAt(center, target);
    problem.true_cam_from_world.push_back(image.cam_from_world);
    reconstruction.images.push_back(image);
  }

  // Points on the box faces, observed in every image.
  for (int k = 0; k < num_points; ++k) {
    Eigen::Vector3d point(lo.x() + uniform(rng) * (hi.x() - lo.x()),
                          lo.y() + uniform(rng) * (hi.y() - lo.y()),
                          lo.z() + uniform(rng) * (hi.z() - lo.z()));
    const int axis = k % 3;
    point[axis] = uniform(rng) < 0.5 ? lo[axis] : hi[axis];
    const point3D_t point3D_id = static_cast<point3D_t>(k + 1);
    Point3D point3D;
    for (Image& image : reconstruction.images) {
      Point2D point2D;
      point2D.xy = ProjectInside(camera, image.cam_from_world * point) +
                   kPixelNoise * Eigen::Vector2d(normal(rng), normal(rng));
      point2D.point3D_id = point3D_id;
      TrackElement element;
      element.image_id = image.image_id;
      element.point2D_idx = static_cast<point2D_t>(image.points2D.size());
      image.points2D.push_back(point2D);
      point3D.track.push_back(element);
    }
    reconstruction.points3D[point3D_id] = point3D;
    problem.true_points[point3D_id] = point;
  }

  // Line observations: a random part of each segment per view.
  for (size_t l = 0; l < problem.true_lines.size(); ++l) {
    const auto& [a, b] = problem.true_lines[l];
    LineTrack track;
    track.line3D_id = l + 1;
    for (const Image& image : reconstruction.images) {
      const double t0 = 0.05 + 0.2 * uniform(rng);
      const double t1 = 0.75 + 0.2 * uniform(rng);
      const Eigen::Vector3d p0_in_cam = image.cam_from_world * (a + t0 * (b - a));
      const Eigen::Vector3d p1_in_cam = image.cam_from_world * (a + t1 * (b - a));
      LineObservation observation;
      observation.image_id = image.image_id;
      observation.line2D_idx = static_cast<uint32_t>(l);
      observation.start2D = ProjectInside(camera, p0_in_cam) +
                            kPixelNoise * Eigen::Vector2d(normal(rng), normal(rng));
      observation.end2D = ProjectInside(camera, p1_in_cam) +
                          kPixelNoise * Eigen::Vector2d(normal(rng), normal(rng));
      observation.has_lidar = true;
      observation.start_in_cam =
          p0_in_cam + kLidarNoiseM * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
      observation.end_in_cam =
          p1_in_cam + kLidarNoiseM * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
      track.observations.push_back(observation);
    }
    problem.line_tracks.push_back(track);
  }

  // Perturb all poses but the first.
  for (size_t i = 1; i < reconstruction.images.size(); ++i) {
    Rigid3d& cam_from_world = reconstruction.images[i].cam_from_world;
    const Eigen::Vector3d axis =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const Eigen::Vector3d shift =
        Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const Eigen::Vector3d center = cam_from_world.Inverse().translation +
                                   kPositionNoiseM * shift;
    cam_from_world.rotation =
        (Eigen::Quaterniond(Eigen::AngleAxisd(kRotationNoiseDeg * M_PI / 180.0, axis)) *
         cam_from_world.rotation)
            .normalized();
    cam_from_world.translation = -(cam_from_world.rotation * center);
  }
  for (auto& [point3D_id, point3D] : reconstruction.points3D) {
    point3D.xyz = Triangulate(reconstruction, point3D);
  }
  return problem;
}

struct PoseErrors {
  double mean_position_m = 0.0;
  double max_position_m = 0.0;
  double mean_rotation_deg = 0.0;
  double max_rotation_deg = 0.0;
};

// Errors of the estimated poses against the truth, without any alignment.
PoseErrors ComputePoseErrors(const SyntheticProblem& problem) {
  PoseErrors errors;
  const auto& images = problem.reconstruction.images;
  for (size_t i = 0; i < images.size(); ++i) {
    const Rigid3d& estimate = images[i].cam_from_world;
    const Rigid3d& truth = problem.true_cam_from_world[i];
    const double position =
        (estimate.Inverse().translation - truth.Inverse().translation).norm();
    const double rotation =
        estimate.rotation.angularDistance(truth.rotation) * 180.0 / M_PI;
    errors.mean_position_m += position / images.size();
    errors.mean_rotation_deg += rotation / images.size();
    errors.max_position_m = std::max(errors.max_position_m, position);
    errors.max_rotation_deg = std::max(errors.max_rotation_deg, rotation);
  }
  return errors;
}

double MaxLineError(const SyntheticProblem& problem) {
  double max_error = 0.0;
  for (size_t l = 0; l < problem.line_tracks.size(); ++l) {
    const auto& [a, b] = problem.true_lines[l];
    const Vector6d& line = problem.line_tracks[l].plucker_in_world;
    max_error = std::max({max_error, PointToPluckerLineDistance(line, a),
                          PointToPluckerLineDistance(line, b)});
  }
  return max_error;
}

LineBundleAdjustmentOptions TestOptions() {
  LineBundleAdjustmentOptions options;
  options.lidar_sigma_m = kLidarNoiseM;
  options.num_threads = 2;
  return options;
}

TEST(LineBundleAdjustmentOptions, Check) {
  EXPECT_TRUE(LineBundleAdjustmentOptions().Check());
  LineBundleAdjustmentOptions options;
  options.lidar_sigma_m = 0.0;
  EXPECT_FALSE(options.Check());
  options = LineBundleAdjustmentOptions();
  options.prior_position_sigma_m = 0.5;  // rotation sigma still 0
  EXPECT_FALSE(options.Check());
  options.prior_rotation_sigma_deg = 5.0;
  EXPECT_TRUE(options.Check());
  options = LineBundleAdjustmentOptions();
  options.gauge = LineBAGauge::kPosePriors;  // without priors
  EXPECT_FALSE(options.Check());
  options = LineBundleAdjustmentOptions();
  options.lambda_R = options.lambda_L = options.lambda_lidar = 0.0;
  EXPECT_FALSE(options.Check());
  options = LineBundleAdjustmentOptions();
  options.lidar_point_weight = -1.0;
  EXPECT_FALSE(options.Check());
  options = LineBundleAdjustmentOptions();
  options.lidar_point_loss_scale = 0.0;
  EXPECT_FALSE(options.Check());
  EXPECT_THROW(LineBundleAdjuster{options}, Error);
  EXPECT_EQ(LineBALossTypeFromName("SOFT_L1"), LineBALossType::kSoftL1);
  EXPECT_EQ(LineBALossTypeName(LineBALossType::kCauchy), "CAUCHY");
  EXPECT_EQ(LineBAGaugeFromName("POSE_PRIORS"), LineBAGauge::kPosePriors);
  EXPECT_THROW(LineBALossTypeFromName("L2"), Error);
}

TEST(LineBundleAdjuster, RecoversPerturbedPosesWithPointsLinesAndLidar) {
  SyntheticProblem problem = MakeSyntheticProblem(1);
  const PoseErrors before = ComputePoseErrors(problem);
  EXPECT_GT(before.mean_position_m, 0.3);

  const LineBundleAdjuster adjuster(TestOptions());
  const LineBundleAdjustmentSummary summary =
      adjuster.Solve(&problem.reconstruction, &problem.line_tracks);
  const PoseErrors after = ComputePoseErrors(problem);
  LOG(INFO) << summary.ToString();
  LOG(INFO) << "Pose errors: mean " << after.mean_position_m << " m (max "
            << after.max_position_m << "), mean " << after.mean_rotation_deg
            << " deg (max " << after.max_rotation_deg << ")";
  EXPECT_TRUE(summary.usable);
  EXPECT_EQ(summary.num_images, 10);
  EXPECT_EQ(summary.num_fixed_images, 1);
  EXPECT_TRUE(summary.unconstrained_image_ids.empty());
  EXPECT_EQ(summary.num_points, 150);
  EXPECT_EQ(summary.num_lines, 18);
  EXPECT_EQ(summary.num_point_residuals, 1500);
  EXPECT_EQ(summary.num_line_residuals, 180);
  EXPECT_EQ(summary.num_lidar_residuals, 180);
  EXPECT_EQ(summary.num_pose_prior_residuals, 0);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  EXPECT_LT(after.mean_position_m, 0.01);
  EXPECT_LT(after.mean_rotation_deg, 0.1);
  EXPECT_LT(summary.mean_point_error_px, 1.0);
  EXPECT_LT(summary.mean_line_error_px, 1.0);
  EXPECT_LT(summary.rms_lidar_distance_m, 2.0 * kLidarNoiseM);
  EXPECT_LT(MaxLineError(problem), 0.05);
  // Segments: the extent of the observed parts, i.e. within the true
  // segment's [0.05, 0.95] part up to noise.
  for (size_t l = 0; l < problem.line_tracks.size(); ++l) {
    const LineTrack& track = problem.line_tracks[l];
    const auto& [a, b] = problem.true_lines[l];
    const double length = (b - a).norm();
    const double segment_length = (track.end_in_world - track.start_in_world).norm();
    EXPECT_GT(segment_length, 0.6 * length) << "line " << l;
    EXPECT_LT(segment_length, 1.0 * length + 0.1) << "line " << l;
    EXPECT_GE(track.error, 0.0);
  }
}

TEST(LineBundleAdjuster, DistortedCamera) {
  // OPENCV camera: line residuals measured in the undistorted image.
  SyntheticProblem problem = MakeSyntheticProblem(9, 150, 10, /*distorted=*/true);
  const LineBundleAdjustmentSummary summary = LineBundleAdjuster(TestOptions()).Solve(
      &problem.reconstruction, &problem.line_tracks);
  const PoseErrors after = ComputePoseErrors(problem);
  EXPECT_TRUE(summary.usable);
  EXPECT_LT(summary.mean_line_error_px, 1.0);
  EXPECT_LT(after.mean_position_m, 0.01);
  EXPECT_LT(after.mean_rotation_deg, 0.1);
}

TEST(LineBundleAdjuster, LinesOnlyStillConverges) {
  SyntheticProblem problem = MakeSyntheticProblem(2);
  LineBundleAdjustmentOptions options = TestOptions();
  options.lambda_R = 0.0;
  const LineBundleAdjustmentSummary summary =
      LineBundleAdjuster(options).Solve(&problem.reconstruction,
                                        &problem.line_tracks);
  const PoseErrors after = ComputePoseErrors(problem);
  LOG(INFO) << summary.ToString();
  LOG(INFO) << "Lines only: mean " << after.mean_position_m << " m, "
            << after.mean_rotation_deg << " deg";
  EXPECT_TRUE(summary.usable);
  EXPECT_EQ(summary.num_point_residuals, 0);
  EXPECT_EQ(summary.num_points, 0);
  EXPECT_LT(after.mean_position_m, 0.03);
  EXPECT_LT(after.mean_rotation_deg, 0.2);
}

TEST(LineBundleAdjuster, ViewsWithoutLinesOrPoints) {
  SyntheticProblem problem = MakeSyntheticProblem(3);
  // Image 4: no line observations; image 6: no point observations;
  // image 8: nothing at all.
  for (LineTrack& track : problem.line_tracks) {
    auto& observations = track.observations;
    observations.erase(
        std::remove_if(observations.begin(), observations.end(),
                       [](const LineObservation& observation) {
                         return observation.image_id == 4 ||
                                observation.image_id == 8;
                       }),
        observations.end());
  }
  for (auto& [point3D_id, point3D] : problem.reconstruction.points3D) {
    auto& track = point3D.track;
    track.erase(std::remove_if(track.begin(), track.end(),
                               [](const TrackElement& element) {
                                 return element.image_id == 6 ||
                                        element.image_id == 8;
                               }),
                track.end());
  }
  for (image_t image_id : {6u, 8u}) {
    for (Point2D& point2D : problem.reconstruction.FindImage(image_id)->points2D) {
      point2D.point3D_id = kInvalidPoint3DId;
    }
  }
  const Rigid3d image8_before = problem.reconstruction.FindImage(8)->cam_from_world;

  const LineBundleAdjustmentSummary summary = LineBundleAdjuster(TestOptions()).Solve(
      &problem.reconstruction, &problem.line_tracks);
  LOG(INFO) << summary.ToString();
  EXPECT_TRUE(summary.usable);
  EXPECT_EQ(summary.num_images, 9);
  ASSERT_EQ(summary.unconstrained_image_ids.size(), 1u);
  EXPECT_EQ(summary.unconstrained_image_ids[0], 8u);
  // Image 8 is untouched; 4 (points only) and 6 (lines only) are refined.
  const Rigid3d& image8_after = problem.reconstruction.FindImage(8)->cam_from_world;
  EXPECT_EQ(image8_after.translation, image8_before.translation);
  EXPECT_EQ(image8_after.rotation.coeffs(), image8_before.rotation.coeffs());
  for (image_t image_id : {4u, 6u}) {
    const Rigid3d& estimate = problem.reconstruction.FindImage(image_id)->cam_from_world;
    const Rigid3d& truth = problem.true_cam_from_world[image_id - 1];
    EXPECT_LT((estimate.Inverse().translation - truth.Inverse().translation).norm(), 0.03)
        << "image " << image_id;
    EXPECT_LT(estimate.rotation.angularDistance(truth.rotation) * 180.0 / M_PI, 0.2)
        << "image " << image_id;
  }
}

// Image 8 has no observations; LIDAR edges 7-8 and 8-9 (from the true
// poses, with a LIDAR mounted differently from the camera) constrain it.
TEST(LineBundleAdjuster, RelativePoseEdgesConstrainAnImageWithoutObservations) {
  const auto make_problem = [] {
    SyntheticProblem problem = MakeSyntheticProblem(3);
    for (LineTrack& track : problem.line_tracks) {
      auto& observations = track.observations;
      observations.erase(std::remove_if(observations.begin(), observations.end(),
                                        [](const LineObservation& observation) {
                                          return observation.image_id == 8;
                                        }),
                         observations.end());
    }
    for (auto& [point3D_id, point3D] : problem.reconstruction.points3D) {
      auto& track = point3D.track;
      track.erase(std::remove_if(track.begin(), track.end(),
                                 [](const TrackElement& element) {
                                   return element.image_id == 8;
                                 }),
                  track.end());
    }
    for (Point2D& point2D : problem.reconstruction.FindImage(8)->points2D) {
      point2D.point3D_id = kInvalidPoint3DId;
    }
    return problem;
  };
  const Rigid3d cam_from_lidar(
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX())),
      Eigen::Vector3d(0.05, -0.1, 0.02));
  std::vector<RelativePoseEdge> edges;
  SyntheticProblem reference = make_problem();
  for (const auto& [id1, id2] : {std::pair<image_t, image_t>{7, 8}, {8, 9}}) {
    RelativePoseEdge edge;
    edge.image_id1 = id1;
    edge.image_id2 = id2;
    edge.cam1_from_lidar = cam_from_lidar;
    edge.cam2_from_lidar = cam_from_lidar;
    edge.lidar1_from_lidar2 = cam_from_lidar.Inverse() *
                              reference.true_cam_from_world[id1 - 1] *
                              reference.true_cam_from_world[id2 - 1].Inverse() *
                              cam_from_lidar;
    // 1 mrad, 1 cm.
    edge.sqrt_information.diagonal() << 1000, 1000, 1000, 100, 100, 100;
    edges.push_back(edge);
  }
  // An edge to an image that does not exist is skipped.
  edges.push_back(edges[0]);
  edges.back().image_id2 = 99;

  const Rigid3d& truth = reference.true_cam_from_world[7];
  const auto error_m = [&](const SyntheticProblem& problem) {
    return (problem.reconstruction.FindImage(8)->cam_from_world.Inverse().translation -
            truth.Inverse().translation)
        .norm();
  };

  // Without edges (weight 0) image 8 is unconstrained and keeps its pose.
  {
    SyntheticProblem problem = make_problem();
    LineBundleAdjustmentOptions options = TestOptions();
    options.lidar_edge_weight = 0.0;
    LineBundleAdjuster adjuster(options);
    adjuster.SetRelativePoseEdges(edges);
    const LineBundleAdjustmentSummary summary =
        adjuster.Solve(&problem.reconstruction, &problem.line_tracks);
    EXPECT_EQ(summary.num_lidar_edge_residuals, 0);
    EXPECT_EQ(summary.mean_lidar_edge_error, -1.0);
    ASSERT_EQ(summary.unconstrained_image_ids.size(), 1u);
    EXPECT_EQ(summary.unconstrained_image_ids[0], 8u);
    EXPECT_GT(error_m(problem), 0.1);
  }

  SyntheticProblem problem = make_problem();
  LineBundleAdjuster adjuster(TestOptions());
  adjuster.SetRelativePoseEdges(edges);
  const LineBundleAdjustmentSummary summary =
      adjuster.Solve(&problem.reconstruction, &problem.line_tracks);
  LOG(INFO) << summary.ToString();
  EXPECT_TRUE(summary.usable);
  EXPECT_EQ(summary.num_lidar_edge_residuals, 2);
  EXPECT_EQ(summary.num_images, 10);
  EXPECT_TRUE(summary.unconstrained_image_ids.empty());
  EXPECT_GE(summary.mean_lidar_edge_error, 0.0);
  EXPECT_LT(summary.mean_lidar_edge_error, 3.0);
  EXPECT_LT(error_m(problem), 0.01);
  EXPECT_LT(problem.reconstruction.FindImage(8)->cam_from_world.rotation.angularDistance(
                truth.rotation) * 180.0 / M_PI,
            0.1);
  for (size_t e = 0; e < 2; ++e) {
    EXPECT_LT(ComputeRelativePoseEdgeError(problem.reconstruction, edges[e]), 3.0);
  }
  EXPECT_EQ(ComputeRelativePoseEdgeError(problem.reconstruction, edges[2]), -1.0);
}

TEST(LineBundleAdjuster, SingleViewLidarLine) {
  SyntheticProblem problem = MakeSyntheticProblem(4);
  // Line 0 only in image 3 (with LIDAR): determined by LIDAR + one view.
  LineTrack& single = problem.line_tracks[0];
  single.observations = {single.observations[2]};
  // Line 1 only in image 3 without LIDAR: under-determined, skipped.
  LineTrack& unusable = problem.line_tracks[1];
  unusable.observations = {unusable.observations[2]};
  unusable.observations[0].has_lidar = false;
  const LineBundleAdjustmentSummary summary = LineBundleAdjuster(TestOptions()).Solve(
      &problem.reconstruction, &problem.line_tracks);
  EXPECT_TRUE(summary.usable);
  EXPECT_EQ(summary.num_lines, 17);
  EXPECT_EQ(summary.num_skipped_lines, 1);
  EXPECT_FALSE(IsLineInitialized(problem.line_tracks[1]));
  const auto& [a, b] = problem.true_lines[0];
  EXPECT_LT(PointToPluckerLineDistance(single.plucker_in_world, a), 0.05);
  EXPECT_LT(PointToPluckerLineDistance(single.plucker_in_world, b), 0.05);
  EXPECT_LT(ComputePoseErrors(problem).mean_position_m, 0.01);
}

TEST(LineBundleAdjuster, PosePriors) {
  // The paper's setting: priors = the noisy poses (0.5 m, 5 deg); with the
  // first pose as gauge they must not pull the solution off.
  SyntheticProblem problem = MakeSyntheticProblem(5);
  LineBundleAdjustmentOptions options = TestOptions();
  options.prior_position_sigma_m = kPositionNoiseM;
  options.prior_rotation_sigma_deg = kRotationNoiseDeg;
  LineBundleAdjustmentSummary summary = LineBundleAdjuster(options).Solve(
      &problem.reconstruction, &problem.line_tracks);
  EXPECT_TRUE(summary.usable);
  EXPECT_EQ(summary.num_pose_prior_residuals, 10);
  EXPECT_LT(ComputePoseErrors(problem).mean_position_m, 0.01);

  // Priors as the only gauge: exact priors pin the world frame.
  SyntheticProblem exact = MakeSyntheticProblem(6);
  std::unordered_map<image_t, Rigid3d> priors;
  for (size_t i = 0; i < exact.reconstruction.images.size(); ++i) {
    priors[exact.reconstruction.images[i].image_id] = exact.true_cam_from_world[i];
  }
  options.gauge = LineBAGauge::kPosePriors;
  options.prior_position_sigma_m = 0.01;
  options.prior_rotation_sigma_deg = 0.1;
  LineBundleAdjuster adjuster(options);
  adjuster.SetPosePriors(priors);
  summary = adjuster.Solve(&exact.reconstruction, &exact.line_tracks);
  EXPECT_TRUE(summary.usable);
  EXPECT_EQ(summary.num_fixed_images, 0);
  EXPECT_LT(ComputePoseErrors(exact).mean_position_m, 0.01);
}

TEST(LineBundleAdjuster, SixtyFramesWithPriorsIsFast) {
  // Size of the paper's sequences (~60 images) with its pose noise as
  // priors; the target is <= 60 s on 2 cores and <= 3 cm.
  SyntheticProblem problem = MakeSyntheticProblem(8, /*num_points=*/500,
                                                  /*num_images=*/60);
  LineBundleAdjustmentOptions options = TestOptions();
  options.prior_position_sigma_m = kPositionNoiseM;
  options.prior_rotation_sigma_deg = kRotationNoiseDeg;
  const auto start = std::chrono::steady_clock::now();
  const LineBundleAdjustmentSummary summary = LineBundleAdjuster(options).Solve(
      &problem.reconstruction, &problem.line_tracks);
  const double wall_s = std::chrono::duration<double>(
                            std::chrono::steady_clock::now() - start)
                            .count();
  const PoseErrors after = ComputePoseErrors(problem);
  LOG(INFO) << "60 frames: " << wall_s << " s wall; mean "
            << after.mean_position_m << " m (max " << after.max_position_m
            << "), mean " << after.mean_rotation_deg << " deg";
  EXPECT_TRUE(summary.usable);
  EXPECT_EQ(summary.num_point_residuals, 30000);
  EXPECT_LT(wall_s, 60.0);
  EXPECT_LT(after.mean_position_m, 0.01);
  EXPECT_LT(after.mean_rotation_deg, 0.1);
}

// The LIDAR planes of the points alone give the metric scale: points only,
// the first pose fixed, every other pose and the points 0.5 m / 5 deg off.
// Without planes the scale is fixed by one translation axis of the second
// image at its perturbed value; with them (each point's box face in every
// image's camera frame, 1 cm noise on the offsets) the poses come back.
TEST(LineBundleAdjuster, LidarPlanesOfPointsFixTheScale) {
  const auto make_problem = [] {
    SyntheticProblem problem = MakeSyntheticProblem(11);
    problem.line_tracks.clear();
    return problem;
  };
  constexpr double kPlaneNoiseM = 0.01;
  SyntheticProblem reference = make_problem();
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, kPlaneNoiseM);
  std::vector<PointPlaneObservation> planes;
  const Eigen::Vector3d lo(-2.0, -1.5, 0.0), hi(2.0, 1.5, 2.5);
  for (const auto& [point3D_id, point] : reference.true_points) {
    // The face the point was drawn on (MakeSyntheticProblem: axis k % 3).
    const int axis = static_cast<int>((point3D_id - 1) % 3);
    Eigen::Vector3d normal_in_world = Eigen::Vector3d::Zero();
    normal_in_world[axis] = std::abs(point[axis] - lo[axis]) < 1e-9 ? -1 : 1;
    for (size_t i = 0; i < reference.true_cam_from_world.size(); ++i) {
      const Rigid3d& cam_from_world = reference.true_cam_from_world[i];
      PointPlaneObservation plane;
      plane.image_id = static_cast<image_t>(i + 1);
      plane.point3D_id = point3D_id;
      plane.normal_in_cam = cam_from_world.rotation * normal_in_world;
      plane.offset_m =
          plane.normal_in_cam.dot(cam_from_world * point) + noise(rng);
      plane.sigma_m = kPlaneNoiseM;
      planes.push_back(plane);
    }
  }
  // A plane of a point that is not adjusted is skipped.
  PointPlaneObservation unknown = planes.front();
  unknown.point3D_id = 100000;
  planes.push_back(unknown);

  LineBundleAdjustmentOptions options = TestOptions();
  const LineBundleAdjustmentSummary without = LineBundleAdjuster(options).Solve(
      &reference.reconstruction, &reference.line_tracks);
  const PoseErrors errors_without = ComputePoseErrors(reference);
  EXPECT_TRUE(without.usable);
  EXPECT_EQ(without.num_lidar_point_residuals, 0);
  EXPECT_GT(errors_without.mean_position_m, 0.1);

  SyntheticProblem problem = make_problem();
  LineBundleAdjuster adjuster(options);
  adjuster.SetPointPlanes(planes);
  const LineBundleAdjustmentSummary summary =
      adjuster.Solve(&problem.reconstruction, &problem.line_tracks);
  const PoseErrors errors = ComputePoseErrors(problem);
  LOG(INFO) << summary.ToString();
  EXPECT_TRUE(summary.usable);
  EXPECT_EQ(summary.num_lidar_point_residuals, 1500);
  EXPECT_LT(errors.mean_position_m, 0.01);
  EXPECT_LT(errors.mean_rotation_deg, 0.1);
  EXPECT_LT(summary.rms_lidar_point_distance_m, 2.0 * kPlaneNoiseM);

  // Weight 0: the planes are ignored.
  SyntheticProblem off = make_problem();
  options.lidar_point_weight = 0.0;
  LineBundleAdjuster off_adjuster(options);
  off_adjuster.SetPointPlanes(planes);
  const LineBundleAdjustmentSummary off_summary =
      off_adjuster.Solve(&off.reconstruction, &off.line_tracks);
  EXPECT_EQ(off_summary.num_lidar_point_residuals, 0);
  EXPECT_NEAR(ComputePoseErrors(off).mean_position_m,
              errors_without.mean_position_m, 1e-6);
}

TEST(LineBundleAdjuster, NothingToSolve) {
  SyntheticProblem problem = MakeSyntheticProblem(7, /*num_points=*/0);
  problem.line_tracks.clear();
  const LineBundleAdjustmentSummary summary = LineBundleAdjuster(TestOptions()).Solve(
      &problem.reconstruction, &problem.line_tracks);
  EXPECT_FALSE(summary.usable);
  EXPECT_EQ(summary.unconstrained_image_ids.size(), 10u);
}

}  // namespace
}  // namespace colmap_lidar
