#include "src/sfm/model_alignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Umeyama with scale on the columns `indices` of source/target; false when
// the source centres are (nearly) collinear, which leaves the rotation about
// their line free.
bool EstimateSim3(const std::vector<Eigen::Vector3d>& source,
                  const std::vector<Eigen::Vector3d>& target,
                  const std::vector<int>& indices, Sim3d* target_from_source) {
  const int n = static_cast<int>(indices.size());
  if (n < 3) {
    return false;
  }
  Eigen::Matrix3Xd src(3, n);
  Eigen::Matrix3Xd dst(3, n);
  for (int i = 0; i < n; ++i) {
    src.col(i) = source[indices[i]];
    dst.col(i) = target[indices[i]];
  }
  const Eigen::Matrix3Xd centred = src.colwise() - src.rowwise().mean();
  const Eigen::Vector3d singular_values =
      Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
  if (!(singular_values(1) > 1e-3 * singular_values(0)) ||
      singular_values(0) < 1e-9) {
    return false;
  }
  const Eigen::Matrix4d transform = Eigen::umeyama(src, dst, true);
  const Eigen::Matrix3d scaled_rotation = transform.topLeftCorner<3, 3>();
  const double scale = std::cbrt(scaled_rotation.determinant());
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    return false;
  }
  target_from_source->scale = scale;
  target_from_source->rotation = scaled_rotation / scale;
  target_from_source->translation = transform.topRightCorner<3, 1>();
  return true;
}

// Camera data of the model images that have a prior.
struct AlignmentData {
  std::vector<image_t> image_ids;
  std::vector<Eigen::Vector3d> model_centres;
  std::vector<Eigen::Quaterniond> model_rotations;  // cam_from_world
  std::vector<Eigen::Vector3d> prior_centres;
  std::vector<Eigen::Quaterniond> prior_rotations;  // cam_from_world
};

struct ImageResiduals {
  double centre_m = 0.0;
  double rotation_rad = 0.0;
};

ImageResiduals Residuals(const AlignmentData& data, const Sim3d& sim3,
                         int i) {
  ImageResiduals residuals;
  residuals.centre_m =
      (sim3 * data.model_centres[i] - data.prior_centres[i]).norm();
  // Aligned orientation: R_cw' = R_cw R^T (see TransformReconstruction).
  const Eigen::Quaterniond aligned =
      data.model_rotations[i] * Eigen::Quaterniond(sim3.rotation).conjugate();
  residuals.rotation_rad = aligned.angularDistance(data.prior_rotations[i]);
  return residuals;
}

// Weighted least-squares sim3 on the images `indices` from both their
// centres and their orientations: the rotation maximises
//   sum_i |p_i - p|^2-weighted agreement of the centred centres (Umeyama's
//   term, model centres pre-scaled by the ratio of the spreads) / sigma_t^2
//   + sum_i tr(R^T R_prior_wc_i R_model_wc_i^T) / sigma_r^2
// (orthogonal Procrustes on H = sum of both cross-covariances), then the
// scale and translation follow from the centres. The orientations pin the
// rotation about the line of a straight walk, which centres alone leave
// free, and make a minimal sample of 3 noisy centres far less erratic.
// False when the model centres coincide or the scale is not positive.
bool EstimateSim3WithOrientations(const AlignmentData& data,
                                  const std::vector<int>& indices,
                                  double position_sigma_m,
                                  double rotation_sigma_rad,
                                  Sim3d* prior_from_model) {
  const int n = static_cast<int>(indices.size());
  if (n < 2) {
    return false;
  }
  Eigen::Vector3d model_mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d prior_mean = Eigen::Vector3d::Zero();
  for (const int i : indices) {
    model_mean += data.model_centres[i];
    prior_mean += data.prior_centres[i];
  }
  model_mean /= n;
  prior_mean /= n;
  double model_spread = 0.0;
  double prior_spread = 0.0;
  for (const int i : indices) {
    model_spread += (data.model_centres[i] - model_mean).squaredNorm();
    prior_spread += (data.prior_centres[i] - prior_mean).squaredNorm();
  }
  if (!(model_spread > 1e-18)) {
    return false;
  }
  const double initial_scale = std::sqrt(prior_spread / model_spread);
  Eigen::Matrix3d cross = Eigen::Matrix3d::Zero();
  const double centre_weight = 1.0 / (position_sigma_m * position_sigma_m);
  const double rotation_weight = 1.0 / (rotation_sigma_rad * rotation_sigma_rad);
  for (const int i : indices) {
    cross += centre_weight * (data.prior_centres[i] - prior_mean) *
             (initial_scale * (data.model_centres[i] - model_mean)).transpose();
    // World-from-camera axes: prior ones against the model's.
    cross += rotation_weight *
             data.prior_rotations[i].toRotationMatrix().transpose() *
             data.model_rotations[i].toRotationMatrix();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d sign = Eigen::Matrix3d::Identity();
  sign(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0
                   ? -1.0
                   : 1.0;
  const Eigen::Matrix3d rotation =
      svd.matrixU() * sign * svd.matrixV().transpose();
  double numerator = 0.0;
  for (const int i : indices) {
    numerator += (data.prior_centres[i] - prior_mean)
                     .dot(rotation * (data.model_centres[i] - model_mean));
  }
  const double scale = numerator / model_spread;
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    return false;
  }
  prior_from_model->scale = scale;
  prior_from_model->rotation = rotation;
  prior_from_model->translation = prior_mean - scale * (rotation * model_mean);
  return true;
}

// Consensus of `sim3` and its truncated quadratic (MSAC) cost.
std::vector<int> Inliers(const AlignmentData& data, const Sim3d& sim3,
                         double max_centre_m, double max_rotation_rad,
                         double* cost) {
  std::vector<int> inliers;
  *cost = 0.0;
  for (size_t i = 0; i < data.image_ids.size(); ++i) {
    const ImageResiduals r = Residuals(data, sim3, static_cast<int>(i));
    const double normalised =
        std::max(r.centre_m / max_centre_m, r.rotation_rad / max_rotation_rad);
    if (normalised <= 1.0) {
      inliers.push_back(static_cast<int>(i));
      *cost += normalised * normalised;
    } else {
      *cost += 1.0;
    }
  }
  return inliers;
}

}  // namespace

