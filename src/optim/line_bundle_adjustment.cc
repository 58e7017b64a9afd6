// The parts of line_bundle_adjustment.h: option names, checks and the
// summary text in line_bundle_adjustment_options.cc, the error measures of
// a reconstruction in line_bundle_adjustment_errors.cc; here the adjuster.
#include "src/optim/line_bundle_adjustment.h"

#include <algorithm>
#include <array>
#include <map>
#include <cmath>
#include <memory>
#include <thread>

#include <ceres/ceres.h>
#include <Eigen/SVD>

#include "colmap_ext/util/logging.h"
#include "src/optim/cost_functions.h"
#include "src/optim/line_geometry.h"
#include "src/optim/line_manifold.h"

namespace colmap_lidar {
namespace {

// Loss of one residual type: the robust loss with its scale, weighted by
// lambda. The result is owned by the caller (the problem does not take
// ownership of losses, which are shared by many residuals).
std::unique_ptr<ceres::LossFunction> CreateLoss(LineBALossType type,
                                                double scale, double weight) {
  ceres::LossFunction* loss = nullptr;
  switch (type) {
    case LineBALossType::kTrivial:
      loss = nullptr;
      break;
    case LineBALossType::kHuber:
      loss = new ceres::HuberLoss(scale);
      break;
    case LineBALossType::kSoftL1:
      loss = new ceres::SoftLOneLoss(scale);
      break;
    case LineBALossType::kCauchy:
      loss = new ceres::CauchyLoss(scale);
      break;
  }
  return std::make_unique<ceres::ScaledLoss>(loss, weight,
                                             ceres::TAKE_OWNERSHIP);
}

// Mean reprojection error of a point over its track, pixels.
double MeanReprojectionError(const Reconstruction& reconstruction,
                             const Point3D& point3D) {
  double sum = 0.0;
  for (const TrackElement& element : point3D.track) {
    const Image& image = *reconstruction.FindImage(element.image_id);
    const Camera& camera = reconstruction.cameras.at(image.camera_id);
    sum += (camera.ImgFromCam(image.cam_from_world * point3D.xyz) -
            image.points2D.at(element.point2D_idx).xy)
               .norm();
  }
  return point3D.track.empty() ? 0.0 : sum / point3D.track.size();
}

// Linear (DLT) triangulation of a point from its track with the current
// poses. Returns false when the point is not in front of every camera.
bool TriangulatePoint(const Reconstruction& reconstruction,
                      const Point3D& point3D, Eigen::Vector3d* xyz) {
  Eigen::MatrixXd a(2 * point3D.track.size(), 4);
  int row = 0;
  for (const TrackElement& element : point3D.track) {
    const Image& image = *reconstruction.FindImage(element.image_id);
    const Camera& camera = reconstruction.cameras.at(image.camera_id);
    const Eigen::Vector2d normalized =
        camera.CamFromImg(image.points2D.at(element.point2D_idx).xy);
    const Eigen::Matrix3x4d projection = image.cam_from_world.ToMatrix();
    a.row(row++) = normalized.x() * projection.row(2) - projection.row(0);
    a.row(row++) = normalized.y() * projection.row(2) - projection.row(1);
  }
  const Eigen::Vector4d homogeneous =
      Eigen::JacobiSVD<Eigen::MatrixXd>(a, Eigen::ComputeFullV).matrixV().col(3);
  if (std::abs(homogeneous[3]) < 1e-12) {
    return false;
  }
  const Eigen::Vector3d candidate = homogeneous.hnormalized();
  for (const TrackElement& element : point3D.track) {
    const Image& image = *reconstruction.FindImage(element.image_id);
    if ((image.cam_from_world * candidate).z() <= 0.0) {
      return false;
    }
  }
  *xyz = candidate;
  return true;
}

}  // namespace

LineBundleAdjuster::LineBundleAdjuster(
    const LineBundleAdjustmentOptions& options)
    : options_(options) {
  THROW_CHECK(options_.Check(), "Invalid LineBundleAdjustmentOptions");
}

void LineBundleAdjuster::SetPosePriors(
    std::unordered_map<image_t, Rigid3d> cam_from_world_priors) {
  cam_from_world_priors_ = std::move(cam_from_world_priors);
}

void LineBundleAdjuster::SetRelativePoseEdges(
    std::vector<RelativePoseEdge> edges) {
  relative_pose_edges_ = std::move(edges);
}

void LineBundleAdjuster::SetPointPlanes(
    std::vector<PointPlaneObservation> planes) {
  point_planes_ = std::move(planes);
}

LineBundleAdjustmentSummary LineBundleAdjuster::Solve(
    Reconstruction* reconstruction, std::vector<LineTrack>* line_tracks) const {
  THROW_CHECK(reconstruction != nullptr && line_tracks != nullptr,
              "LineBundleAdjuster::Solve needs a reconstruction and tracks");
  reconstruction->CheckConsistency();
  LineBundleAdjustmentSummary summary;
  const bool use_points = options_.lambda_R > 0.0;
  const bool use_lines = options_.lambda_L > 0.0;
  const bool use_lidar = options_.lambda_lidar > 0.0;
  const bool use_priors = options_.prior_position_sigma_m > 0.0;
  const bool use_edges = options_.lidar_edge_weight > 0.0;
  const bool use_point_planes = use_points && options_.lidar_point_weight > 0.0;

  for (Image& image : reconstruction->images) {
    image.cam_from_world.rotation.normalize();
  }
  std::unordered_map<image_t, size_t> image_index;
  for (size_t i = 0; i < reconstruction->images.size(); ++i) {
    image_index.emplace(reconstruction->images[i].image_id, i);
  }
  const auto find_image = [&](image_t image_id) -> Image* {
    const auto it = image_index.find(image_id);
    return it == image_index.end() ? nullptr
                                   : &reconstruction->images[it->second];
  };

  // Select the points and lines, and count each image's scalar residuals.
  std::vector<int> num_constraints(reconstruction->images.size(), 0);
  std::vector<point3D_t> point_ids;
  if (use_points) {
    for (const auto& [point3D_id, point3D] : reconstruction->points3D) {
      if (static_cast<int>(point3D.track.size()) <
          options_.min_point_track_length) {
        continue;
      }
      point_ids.push_back(point3D_id);
      for (const TrackElement& element : point3D.track) {
        num_constraints[image_index.at(element.image_id)] += 2;
      }
    }
  }
  std::vector<size_t> line_indices;
  if (use_lines || use_lidar) {
    for (size_t i = 0; i < line_tracks->size(); ++i) {
      LineTrack& track = (*line_tracks)[i];
      int num_views = 0;
      int num_lidar_views = 0;
      for (const LineObservation& observation : track.observations) {
        if (find_image(observation.image_id) != nullptr) {
          ++num_views;
          num_lidar_views += observation.has_lidar ? 1 : 0;
        }
      }
      if (!use_lidar) {
        num_lidar_views = 0;
      }
      // A line has 4 DoF: one view without LIDAR gives only 2 equations.
      const bool determined =
          (use_lines && num_views >= 2) || num_lidar_views >= 1;
      const bool initialized = IsLineInitialized(track) ||
                               InitializeLineFromLidar(*reconstruction, &track) ||
                               InitializeLineFromViews(*reconstruction, &track);
      if (!determined || !initialized) {
        ++summary.num_skipped_lines;
        continue;
      }
      line_indices.push_back(i);
      for (const LineObservation& observation : track.observations) {
        Image* image = find_image(observation.image_id);
        if (image == nullptr) {
          continue;
        }
        int& count = num_constraints[image_index.at(observation.image_id)];
        count += use_lines ? 2 : 0;
        count += (use_lidar && observation.has_lidar) ? 4 : 0;
      }
    }
  }
  // LIDAR edges between two images of the reconstruction (6 constraints
  // each).
  std::vector<const RelativePoseEdge*> edges;
  if (use_edges) {
    for (const RelativePoseEdge& edge : relative_pose_edges_) {
      if (edge.image_id1 == edge.image_id2 ||
          find_image(edge.image_id1) == nullptr ||
          find_image(edge.image_id2) == nullptr) {
        continue;
      }
      edges.push_back(&edge);
      num_constraints[image_index.at(edge.image_id1)] += 6;
      num_constraints[image_index.at(edge.image_id2)] += 6;
    }
  }
  // LIDAR planes of adjusted points (1 constraint each).
  std::vector<const PointPlaneObservation*> point_planes;
  if (use_point_planes && !point_planes_.empty()) {
    std::unordered_map<point3D_t, bool> adjusted;
    for (const point3D_t point3D_id : point_ids) {
      adjusted[point3D_id] = true;
    }
    for (const PointPlaneObservation& plane : point_planes_) {
      if (find_image(plane.image_id) == nullptr ||
          adjusted.count(plane.point3D_id) == 0) {
        continue;
      }
      THROW_CHECK(plane.sigma_m > 0.0 && std::isfinite(plane.offset_m) &&
                      std::abs(plane.normal_in_cam.norm() - 1.0) < 1e-6,
                  "Line bundle adjustment: invalid LIDAR plane of point "
                      << plane.point3D_id << " in image " << plane.image_id);
      point_planes.push_back(&plane);
      num_constraints[image_index.at(plane.image_id)] += 1;
    }
  }
  summary.num_points = static_cast<int>(point_ids.size());
  summary.num_lines = static_cast<int>(line_indices.size());

  // Owned here, outlive the problem (declared before it).
  const std::unique_ptr<ceres::LossFunction> point_loss =
      CreateLoss(options_.point_loss_type, options_.point_loss_scale,
                 options_.lambda_R);
  const std::unique_ptr<ceres::LossFunction> line_loss = CreateLoss(
      options_.line_loss_type, options_.line_loss_scale, options_.lambda_L);
  const std::unique_ptr<ceres::LossFunction> lidar_loss =
      CreateLoss(options_.lidar_loss_type, options_.lidar_loss_scale,
                 options_.lambda_lidar);
  const std::unique_ptr<ceres::LossFunction> edge_loss =
      CreateLoss(LineBALossType::kCauchy, options_.lidar_edge_loss_scale,
                 options_.lidar_edge_weight);
  const std::unique_ptr<ceres::LossFunction> point_plane_loss =
      CreateLoss(LineBALossType::kCauchy, options_.lidar_point_loss_scale,
                 options_.lidar_point_weight);
  const auto quaternion_manifold =
      std::make_unique<ceres::EigenQuaternionManifold>();
  const auto line_manifold = std::make_unique<OrthonormalLineManifold>();
  std::vector<std::unique_ptr<ceres::Manifold>> owned_manifolds;
  std::vector<Vector6d> line_params(line_tracks->size());

  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);

