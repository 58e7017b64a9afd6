// The noise of LIDAR registration edges measured by the graph's own loop
// closures (issue 16), for the edges' information matrices.
//
// A registration's information is the Gauss-Newton Hessian of its
// point-to-plane residuals (src/lidar/scan_registration.h), capped at floor
// sigmas. In a straight corridor scanned by a 16-ring LIDAR that Hessian
// claims 5 mm along the corridor's axis while the registrations are off by
// 2-16 cm there (measured on the synthetic corridor_vlp16 cell, 19
// consecutive edges against the ground truth): the floor and wall normals,
// estimated from sparse rings, lean a little along the axis and the
// point-to-plane cost is flat and rough in that direction. The Hessian
// cannot see it; the loops can. A loop edge i -> j registered directly and
// the chain of consecutive edges i -> i+1 -> ... -> j measure the same
// relative pose; their difference (the closure) is the sum of j - i + 1
// independent edge errors. Its robust spread per axis, divided by
// sqrt(j - i + 1), is the per-edge error the data shows.
//
// Random edge errors give closures of zero mean. A closure mean far from
// zero (|t| = |mean| / (sigma / sqrt(n)) beyond max_bias_t) says that the
// loops and the chains disagree systematically: on the KITTI sample the
// two-step loops are 8.8 cm longer on average than the two consecutive
// edges they close (t = 8; moving traffic drags a registration twice as
// far over two steps, and the recording's README puts the drive at about
// 3 m, the consecutive chain's length). Which side is wrong is unknown,
// so such an axis is left as registered and the log says so.
//
// Frame and order: the closure delta of a loop edge is the right
// perturbation of the chained pose, chained * Exp(delta) = loop, as
// [rotation (rad, 3); translation (m, 3)] in the loop's source frame (the
// parameterisation of ScanRegistrationResult::information). The estimate is
// per axis of the sensor frame, so it captures a degenerate direction that
// stays fixed in the sensor frame along the recording (a corridor's axis is
// the sensor's forward direction).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/rigid3.h"

namespace colmap_lidar {

struct LidarEdgeNoiseOptions {
  // Estimate the edge noise from the loop closures, 0/1; off: the
  // registrations' information is used as it is.
  bool enabled = true;
  // At least this many closures (loop edges whose consecutive chain is
  // complete) are needed for an estimate, >= 1: the median of fewer is
  // not a measurement.
  int min_num_closures = 5;
  // An axis whose measured per-edge sigma exceeds the registration's floor
  // sigma by this factor is inflated, and one whose sigma lies below the
  // floor by this factor gets its cap lowered to the measured sigma, >= 1:
  // near the floor the information stays as the Hessian has it.
  double min_excess_ratio = 1.5;
  // A lowered cap stays at or above this fraction of the floor, (0, 1]:
  // the closures of a clean scan measure sub-millimetre noise (0.5 mm and
  // 0.002 deg on the 64-ring quad, a tenth of the floor), which the
  // median of a few dozen closures cannot resolve much further.
  double min_cap_fraction = 0.1;
  // An axis whose closures' mean lies more than this many standard errors
  // from zero, and farther than half the floor sigma, is biased and left as
  // registered, > 0 (a Student t of 17 degrees of freedom passes 4 with
  // probability 0.1 %).
  double max_bias_t = 4.0;

  bool Check() const;
};

// One loop closure: a loop edge i -> j (j >= i + 2) and the chain of
// consecutive edges between them.
struct LidarLoopClosure {
  int i = 0;
  int j = 0;
  // chained * Exp(delta) = loop; [rotation (rad); translation (m)].
  Eigen::Matrix<double, 6, 1> delta = Eigen::Matrix<double, 6, 1>::Zero();
};

struct LidarEdgeNoiseEstimate {
  int num_closures = 0;
  // Robust per-edge standard deviation per axis, [rotation (rad, 3);
  // translation (m, 3)] in the sensor frame: 1.4826 x the median over the
  // closures of |delta_k| / sqrt(j - i + 1). Zero without an estimate.
  Eigen::Matrix<double, 6, 1> sigma = Eigen::Matrix<double, 6, 1>::Zero();
  // Per axis: the mean of delta_k / sqrt(j - i + 1) over the closures and
  // its t statistic against the spread about the median (1.4826 x median
  // absolute deviation / sqrt(n)); biased: |t| > max_bias_t and |mean| >
  // floor / 2.
  Eigen::Matrix<double, 6, 1> mean = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> bias_t = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<bool, 6, 1> biased = Eigen::Matrix<bool, 6, 1>::Constant(false);
  // The variance added to every edge's covariance per axis (the excess
  // of sigma^2 over the floor's, where sigma exceeds the floor by
  // min_excess_ratio; else 0).
  Eigen::Matrix<double, 6, 1> added_variance =
      Eigen::Matrix<double, 6, 1>::Zero();
  // The cap of the registrations' Hessians per axis (CapInformation in
  // src/lidar/scan_registration.h): the floor, or the measured sigma where
  // it lies below the floor by min_excess_ratio (bounded by
  // min_cap_fraction x floor).
  Eigen::Matrix<double, 6, 1> cap_sigma = Eigen::Matrix<double, 6, 1>::Zero();
  // The registrations' floor it was measured against.
  Eigen::Matrix<double, 6, 1> floor_sigma =
      Eigen::Matrix<double, 6, 1>::Zero();
  bool estimated = false;

  // One line: closures, sigmas (deg, m), inflated and tightened axes.
  std::string Format() const;
};

// delta of the closure: chained * Exp(delta) = loop (first order in the
// translation, as the registration's right perturbation).
Eigen::Matrix<double, 6, 1> ClosureDelta(const Rigid3d& chained,
                                         const Rigid3d& loop);

// The estimate from `closures`; `floor_sigma` is the registrations' floor
// [rotation (rad); translation (m)], > 0. Fewer than min_num_closures
// closures, or options.enabled false: estimated = false, nothing added,
// cap_sigma = floor_sigma.
LidarEdgeNoiseEstimate EstimateLidarEdgeNoise(
    const std::vector<LidarLoopClosure>& closures,
    const Eigen::Matrix<double, 6, 1>& floor_sigma,
    const LidarEdgeNoiseOptions& options);

// (information^+ + diag(added_variance))^-1 without inverting a possibly
// singular information: information (I + D information)^-1. A zero
// added_variance returns the information unchanged; a direction without
// information keeps none.
Eigen::Matrix<double, 6, 6> InflateInformation(
    const Eigen::Matrix<double, 6, 6>& information,
    const Eigen::Matrix<double, 6, 1>& added_variance);

}  // namespace colmap_lidar