void TransformReconstruction(const Sim3d& target_from_source,
                             Reconstruction* model) {
  const Eigen::Quaterniond rotation(target_from_source.rotation);
  for (Image& image : model->images) {
    // world_from_cam' = sim3 * world_from_cam: centre c' = s R c + t,
    // orientation R_cw' = R_cw R^T.
    const Eigen::Vector3d centre =
        target_from_source * image.ProjectionCenter();
    const Eigen::Quaterniond cam_from_world_rotation =
        (image.cam_from_world.rotation * rotation.conjugate()).normalized();
    image.cam_from_world = Rigid3d(cam_from_world_rotation,
                                   -(cam_from_world_rotation * centre));
  }
  for (auto& [point3D_id, point3D] : model->points3D) {
    point3D.xyz = target_from_source * point3D.xyz;
  }
  for (auto& [line3D_id, line3D] : model->lines3D) {
    line3D.start_in_world = target_from_source * line3D.start_in_world;
    line3D.end_in_world = target_from_source * line3D.end_in_world;
  }
}

PriorAlignmentSummary AlignReconstructionToPriors(
    const std::unordered_map<image_t, Rigid3d>& cam_from_world_priors,
    Reconstruction* model) {
  std::vector<Eigen::Vector3d> model_centres;
  std::vector<Eigen::Vector3d> prior_centres;
  for (const Image& image : model->images) {
    const auto it = cam_from_world_priors.find(image.image_id);
    if (it == cam_from_world_priors.end()) {
      continue;
    }
    model_centres.push_back(image.ProjectionCenter());
    prior_centres.push_back(it->second.Inverse().translation);
  }
  const int num_images = static_cast<int>(model_centres.size());
  THROW_CHECK(num_images >= 3, "Sim3 alignment to the priors needs at least 3 "
                               "model images with a prior pose, got "
                                   << num_images);
  Eigen::Matrix3Xd source(3, num_images);
  Eigen::Matrix3Xd target(3, num_images);
  for (int i = 0; i < num_images; ++i) {
    source.col(i) = model_centres[i];
    target.col(i) = prior_centres[i];
  }
  // Degenerate configurations (all centres on a line) leave the rotation
  // about that line undetermined.
  const Eigen::Matrix3Xd centred =
      source.colwise() - source.rowwise().mean();
  const Eigen::JacobiSVD<Eigen::Matrix3Xd> svd(centred);
  const Eigen::Vector3d singular_values = svd.singularValues();
  THROW_CHECK(singular_values(1) > 1e-3 * std::sqrt(num_images) &&
                  singular_values(1) > 1e-6 * singular_values(0),
              "Sim3 alignment to the priors: the " << num_images
                  << " model camera centres are collinear or identical");

  const Eigen::Matrix4d transform = Eigen::umeyama(source, target, true);
  PriorAlignmentSummary summary;
  summary.num_images = num_images;
  const Eigen::Matrix3d scaled_rotation = transform.topLeftCorner<3, 3>();
  summary.prior_from_model.scale = std::cbrt(scaled_rotation.determinant());
  summary.prior_from_model.rotation =
      scaled_rotation / summary.prior_from_model.scale;
  summary.prior_from_model.translation = transform.topRightCorner<3, 1>();
  double sum_squared = 0.0;
  for (int i = 0; i < num_images; ++i) {
    sum_squared += (summary.prior_from_model * model_centres[i] -
                    prior_centres[i])
                       .squaredNorm();
  }
  summary.rms_residual_m = std::sqrt(sum_squared / num_images);
  TransformReconstruction(summary.prior_from_model, model);
  return summary;
}