  std::vector<bool> image_used(reconstruction->images.size(), false);
  std::map<camera_t, bool> camera_used;
  const auto use_image = [&](const Image& image) {
    image_used[image_index.at(image.image_id)] = true;
    camera_used[image.camera_id] = true;
  };

  for (const point3D_t point3D_id : point_ids) {
    Point3D& point3D = reconstruction->points3D.at(point3D_id);
    for (const TrackElement& element : point3D.track) {
      Image& image = *find_image(element.image_id);
      Camera& camera = reconstruction->cameras.at(image.camera_id);
      problem.AddResidualBlock(
          CreatePointReprojectionCostFunction(
              camera.model_id, image.points2D.at(element.point2D_idx).xy),
          point_loss.get(), image.cam_from_world.rotation.coeffs().data(),
          image.cam_from_world.translation.data(), point3D.xyz.data(),
          camera.params.data());
      ++summary.num_point_residuals;
      use_image(image);
    }
    if (!options_.refine_points) {
      problem.SetParameterBlockConstant(point3D.xyz.data());
    }
  }

  for (const size_t line_index : line_indices) {
    LineTrack& track = (*line_tracks)[line_index];
    Vector6d& params = line_params[line_index];
    params = PluckerToOrthonormal(track.plucker_in_world);
    for (const LineObservation& observation : track.observations) {
      Image* image = find_image(observation.image_id);
      if (image == nullptr) {
        continue;
      }
      Camera& camera = reconstruction->cameras.at(image->camera_id);
      if (use_lines) {
        problem.AddResidualBlock(
            CreateLineReprojectionCostFunction(
                camera.model_id, observation.start2D, observation.end2D,
                camera.params.data()),
            line_loss.get(), image->cam_from_world.rotation.coeffs().data(),
            image->cam_from_world.translation.data(), params.data(),
            camera.params.data());
        ++summary.num_line_residuals;
        use_image(*image);
      }
      if (use_lidar && observation.has_lidar) {
        problem.AddResidualBlock(
            LidarLineCostFunctor::Create(observation.start_in_cam,
                                         observation.end_in_cam,
                                         options_.lidar_sigma_m),
            lidar_loss.get(), image->cam_from_world.rotation.coeffs().data(),
            image->cam_from_world.translation.data(), params.data());
        ++summary.num_lidar_residuals;
        use_image(*image);
      }
    }
    problem.SetManifold(params.data(), line_manifold.get());
    if (!options_.refine_lines) {
      problem.SetParameterBlockConstant(params.data());
    }
  }

