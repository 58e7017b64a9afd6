#include "src/sfm/lidar_edge_noise.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <glog/logging.h>

namespace colmap_lidar {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Median absolute value -> standard deviation of a normal distribution.
constexpr double kMadToSigma = 1.4826;

double Median(std::vector<double> values) {
  const size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + middle, values.end());
  const double upper = values[middle];
  if (values.size() % 2 == 1) {
    return upper;
  }
  return 0.5 * (upper + *std::max_element(values.begin(),
                                          values.begin() + middle));
}

}  // namespace

bool LidarEdgeNoiseOptions::Check() const {
  if (min_num_closures < 1) {
    LOG(ERROR) << "LidarPoseGraph.edge_noise_min_num_closures = "
               << min_num_closures << " is out of range (>= 1)";
    return false;
  }
  if (!(min_cap_fraction > 0.0 && min_cap_fraction <= 1.0)) {
    LOG(ERROR) << "LidarPoseGraph.edge_noise_min_cap_fraction = "
               << min_cap_fraction << " is out of range ((0, 1])";
    return false;
  }
  if (!(max_bias_t > 0.0)) {
    LOG(ERROR) << "LidarPoseGraph.edge_noise_max_bias_t = " << max_bias_t
               << " is out of range (> 0)";
    return false;
  }
  if (!(min_excess_ratio >= 1.0)) {
    LOG(ERROR) << "LidarPoseGraph.edge_noise_min_excess_ratio = "
               << min_excess_ratio << " is out of range (>= 1)";
    return false;
  }
  return true;
}

std::string LidarEdgeNoiseEstimate::Format() const {
  std::ostringstream out;
  if (!estimated) {
    out << "edge noise: " << num_closures
        << " loop closures, too few for an estimate (registration "
           "information as it is)";
    return out.str();
  }
  out.precision(3);
  out << "edge noise from " << num_closures
      << " loop closures: sigma rotation (" << sigma[0] * 180.0 / kPi << ", "
      << sigma[1] * 180.0 / kPi << ", " << sigma[2] * 180.0 / kPi
      << ") deg, translation (" << sigma[3] << ", " << sigma[4] << ", "
      << sigma[5] << ") m per sensor axis; ";
  static const char* const kAxisNames[6] = {"rx", "ry", "rz", "x", "y", "z"};
  std::string inflated;
  std::string tightened;
  std::ostringstream biased_axes;
  biased_axes.precision(3);
  for (int k = 0; k < 6; ++k) {
    if (biased[k]) {
      biased_axes << (biased_axes.tellp() > 0 ? ", " : "") << kAxisNames[k]
                  << " (mean " << (k < 3 ? mean[k] * 180.0 / kPi : mean[k])
                  << (k < 3 ? " deg" : " m") << ", t = " << bias_t[k] << ")";
    }
    if (added_variance[k] > 0.0) {
      inflated += (inflated.empty() ? "" : ", ") + std::string(kAxisNames[k]);
    }
    if (cap_sigma[k] > 0.0 && cap_sigma[k] < floor_sigma[k]) {
      tightened += (tightened.empty() ? "" : ", ") + std::string(kAxisNames[k]);
    }
  }
  out << (inflated.empty() ? "none inflated" : "inflated beyond the floor: " + inflated)
      << "; "
      << (tightened.empty() ? "no cap lowered"
                            : "cap lowered below the floor: " + tightened);
  if (biased_axes.tellp() > 0) {
    out << "; WARNING: loops and chains disagree systematically along "
        << biased_axes.str()
        << " (moving objects?): left as registered";
  }
  return out.str();
}

Eigen::Matrix<double, 6, 1> ClosureDelta(const Rigid3d& chained,
                                         const Rigid3d& loop) {
  const Rigid3d step = chained.Inverse() * loop;
  const Eigen::AngleAxisd angle_axis(step.rotation.normalized());
  Eigen::Matrix<double, 6, 1> delta;
  delta.head<3>() = angle_axis.angle() * angle_axis.axis();
  delta.tail<3>() = step.translation;
  return delta;
}