bool RobustPriorAlignmentOptions::Check() const {
  return position_sigma_m > 0.0 && rotation_sigma_deg > 0.0 &&
         position_num_sigmas > 0.0 && rotation_num_sigmas > 0.0 && num_trials > 0 && min_num_inliers >= 3 &&
         min_inlier_ratio >= 0.0 && min_inlier_ratio <= 1.0 &&
         max_scale_num_sigmas > 0.0;
}

std::string RobustPriorAlignmentSummary::Format() const {
  std::ostringstream out;
  out << inlier_image_ids.size() << " of " << num_images
      << " images agree with their priors";
  if (rms_residual_m >= 0.0) {
    out << " (scale " << prior_from_model.scale << ", rms " << rms_residual_m
        << " m / " << rms_rotation_error_deg << " deg";
    if (half_scales[0] > 0.0) {
      out << ", half scales " << half_scales[0] << " / " << half_scales[1];
    }
    out << ")";
  }
  out << (accepted ? ": accepted" : ": rejected, " + rejection);
  return out.str();
}

RobustPriorAlignmentSummary RobustAlignReconstructionToPriors(
    const std::unordered_map<image_t, Rigid3d>& cam_from_world_priors,
    const RobustPriorAlignmentOptions& options, Reconstruction* model) {
  THROW_CHECK(options.Check(), "RobustPriorAlignmentOptions are invalid");
  AlignmentData data;
  for (const Image& image : model->images) {
    const auto it = cam_from_world_priors.find(image.image_id);
    if (it == cam_from_world_priors.end()) {
      continue;
    }
    data.image_ids.push_back(image.image_id);
    data.model_centres.push_back(image.ProjectionCenter());
    data.model_rotations.push_back(
        image.cam_from_world.rotation.normalized());
    data.prior_centres.push_back(it->second.Inverse().translation);
    data.prior_rotations.push_back(it->second.rotation.normalized());
  }
  RobustPriorAlignmentSummary summary;
  const int n = static_cast<int>(data.image_ids.size());
  summary.num_images = n;
  const double max_centre_m =
      options.position_num_sigmas * options.position_sigma_m;
  const double rotation_sigma_rad = options.rotation_sigma_deg * M_PI / 180.0;
  const double max_rotation_rad = options.rotation_num_sigmas * rotation_sigma_rad;
  auto reject = [&](const std::string& reason) {
    summary.accepted = false;
    summary.rejection = reason;
    summary.inlier_image_ids.clear();
    summary.outlier_image_ids = data.image_ids;
    return summary;
  };
  if (n < std::max(3, options.min_num_inliers)) {
    return reject("too few images with a prior");
  }

  // RANSAC on minimal samples, then local optimisation of the best.
  std::mt19937 rng(options.random_seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::vector<int> best_inliers;
  double best_cost = std::numeric_limits<double>::infinity();
  Sim3d best_sim3;
  for (int trial = 0; trial < options.num_trials; ++trial) {
    const int a = pick(rng);
    const int b = pick(rng);
    const int c = pick(rng);
    if (a == b || b == c || a == c) {
      continue;
    }
    Sim3d sim3;
    if (!EstimateSim3WithOrientations(data, {a, b, c}, options.position_sigma_m,
                                      rotation_sigma_rad, &sim3)) {
      continue;
    }
    double cost = 0.0;
    std::vector<int> inliers =
        Inliers(data, sim3, max_centre_m, max_rotation_rad, &cost);
    if (inliers.size() > best_inliers.size() ||
        (inliers.size() == best_inliers.size() && cost < best_cost)) {
      best_inliers = std::move(inliers);
      best_cost = cost;
      best_sim3 = sim3;
    }
  }
  // Local optimisation: least squares on the consensus, re-scored, until
  // the consensus stops growing. The least-squares fit replaces the minimal
  // sample's even when it keeps a few less inliers (it is far less noisy);
  // the final consensus is the one of the final fit.
  for (int iteration = 0; iteration < 20 && best_inliers.size() >= 3;
       ++iteration) {
    Sim3d refined;
    if (!EstimateSim3WithOrientations(data, best_inliers,
                                      options.position_sigma_m,
                                      rotation_sigma_rad, &refined)) {
      break;
    }
    best_sim3 = refined;
    double cost = 0.0;
    std::vector<int> inliers =
        Inliers(data, refined, max_centre_m, max_rotation_rad, &cost);
    if (inliers.size() <= best_inliers.size()) {
      break;
    }
    best_inliers = std::move(inliers);
  }
  best_inliers =
      Inliers(data, best_sim3, max_centre_m, max_rotation_rad, &best_cost);

  // Acceptance tests.
  const int num_inliers = static_cast<int>(best_inliers.size());
  const int min_inliers = std::max(
      options.min_num_inliers,
      static_cast<int>(std::ceil(options.min_inlier_ratio * n)));
  summary.prior_from_model = best_sim3;
  if (num_inliers >= 3) {
    double sum_centre = 0.0;
    double sum_rotation = 0.0;
    for (const int i : best_inliers) {
      const ImageResiduals r = Residuals(data, best_sim3, i);
      sum_centre += r.centre_m * r.centre_m;
      sum_rotation += r.rotation_rad * r.rotation_rad;
    }
    summary.rms_residual_m = std::sqrt(sum_centre / num_inliers);
    summary.rms_rotation_error_deg =
        std::sqrt(sum_rotation / num_inliers) * 180.0 / M_PI;
  }
  if (num_inliers < min_inliers) {
    std::ostringstream reason;
    reason << "consensus of " << num_inliers << " images, need "
           << min_inliers;
    return reject(reason.str());
  }
  // Scale consistency of the two halves along the consensus' main axis.
  {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const int i : best_inliers) {
      mean += data.prior_centres[i];
    }
    mean /= num_inliers;
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const int i : best_inliers) {
      const Eigen::Vector3d d = data.prior_centres[i] - mean;
      scatter += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
    const Eigen::Vector3d axis = eigen.eigenvectors().col(2);
    std::vector<int> sorted = best_inliers;
    std::sort(sorted.begin(), sorted.end(), [&](int l, int r) {
      return axis.dot(data.prior_centres[l]) < axis.dot(data.prior_centres[r]);
    });
    const std::vector<int> halves[2] = {
        std::vector<int>(sorted.begin(), sorted.begin() + num_inliers / 2),
        std::vector<int>(sorted.begin() + num_inliers / 2, sorted.end())};
    double log_scales[2] = {0.0, 0.0};
    double variances[2] = {0.0, 0.0};
    bool ok = true;
    for (int h = 0; h < 2; ++h) {
      Sim3d half_sim3;
      if (!EstimateSim3(data.model_centres, data.prior_centres, halves[h],
                        &half_sim3)) {
        ok = false;
        break;
      }
      // var(log s) = sigma^2 / sum |target - mean|^2 for Umeyama's scale.
      Eigen::Vector3d half_mean = Eigen::Vector3d::Zero();
      for (const int i : halves[h]) {
        half_mean += data.prior_centres[i];
      }
      half_mean /= halves[h].size();
      double spread = 0.0;
      for (const int i : halves[h]) {
        spread += (data.prior_centres[i] - half_mean).squaredNorm();
      }
      summary.half_scales[h] = half_sim3.scale;
      log_scales[h] = std::log(half_sim3.scale);
      variances[h] = options.position_sigma_m * options.position_sigma_m /
                     std::max(spread, 1e-12);
    }
    // Halves whose centres are collinear cannot be tested; the consensus
    // as a whole was not (EstimateSim3 succeeded on it).
    if (ok) {
      const double difference = std::abs(log_scales[0] - log_scales[1]);
      const double allowed =
          options.max_scale_num_sigmas * std::sqrt(variances[0] + variances[1]) +
          0.02;
      if (difference > allowed) {
        std::ostringstream reason;
        reason << "the scales of the two halves differ by "
               << 100.0 * (std::exp(difference) - 1.0) << " % (allowed "
               << 100.0 * (std::exp(allowed) - 1.0) << " %)";
        return reject(reason.str());
      }
    }
  }

  summary.accepted = true;
  std::vector<bool> is_inlier(n, false);
  for (const int i : best_inliers) {
    is_inlier[i] = true;
  }
  for (int i = 0; i < n; ++i) {
    (is_inlier[i] ? summary.inlier_image_ids : summary.outlier_image_ids)
        .push_back(data.image_ids[i]);
  }
  TransformReconstruction(best_sim3, model);
  return summary;
}

}  // namespace colmap_lidar