  for (const RelativePoseEdge* edge : edges) {
    Image& image1 = *find_image(edge->image_id1);
    Image& image2 = *find_image(edge->image_id2);
    problem.AddResidualBlock(
        RelativeLidarPoseCostFunctor::Create(
            edge->lidar1_from_lidar2, edge->cam1_from_lidar,
            edge->cam2_from_lidar, edge->sqrt_information),
        edge_loss.get(), image1.cam_from_world.rotation.coeffs().data(),
        image1.cam_from_world.translation.data(),
        image2.cam_from_world.rotation.coeffs().data(),
        image2.cam_from_world.translation.data());
    ++summary.num_lidar_edge_residuals;
    // Not use_image: an edge does not involve the camera parameters, which
    // may then be absent from the problem.
    image_used[image_index.at(image1.image_id)] = true;
    image_used[image_index.at(image2.image_id)] = true;
  }

  for (const PointPlaneObservation* plane : point_planes) {
    Image& image = *find_image(plane->image_id);
    problem.AddResidualBlock(
        LidarPointPlaneCostFunctor::Create(plane->normal_in_cam,
                                           plane->offset_m, plane->sigma_m),
        point_plane_loss.get(), image.cam_from_world.rotation.coeffs().data(),
        image.cam_from_world.translation.data(),
        reconstruction->points3D.at(plane->point3D_id).xyz.data());
    ++summary.num_lidar_point_residuals;
    image_used[image_index.at(image.image_id)] = true;
  }