LidarEdgeNoiseEstimate EstimateLidarEdgeNoise(
    const std::vector<LidarLoopClosure>& closures,
    const Eigen::Matrix<double, 6, 1>& floor_sigma,
    const LidarEdgeNoiseOptions& options) {
  LidarEdgeNoiseEstimate estimate;
  estimate.num_closures = static_cast<int>(closures.size());
  estimate.floor_sigma = floor_sigma;
  estimate.cap_sigma = floor_sigma;
  if (!options.enabled ||
      estimate.num_closures < std::max(1, options.min_num_closures)) {
    return estimate;
  }
  for (int k = 0; k < 6; ++k) {
    // delta_k / sqrt(j - i + 1): a closure sums j - i consecutive edges'
    // errors and the loop edge's own.
    std::vector<double> signed_values;
    std::vector<double> per_edge;
    signed_values.reserve(closures.size());
    per_edge.reserve(closures.size());
    double sum = 0.0;
    for (const LidarLoopClosure& closure : closures) {
      const double num_edges = closure.j - closure.i + 1;
      signed_values.push_back(closure.delta[k] / std::sqrt(num_edges));
      per_edge.push_back(std::abs(signed_values.back()));
      sum += signed_values.back();
    }
    estimate.sigma[k] = kMadToSigma * Median(per_edge);
    // Bias: the signed values' mean against their spread about the median.
    estimate.mean[k] = sum / signed_values.size();
    const double median = Median(signed_values);
    std::vector<double> deviations;
    deviations.reserve(signed_values.size());
    for (const double value : signed_values) {
      deviations.push_back(std::abs(value - median));
    }
    const double spread = kMadToSigma * Median(deviations);
    const double standard_error =
        spread / std::sqrt(static_cast<double>(signed_values.size()));
    estimate.bias_t[k] = standard_error > 0.0
                             ? estimate.mean[k] / standard_error
                             : (estimate.mean[k] == 0.0 ? 0.0 : 1e9);
    // Significant and large enough to matter: a bias below half the
    // registration's floor (0.2 mm on the 64-ring quad, t = 9) changes no
    // pose that the floor would not.
    estimate.biased[k] = std::abs(estimate.bias_t[k]) > options.max_bias_t &&
                         std::abs(estimate.mean[k]) > 0.5 * floor_sigma[k];
    if (estimate.biased[k]) {
      continue;
    }
    if (estimate.sigma[k] > options.min_excess_ratio * floor_sigma[k]) {
      estimate.added_variance[k] =
          estimate.sigma[k] * estimate.sigma[k] - floor_sigma[k] * floor_sigma[k];
    } else if (options.min_excess_ratio * estimate.sigma[k] < floor_sigma[k]) {
      estimate.cap_sigma[k] =
          std::max(estimate.sigma[k], options.min_cap_fraction * floor_sigma[k]);
    }
  }
  estimate.estimated = true;
  return estimate;
}

Eigen::Matrix<double, 6, 6> InflateInformation(
    const Eigen::Matrix<double, 6, 6>& information,
    const Eigen::Matrix<double, 6, 1>& added_variance) {
  if (!(added_variance.array() > 0.0).any()) {
    return information;
  }
  // (I^+ + D)^-1 = I (Id + D I)^-1; Id + D I has eigenvalues >= 1 (D I is
  // similar to D^1/2 I D^1/2, positive semi-definite), so it is invertible.
  const Eigen::Matrix<double, 6, 6> identity =
      Eigen::Matrix<double, 6, 6>::Identity();
  const Eigen::Matrix<double, 6, 6> inflated =
      information *
      (identity + added_variance.asDiagonal() * information).inverse();
  return 0.5 * (inflated + inflated.transpose());
}

}  // namespace colmap_lidar