  // Poses: manifolds, priors, gauge, under-constrained images.
  const double rotation_sigma_rad =
      options_.prior_rotation_sigma_deg * M_PI / 180.0;
  int first_image = -1;
  int second_image = -1;
  for (size_t i = 0; i < reconstruction->images.size(); ++i) {
    Image& image = reconstruction->images[i];
    if (!image_used[i]) {
      summary.unconstrained_image_ids.push_back(image.image_id);
      continue;
    }
    ++summary.num_images;
    double* rotation = image.cam_from_world.rotation.coeffs().data();
    double* translation = image.cam_from_world.translation.data();
    problem.SetManifold(rotation, quaternion_manifold.get());
    if (use_priors) {
      const auto prior_it = cam_from_world_priors_.find(image.image_id);
      const Rigid3d& prior = prior_it != cam_from_world_priors_.end()
                                 ? prior_it->second
                                 : image.cam_from_world;
      problem.AddResidualBlock(
          PosePriorCostFunctor::Create(prior, options_.prior_position_sigma_m,
                                       rotation_sigma_rad),
          nullptr, rotation, translation);
      ++summary.num_pose_prior_residuals;
    } else if (num_constraints[i] < options_.min_constraints_per_image) {
      summary.unconstrained_image_ids.push_back(image.image_id);
      problem.SetParameterBlockConstant(rotation);
      problem.SetParameterBlockConstant(translation);
      ++summary.num_fixed_images;
      continue;
    }
    if (first_image < 0) {
      first_image = static_cast<int>(i);
    } else if (second_image < 0) {
      second_image = static_cast<int>(i);
    }
  }
  for (const image_t image_id : summary.unconstrained_image_ids) {
    LOG(WARNING) << "Line bundle adjustment: image " << image_id
                 << " is unconstrained and keeps its input pose";
  }

  if (options_.gauge == LineBAGauge::kFixFirstPose && first_image >= 0) {
    Image& image = reconstruction->images[first_image];
    problem.SetParameterBlockConstant(image.cam_from_world.rotation.coeffs().data());
    problem.SetParameterBlockConstant(image.cam_from_world.translation.data());
    ++summary.num_fixed_images;
  }
  if (!use_priors && summary.num_lidar_residuals == 0 &&
      summary.num_lidar_edge_residuals == 0 &&
      summary.num_lidar_point_residuals == 0 && first_image >= 0 &&
      second_image >= 0) {
    // No metric information: fix the scale through one coordinate of the
    // second image's translation.
    const Image& first = reconstruction->images[first_image];
    Image& second = reconstruction->images[second_image];
    int axis = 0;
    (second.cam_from_world.translation - first.cam_from_world.translation)
        .cwiseAbs()
        .maxCoeff(&axis);
    owned_manifolds.push_back(
        std::make_unique<ceres::SubsetManifold>(3, std::vector<int>{axis}));
    problem.SetManifold(second.cam_from_world.translation.data(),
                        owned_manifolds.back().get());
    LOG(WARNING) << "Line bundle adjustment without LIDAR residuals and pose "
                    "priors: scale fixed by translation axis "
                 << axis << " of image " << second.image_id;
  }

  // Intrinsics.
  for (const auto& [camera_id, used] : camera_used) {
    Camera& camera = reconstruction->cameras.at(camera_id);
    std::vector<int> constant_idxs;
    const auto add = [&](const std::vector<size_t>& idxs, bool refine) {
      if (!refine) {
        constant_idxs.insert(constant_idxs.end(), idxs.begin(), idxs.end());
      }
    };
    add(CameraModelFocalLengthIdxs(camera.model_id),
        options_.refine_focal_length);
    add(CameraModelPrincipalPointIdxs(camera.model_id),
        options_.refine_principal_point);
    add(CameraModelExtraParamsIdxs(camera.model_id),
        options_.refine_extra_params);
    if (constant_idxs.size() == camera.params.size()) {
      problem.SetParameterBlockConstant(camera.params.data());
    } else if (!constant_idxs.empty()) {
      owned_manifolds.push_back(std::make_unique<ceres::SubsetManifold>(
          static_cast<int>(camera.params.size()), constant_idxs));
      problem.SetManifold(camera.params.data(), owned_manifolds.back().get());
    }
  }

  if (problem.NumResidualBlocks() == 0) {
    LOG(WARNING) << "Line bundle adjustment: no residuals, nothing to solve";
    summary.termination_message = "No residuals";
    return summary;
  }

  // Schur elimination order: points and lines first, then poses and
  // intrinsics.
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (const point3D_t point3D_id : point_ids) {
    ordering->AddElementToGroup(reconstruction->points3D.at(point3D_id).xyz.data(),
                                0);
  }
  for (const size_t line_index : line_indices) {
    ordering->AddElementToGroup(line_params[line_index].data(), 0);
  }
  for (size_t i = 0; i < reconstruction->images.size(); ++i) {
    if (image_used[i]) {
      Image& image = reconstruction->images[i];
      ordering->AddElementToGroup(image.cam_from_world.rotation.coeffs().data(), 1);
      ordering->AddElementToGroup(image.cam_from_world.translation.data(), 1);
    }
  }
  for (const auto& [camera_id, used] : camera_used) {
    ordering->AddElementToGroup(reconstruction->cameras.at(camera_id).params.data(),
                                1);
  }

  ceres::Solver::Options solver_options;
  solver_options.minimizer_type = ceres::TRUST_REGION;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.linear_solver_type = options_.use_iterative_schur
                                          ? ceres::ITERATIVE_SCHUR
                                          : ceres::SPARSE_SCHUR;
  if (options_.use_iterative_schur) {
    solver_options.preconditioner_type = ceres::SCHUR_JACOBI;
  }
  solver_options.linear_solver_ordering = ordering;
  solver_options.max_num_iterations = options_.max_num_iterations;
  solver_options.function_tolerance = options_.function_tolerance;
  solver_options.gradient_tolerance = options_.gradient_tolerance;
  solver_options.parameter_tolerance = options_.parameter_tolerance;
  solver_options.num_threads =
      options_.num_threads > 0
          ? options_.num_threads
          : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  solver_options.minimizer_progress_to_stdout =
      options_.minimizer_progress_to_stdout;
  solver_options.logging_type = options_.minimizer_progress_to_stdout
                                    ? ceres::PER_MINIMIZER_ITERATION
                                    : ceres::SILENT;
  std::string error;
  THROW_CHECK(solver_options.IsValid(&error),
              "Invalid Ceres options for the line bundle adjustment: " << error);

  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver_options, &problem, &ceres_summary);
  summary.initial_cost = ceres_summary.initial_cost;
  summary.num_iterations = static_cast<int>(ceres_summary.iterations.size()) - 1;
  summary.solve_time_s = ceres_summary.total_time_in_seconds;

  // Second pass for points stuck in a wrong minimum (see the option).
  if (options_.retriangulation_max_error_px > 0.0 && options_.refine_points &&
      ceres_summary.IsSolutionUsable()) {
    for (const point3D_t point3D_id : point_ids) {
      Point3D& point3D = reconstruction->points3D.at(point3D_id);
      Eigen::Vector3d xyz;
      if (MeanReprojectionError(*reconstruction, point3D) >
              options_.retriangulation_max_error_px &&
          TriangulatePoint(*reconstruction, point3D, &xyz)) {
        point3D.xyz = xyz;
        ++summary.num_retriangulated_points;
      }
    }
    if (summary.num_retriangulated_points > 0) {
      ceres::Solve(solver_options, &problem, &ceres_summary);
      summary.num_iterations +=
          static_cast<int>(ceres_summary.iterations.size()) - 1;
      summary.solve_time_s += ceres_summary.total_time_in_seconds;
    }
  }
  summary.final_cost = ceres_summary.final_cost;
  summary.usable = ceres_summary.IsSolutionUsable();
  summary.termination_message = ceres_summary.message;

  // Write back lines, then errors.
  for (const size_t line_index : line_indices) {
    LineTrack& track = (*line_tracks)[line_index];
    track.plucker_in_world = OrthonormalToPlucker(line_params[line_index]);
    ComputeLineSegment(*reconstruction, &track);
  }
  double point_error_sum = 0.0;
  int point_error_count = 0;
  for (const point3D_t point3D_id : point_ids) {
    Point3D& point3D = reconstruction->points3D.at(point3D_id);
    point3D.error = MeanReprojectionError(*reconstruction, point3D);
    point_error_sum += point3D.error * point3D.track.size();
    point_error_count += static_cast<int>(point3D.track.size());
  }
  if (point_error_count > 0) {
    summary.mean_point_error_px = point_error_sum / point_error_count;
  }
  double line_error_sum = 0.0;
  int line_error_count = 0;
  double lidar_squared_sum = 0.0;
  int lidar_count = 0;
  for (const size_t line_index : line_indices) {
    LineTrack& track = (*line_tracks)[line_index];
    track.error = ComputeLineReprojectionError(*reconstruction, track);
    if (track.error >= 0.0) {
      line_error_sum += track.error;
      ++line_error_count;
    }
    for (const LineObservation& observation : track.observations) {
      const Image* image = find_image(observation.image_id);
      if (image == nullptr || !observation.has_lidar) {
        continue;
      }
      const Vector6d line_in_cam =
          TransformPlucker(image->cam_from_world, track.plucker_in_world);
      for (const Eigen::Vector3d& point :
           {observation.start_in_cam, observation.end_in_cam}) {
        const double distance = PointToPluckerLineDistance(line_in_cam, point);
        lidar_squared_sum += distance * distance;
        ++lidar_count;
      }
    }
  }
  if (line_error_count > 0) {
    summary.mean_line_error_px = line_error_sum / line_error_count;
  }
  if (lidar_count > 0) {
    summary.rms_lidar_distance_m = std::sqrt(lidar_squared_sum / lidar_count);
  }
  if (!edges.empty()) {
    double edge_error_sum = 0.0;
    for (const RelativePoseEdge* edge : edges) {
      edge_error_sum += ComputeRelativePoseEdgeError(*reconstruction, *edge);
    }
    summary.mean_lidar_edge_error = edge_error_sum / edges.size();
  }
  if (!point_planes.empty()) {
    double squared_sum = 0.0;
    for (const PointPlaneObservation* plane : point_planes) {
      const Image& image = *find_image(plane->image_id);
      const double distance =
          plane->normal_in_cam.dot(
              image.cam_from_world *
              reconstruction->points3D.at(plane->point3D_id).xyz) -
          plane->offset_m;
      squared_sum += distance * distance;
    }
    summary.rms_lidar_point_distance_m =
        std::sqrt(squared_sum / point_planes.size());
  }
  LOG(INFO) << "Line bundle adjustment: " << summary.ToString();
  if (!summary.usable) {
    LOG(WARNING) << "Line bundle adjustment failed: " << ceres_summary.message;
  }
  return summary;
}

}  // namespace colmap_lidar
