#include "src/matching/relative_line_pose.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "src/matching/segment_similarity.h"

namespace colmap_lidar {
namespace {

// A segment in its camera frame: endpoints, midpoint, unit direction.
struct Line {
  Eigen::Vector3d start;
  Eigen::Vector3d end;
  Eigen::Vector3d midpoint;
  Eigen::Vector3d direction;
  // Unit normal of the plane through the camera centre and the segment.
  Eigen::Vector3d plane_normal;
};

Line MakeLine(const MatchingSegment& segment) {
  Line line;
  line.start = segment.start_in_cam;
  line.end = segment.end_in_cam;
  line.midpoint = 0.5 * (line.start + line.end);
  line.direction = (line.end - line.start).normalized();
  line.plane_normal = line.start.cross(line.end).normalized();
  return line;
}

// A candidate correspondence: segment a of view 1, segment b of view 2,
// b's direction signed to agree with a's under the prior rotation.
struct Candidate {
  int a = -1;
  int b = -1;
  Eigen::Vector3d direction_b;
};

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d skew;
  skew << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return skew;
}

Eigen::Matrix3d OrthogonalProjector(const Eigen::Vector3d& direction) {
  return Eigen::Matrix3d::Identity() - direction * direction.transpose();
}

// Mean distance of a's endpoints, moved by (rotation, translation), to b's
// line.
double LineDistance(const Eigen::Matrix3d& rotation,
                    const Eigen::Vector3d& translation, const Line& a,
                    const Line& b) {
  const auto distance = [&](const Eigen::Vector3d& point) {
    const Eigen::Vector3d offset = rotation * point + translation - b.midpoint;
    return (offset - offset.dot(b.direction) * b.direction).norm();
  };
  return 0.5 * (distance(a.start) + distance(a.end));
}

double AngleDeg(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::acos(std::min(1.0, std::abs(u.dot(v)))) * 180.0 / M_PI;
}

double RotationAngleDeg(const Eigen::Matrix3d& rotation) {
  return Eigen::AngleAxisd(rotation).angle() * 180.0 / M_PI;
}

// The rotation taking directions x1, x2 onto y1, y2 (least squares over the
// two and their cross product).
Eigen::Matrix3d RotationFromTwoDirections(const Eigen::Vector3d& x1,
                                          const Eigen::Vector3d& x2,
                                          const Eigen::Vector3d& y1,
                                          const Eigen::Vector3d& y2) {
  const Eigen::Vector3d x3 = x1.cross(x2).normalized();
  const Eigen::Vector3d y3 = y1.cross(y2).normalized();
  const Eigen::Matrix3d covariance =
      y1 * x1.transpose() + y2 * x2.transpose() + y3 * x3.transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d fix = Eigen::Matrix3d::Identity();
  fix(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0
                  ? -1.0
                  : 1.0;
  return svd.matrixU() * fix * svd.matrixV().transpose();
}

class Registration {
 public:
  Registration(const MatchingView& view1, const std::vector<int>& segments1,
               const MatchingView& view2, const LineMatchingOptions& options)
      : options_(options) {
    for (const int idx : segments1) {
      lines1_.push_back(MakeLine(view1.segments.at(idx)));
      descriptors1_.push_back(&view1.segments[idx].descriptor);
    }
    for (const MatchingSegment& segment : view2.segments) {
      lines2_.push_back(MakeLine(segment));
      descriptors2_.push_back(&segment.descriptor);
    }
    const Rigid3d prior = view2.cam_from_world * view1.cam_from_world.Inverse();
    prior_rotation_ = prior.rotation.toRotationMatrix();
    prior_translation_ = prior.translation;
    focal_length_ = view2.camera.MeanFocalLength();
    focal_length1_ = view1.camera.MeanFocalLength();
    sin_inlier_angle_ =
        std::sin(options.relative_pose_inlier_angle_deg * M_PI / 180.0);
    inlier_distance_m_ = options.relative_pose_inlier_distance_m;
  }

  void FindCandidates() {
    candidates_of_.assign(lines1_.size(), {});
    for (size_t a = 0; a < lines1_.size(); ++a) {
      const Line& line1 = lines1_[a];
      const Eigen::Vector3d direction = prior_rotation_ * line1.direction;
      const Eigen::Vector3d midpoint =
          prior_rotation_ * line1.midpoint + prior_translation_;
      const MatchingThresholds gate =
          EffectiveThresholds(options_, midpoint.z(), focal_length_);
      for (size_t b = 0; b < lines2_.size(); ++b) {
        const Line& line2 = lines2_[b];
        if (AngleDeg(direction, line2.direction) >= gate.theta_deg) continue;
        const Eigen::Vector3d offset = midpoint - line2.midpoint;
        const double distance =
            (offset - offset.dot(line2.direction) * line2.direction).norm();
        if (distance >= gate.dO_m) continue;
        if (HammingDistance(*descriptors1_[a], *descriptors2_[b]) >= gate.LBD) {
          continue;
        }
        Candidate candidate;
        candidate.a = static_cast<int>(a);
        candidate.b = static_cast<int>(b);
        candidate.direction_b = direction.dot(line2.direction) >= 0.0
                                    ? line2.direction
                                    : Eigen::Vector3d(-line2.direction);
        candidates_of_[a].push_back(static_cast<int>(candidates_.size()));
        candidates_.push_back(candidate);
      }
    }
  }

  // Per segment of view 1: the best candidate's normalised squared error
  // under the hypothesis (and its index), truncated at 1.
  double Score(const Eigen::Matrix3d& rotation,
               const Eigen::Vector3d& translation, const double distance_scale,
               std::vector<int>* best_candidate) const {
    double cost = 0.0;
    if (best_candidate != nullptr) {
      best_candidate->assign(lines1_.size(), -1);
    }
    for (size_t a = 0; a < lines1_.size(); ++a) {
      double best = 1.0;
      const Eigen::Vector3d direction = rotation * lines1_[a].direction;
      for (const int c : candidates_of_[a]) {
        const Line& b = lines2_[candidates_[c].b];
        // Small angles: the sine is the angle.
        const double angle =
            direction.cross(b.direction).norm() / sin_inlier_angle_;
        if (angle >= 1.0) continue;
        const double distance =
            LineDistance(rotation, translation, lines1_[a], b) / distance_scale;
        const double error = angle * angle + distance * distance;
        if (error < best) {
          best = error;
          if (best_candidate != nullptr) (*best_candidate)[a] = c;
        }
      }
      cost += best;
    }
    return cost;
  }

  // Gauss-Newton on the endpoint-to-line distances of the inliers.
  // Gauss-Newton over the inliers on two kinds of residuals: the 3D
  // distance of a's endpoints to b's line (metric, but dominated by the
  // LIDAR depth noise along the rays), and, both ways, the angle between
  // an endpoint and the other view's interpretation plane of its segment
  // (the plane through the camera centre and the 2D segment: blind to
  // depth noise along the rays, as precise as the 2D detection).
  struct Linearization {
    Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> gradient = Eigen::Matrix<double, 6, 1>::Zero();
    double squared_error = 0.0;
    int num_residuals = 0;
  };

  // Normal equations in (theta, t): rotation <- Exp(theta) rotation,
  // translation <- translation + t.
  Linearization Linearize(const std::vector<int>& inliers,
                          const Eigen::Matrix3d& rotation,
                          const Eigen::Vector3d& translation) const {
    const double weight_3d = 1.0 / kRefineSigma3DM;
    const double weight_plane2 = focal_length_ / kRefineSigmaPx;
    const double weight_plane1 = focal_length1_ / kRefineSigmaPx;
    Linearization lin;
    const auto add = [&](const auto& jacobian, const auto& residual) {
      lin.hessian += jacobian.transpose() * jacobian;
      lin.gradient += jacobian.transpose() * residual;
      lin.squared_error += residual.squaredNorm();
      lin.num_residuals += static_cast<int>(residual.size());
    };
    for (const int c : inliers) {
      const Line& a = lines1_[candidates_[c].a];
      const Line& b = lines2_[candidates_[c].b];
      const Eigen::Matrix3d projector = OrthogonalProjector(b.direction);
      for (const Eigen::Vector3d* point : {&a.start, &a.end}) {
        const Eigen::Vector3d moved = rotation * *point;
        const Eigen::Vector3d in_cam2 = moved + translation;
        // 3D endpoint to line.
        Eigen::Matrix<double, 3, 6> jacobian;
        jacobian.leftCols<3>() = -projector * Skew(moved);
        jacobian.rightCols<3>() = projector;
        add(weight_3d * jacobian,
            Eigen::Vector3d(weight_3d * projector * (in_cam2 - b.midpoint)));
        // Endpoint of a to b's interpretation plane, view 2.
        const double norm = in_cam2.norm();
        if (norm < 1e-9) continue;
        const Eigen::Matrix<double, 1, 3> d_residual =
            weight_plane2 * (b.plane_normal.transpose() / norm -
                             b.plane_normal.dot(in_cam2) * in_cam2.transpose() /
                                 (norm * norm * norm));
        Eigen::Matrix<double, 1, 6> plane_jacobian;
        plane_jacobian.leftCols<3>() = -d_residual * Skew(moved);
        plane_jacobian.rightCols<3>() = d_residual;
        add(plane_jacobian,
            Eigen::Matrix<double, 1, 1>(weight_plane2 *
                                        b.plane_normal.dot(in_cam2) / norm));
      }
      // Endpoints of b to a's interpretation plane, view 1:
      // q = R^T (B - t); dq/dtheta = R^T [B - t]x, dq/dt = -R^T.
      for (const Eigen::Vector3d* point : {&b.start, &b.end}) {
        const Eigen::Vector3d offset = *point - translation;
        const Eigen::Vector3d in_cam1 = rotation.transpose() * offset;
        const double norm = in_cam1.norm();
        if (norm < 1e-9) continue;
        const Eigen::Matrix<double, 1, 3> d_residual =
            weight_plane1 * (a.plane_normal.transpose() / norm -
                             a.plane_normal.dot(in_cam1) * in_cam1.transpose() /
                                 (norm * norm * norm));
        Eigen::Matrix<double, 1, 6> plane_jacobian;
        plane_jacobian.leftCols<3>() =
            d_residual * rotation.transpose() * Skew(offset);
        plane_jacobian.rightCols<3>() = -d_residual * rotation.transpose();
        add(plane_jacobian,
            Eigen::Matrix<double, 1, 1>(weight_plane1 *
                                        a.plane_normal.dot(in_cam1) / norm));
      }
    }
    return lin;
  }

  void Refine(const std::vector<int>& inliers, Eigen::Matrix3d* rotation,
              Eigen::Vector3d* translation,
              const int num_iterations = kGaussNewtonIterations) const {
    for (int iteration = 0; iteration < num_iterations; ++iteration) {
      const Linearization lin = Linearize(inliers, *rotation, *translation);
      const Eigen::Matrix<double, 6, 1> step =
          lin.hessian.ldlt().solve(-lin.gradient);
      if (!step.allFinite()) return;
      const Eigen::Vector3d omega = step.head<3>();
      if (omega.norm() > 0.0) {
        *rotation = Eigen::AngleAxisd(omega.norm(), omega.normalized())
                        .toRotationMatrix() *
                    *rotation;
      }
      *translation += step.tail<3>();
      if (step.norm() < 1e-9) return;
    }
  }

  RelativeLinePose Run(const uint32_t seed) {
    RelativeLinePose result;
    max_rotation_change_deg_ =
        EffectiveThresholds(options_, 1.0, focal_length_).theta_deg;
    FindCandidates();
    result.num_candidates = static_cast<int>(candidates_.size());
    if (result.num_candidates < 2) return result;
    Eigen::Matrix3d rotation;
    if (!EstimateRotation(seed, &rotation)) return result;
    // Screen the vote peaks with one short refinement each; refine the
    // most promising ones fully.
    std::vector<std::pair<double, Eigen::Vector3d>> screened;
    for (const Eigen::Vector3d& translation : VoteTranslations(rotation)) {
      screened.emplace_back(Screen(rotation, translation), translation);
    }
    std::sort(screened.begin(), screened.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::pair<double, RelativeLinePose>> hypotheses;
    for (size_t h = 0;
         h < screened.size() && static_cast<int>(h) < kFullHypotheses; ++h) {
      if (!std::isfinite(screened[h].first)) break;
      RelativeLinePose candidate = result;
      const double cost = Finish(rotation, screened[h].second, &candidate);
      if (std::isfinite(cost)) hypotheses.emplace_back(cost, candidate);
    }
    if (hypotheses.empty()) return result;
    std::sort(hypotheses.begin(), hypotheses.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    const int num_hypotheses = static_cast<int>(hypotheses.size());
    result = hypotheses.front().second;
    result.num_hypotheses = num_hypotheses;
    result.cost = hypotheses.front().first;
    // The runner-up: the best hypothesis that converged elsewhere.
    for (size_t h = 1; h < hypotheses.size(); ++h) {
      const Rigid3d& other = hypotheses[h].second.cam2_from_cam1;
      if ((other.translation - result.cam2_from_cam1.translation).norm() >
              kDistinctTranslationM ||
          RotationAngleDeg(
              (other.rotation * result.cam2_from_cam1.rotation.inverse())
                  .toRotationMatrix()) > kDistinctRotationDeg) {
        result.runner_up_cost = hypotheses[h].first;
        result.runner_up_inliers = hypotheses[h].second.num_inliers;
        break;
      }
    }
    return result;
  }

  // The rotation alone, from the candidates' directions: any candidate of
  // the right direction family agrees, true match or not, so that RANSAC on
  // pairs of directions converges in a few samples. False when the
  // directions cannot fix it (one family).
  bool EstimateRotation(const uint32_t seed, Eigen::Matrix3d* rotation) const {
    const int num_candidates = static_cast<int>(candidates_.size());
    std::vector<Eigen::Vector3d> from(num_candidates);
    for (int c = 0; c < num_candidates; ++c) {
      const Eigen::Vector3d& direction = lines1_[candidates_[c].a].direction;
      from[c] =
          (prior_rotation_ * direction).dot(candidates_[c].direction_b) >= 0.0
              ? direction
              : Eigen::Vector3d(-direction);
    }
    const double cos_inlier =
        std::cos(options_.relative_pose_inlier_angle_deg * M_PI / 180.0);
    const auto count_inliers = [&](const Eigen::Matrix3d& r,
                                   std::vector<int>* inliers) {
      int count = 0;
      if (inliers != nullptr) inliers->clear();
      for (int c = 0; c < num_candidates; ++c) {
        if ((r * from[c]).dot(candidates_[c].direction_b) > cos_inlier) {
          ++count;
          if (inliers != nullptr) inliers->push_back(c);
        }
      }
      return count;
    };
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> pick(0, num_candidates - 1);
    int best_count = 0;
    Eigen::Matrix3d best = prior_rotation_;
    for (int sample = 0; sample < kRotationSamples; ++sample) {
      const int c1 = pick(rng);
      const int c2 = pick(rng);
      if (AngleDeg(from[c1], from[c2]) < kMinSampleAngleDeg ||
          AngleDeg(candidates_[c1].direction_b, candidates_[c2].direction_b) <
              kMinSampleAngleDeg) {
        continue;
      }
      const Eigen::Matrix3d r = RotationFromTwoDirections(
          from[c1], from[c2], candidates_[c1].direction_b,
          candidates_[c2].direction_b);
      if (RotationAngleDeg(r * prior_rotation_.transpose()) >
          max_rotation_change_deg_) {
        continue;
      }
      const int count = count_inliers(r, nullptr);
      if (count > best_count) {
        best_count = count;
        best = r;
      }
    }
    if (best_count < 2) return false;
    // Least squares over the inliers (Kabsch on directions).
    std::vector<int> inliers;
    for (int round = 0; round < 2; ++round) {
      count_inliers(best, &inliers);
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
      for (const int c : inliers) {
        covariance += candidates_[c].direction_b * from[c].transpose();
        spread += from[c] * from[c].transpose();
      }
      // Two directions at least: the second eigenvalue of the spread.
      if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(spread).eigenvalues()(
              1) < kMinRotationConditioning) {
        return false;
      }
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
          covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix3d fix = Eigen::Matrix3d::Identity();
      fix(2, 2) =
          (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0
                                                                          : 1.0;
      best = svd.matrixU() * fix * svd.matrixV().transpose();
    }
    *rotation = best;
    return true;
  }

  // Translation hypotheses under `rotation`: each candidate (a, b) allows
  // the translations of a line (a's midpoint onto b's line), which vote in
  // a grid around the prior; the best local maxima (kMaxTranslationPeaks,
  // kPeakSeparationCells apart) are returned.
  std::vector<Eigen::Vector3d> VoteTranslations(
      const Eigen::Matrix3d& rotation) const {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Line& line : lines1_) centroid += line.midpoint;
    centroid /= static_cast<double>(lines1_.size());
    // The prior translation, moved so that the segments' centroid stays put
    // under the new rotation; the half size is the distance gate there.
    const Eigen::Vector3d center =
        prior_translation_ + (prior_rotation_ - rotation) * centroid;
    const double depth = (prior_rotation_ * centroid + prior_translation_).z();
    const double cell = kVoteCellM;
    const double half_size =
        EffectiveThresholds(options_, depth, focal_length_).dO_m;
    const int size =
        std::max(1, static_cast<int>(std::ceil(2.0 * half_size / cell)));
    const Eigen::Vector3d origin =
        center - Eigen::Vector3d::Constant(half_size);
    const double extent = size * cell;
    std::vector<float> votes(static_cast<size_t>(size) * size * size, 0.0f);
    const auto index_of = [&](int x, int y, int z) {
      return (static_cast<size_t>(z) * size + y) * size + x;
    };
    for (const Candidate& c : candidates_) {
      const Eigen::Vector3d point =
          lines2_[c.b].midpoint - rotation * lines1_[c.a].midpoint - origin;
      const Eigen::Vector3d& direction = c.direction_b;
      // Clip the line to the grid box (slabs).
      double s_min = -std::numeric_limits<double>::infinity();
      double s_max = std::numeric_limits<double>::infinity();
      bool inside = true;
      for (int k = 0; k < 3 && inside; ++k) {
        if (std::abs(direction(k)) < 1e-12) {
          inside = point(k) >= 0.0 && point(k) < extent;
          continue;
        }
        double s0 = -point(k) / direction(k);
        double s1 = (extent - point(k)) / direction(k);
        if (s0 > s1) std::swap(s0, s1);
        s_min = std::max(s_min, s0);
        s_max = std::min(s_max, s1);
      }
      if (!inside || !(s_min < s_max)) continue;
      size_t last = std::numeric_limits<size_t>::max();
      for (double s = s_min; s < s_max; s += cell) {
        const Eigen::Vector3d q = (point + s * direction) / cell;
        const int x = std::clamp(static_cast<int>(q.x()), 0, size - 1);
        const int y = std::clamp(static_cast<int>(q.y()), 0, size - 1);
        const int z = std::clamp(static_cast<int>(q.z()), 0, size - 1);
        const size_t index = index_of(x, y, z);
        if (index == last) continue;
        votes[index] += 1.0f;
        last = index;
      }
    }
    // Local maxima of the 3x3x3 box sums (a line crossing a cell corner
    // votes in a neighbour), strongest first.
    struct Peak {
      float score;
      int x, y, z;
    };
    std::vector<Peak> peaks;
    const auto box_sum = [&](int x, int y, int z) {
      float sum = 0.0f;
      for (int dz = -1; dz <= 1; ++dz) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy, zz = z + dz;
            if (xx < 0 || yy < 0 || zz < 0 || xx >= size || yy >= size ||
                zz >= size) {
              continue;
            }
            sum += votes[index_of(xx, yy, zz)];
          }
        }
      }
      return sum;
    };
    for (int z = 0; z < size; ++z) {
      for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
          // A solution needs two non-parallel lines through its cell.
          if (votes[index_of(x, y, z)] < 2.0f) continue;
          peaks.push_back({box_sum(x, y, z), x, y, z});
        }
      }
    }
    // Only the strongest few hundred can make the cut.
    const auto stronger = [](const Peak& a, const Peak& b) {
      return a.score > b.score;
    };
    if (peaks.size() > kMaxSortedPeaks) {
      std::nth_element(peaks.begin(), peaks.begin() + kMaxSortedPeaks,
                       peaks.end(), stronger);
      peaks.resize(kMaxSortedPeaks);
    }
    std::sort(peaks.begin(), peaks.end(), stronger);
    std::vector<Eigen::Vector3d> translations;
    std::vector<Peak> kept;
    for (const Peak& peak : peaks) {
      bool separate = true;
      for (const Peak& other : kept) {
        separate &=
            std::max({std::abs(peak.x - other.x), std::abs(peak.y - other.y),
                      std::abs(peak.z - other.z)}) > kPeakSeparationCells;
      }
      if (!separate) continue;
      kept.push_back(peak);
      translations.push_back(origin + cell * Eigen::Vector3d(peak.x + 0.5,
                                                             peak.y + 0.5,
                                                             peak.z + 0.5));
      if (static_cast<int>(kept.size()) >= kMaxTranslationPeaks) break;
    }
    return translations;
  }

  // Inliers <-> refinement from (rotation, translation), then validation.
  RelativeLinePose RunFrom(const Rigid3d& cam2_from_cam1) {
    RelativeLinePose result;
    max_rotation_change_deg_ =
        EffectiveThresholds(options_, 1.0, focal_length_).theta_deg;
    FindCandidates();
    result.num_candidates = static_cast<int>(candidates_.size());
    Finish(cam2_from_cam1.rotation.toRotationMatrix(),
           cam2_from_cam1.translation, &result);
    return result;
  }

  // MSAC cost after a short refinement from a vote cell's centre.
  double Screen(Eigen::Matrix3d rotation, Eigen::Vector3d translation) const {
    std::vector<int> best_candidate;
    Score(rotation, translation, std::max(inlier_distance_m_, kVoteCellM),
          &best_candidate);
    std::vector<int> inliers;
    for (const int c : best_candidate) {
      if (c >= 0) inliers.push_back(c);
    }
    if (static_cast<int>(inliers.size()) < 2) {
      return std::numeric_limits<double>::infinity();
    }
    Refine(inliers, &rotation, &translation, kScreeningIterations);
    return Score(rotation, translation, inlier_distance_m_, nullptr);
  }

  // Returns the final MSAC cost.
  double Finish(Eigen::Matrix3d best_rotation, Eigen::Vector3d best_translation,
                RelativeLinePose* result_ptr) const {
    RelativeLinePose& result = *result_ptr;
    std::vector<int> best_candidate;
    std::vector<int> inliers;
    for (int round = 0; round < kRefinementRounds; ++round) {
      // The first round starts from a vote cell's centre.
      Score(best_rotation, best_translation,
            round == 0 ? std::max(inlier_distance_m_, kVoteCellM)
                       : inlier_distance_m_,
            &best_candidate);
      inliers.clear();
      for (const int c : best_candidate) {
        if (c >= 0) inliers.push_back(c);
      }
      if (static_cast<int>(inliers.size()) < 2) {
        return std::numeric_limits<double>::infinity();
      }
      Refine(inliers, &best_rotation, &best_translation);
    }
    const double cost = Score(best_rotation, best_translation,
                              inlier_distance_m_, &best_candidate);
    inliers.clear();
    Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
    for (const int c : best_candidate) {
      if (c < 0) continue;
      inliers.push_back(c);
      information += OrthogonalProjector(lines2_[candidates_[c].b].direction);
    }
    result.num_inliers = static_cast<int>(inliers.size());
    result.translation_conditioning =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(information)
            .eigenvalues()(0);
    result.cam2_from_cam1 = Rigid3d(
        Eigen::Quaterniond(best_rotation).normalized(), best_translation);
    // Information of (theta, t), scaled by the a posteriori variance factor
    // (the residuals' scales above are nominal), with a floor on the
    // covariance for what the residuals do not model.
    const Linearization lin =
        Linearize(inliers, best_rotation, best_translation);
    const double variance_factor =
        lin.num_residuals > 6
            ? std::max(kMinVarianceFactor,
                       lin.squared_error / (lin.num_residuals - 6))
            : 1.0;
    Eigen::Matrix<double, 6, 6> covariance =
        (lin.hessian / variance_factor)
            .ldlt()
            .solve(Eigen::Matrix<double, 6, 6>::Identity());
    covariance.diagonal().head<3>().array() +=
        std::pow(kMinSigmaRotationDeg * M_PI / 180.0, 2);
    covariance.diagonal().tail<3>().array() +=
        std::pow(kMinSigmaTranslationM, 2);
    result.information =
        covariance.ldlt().solve(Eigen::Matrix<double, 6, 6>::Identity());
    result.valid =
        result.num_inliers >= options_.relative_pose_min_inliers &&
        result.translation_conditioning >= kMinTranslationConditioning &&
        RotationAngleDeg(best_rotation * prior_rotation_.transpose()) <=
            max_rotation_change_deg_;
    return cost;
  }

 private:
  static constexpr double kMinSampleAngleDeg = 20.0;
  static constexpr int kRotationSamples = 100;
  // Second eigenvalue of the sum of x x^T over the direction inliers.
  static constexpr double kMinRotationConditioning = 1.0;
  static constexpr double kVoteCellM = 0.15;
  static constexpr double kDistinctTranslationM = 0.3;
  static constexpr double kDistinctRotationDeg = 1.0;
  static constexpr int kMaxTranslationPeaks = 12;
  static constexpr size_t kMaxSortedPeaks = 400;
  static constexpr int kScreeningIterations = 2;
  static constexpr int kFullHypotheses = 3;
  static constexpr int kPeakSeparationCells = 2;
  static constexpr int kRefinementRounds = 3;
  static constexpr int kGaussNewtonIterations = 5;
  // Noise scales of the refinement's residuals: 3D endpoint to line, and
  // endpoint to interpretation plane in pixels.
  static constexpr double kRefineSigma3DM = 0.05;
  static constexpr double kRefineSigmaPx = 1.0;
  static constexpr double kMinVarianceFactor = 0.25;
  static constexpr double kMinSigmaRotationDeg = 0.03;
  static constexpr double kMinSigmaTranslationM = 0.005;
  // About two lines' worth of constraint along the weakest axis.
  static constexpr double kMinTranslationConditioning = 1.5;

  const LineMatchingOptions& options_;
  std::vector<Line> lines1_;
  std::vector<Line> lines2_;
  std::vector<const std::array<uint8_t, 32>*> descriptors1_;
  std::vector<const std::array<uint8_t, 32>*> descriptors2_;
  Eigen::Matrix3d prior_rotation_;
  Eigen::Vector3d prior_translation_;
  double focal_length_ = 1.0;  // view 2
  double focal_length1_ = 1.0;
  double sin_inlier_angle_ = 1.0;
  double inlier_distance_m_ = 0.1;
  double max_rotation_change_deg_ = 180.0;
  std::vector<Candidate> candidates_;
  std::vector<std::vector<int>> candidates_of_;
};

}  // namespace

RelativeLinePose EstimateRelativeLinePose(const MatchingView& view1,
                                          const std::vector<int>& segments1,
                                          const MatchingView& view2,
                                          const LineMatchingOptions& options,
                                          const uint32_t seed) {
  Registration registration(view1, segments1, view2, options);
  return registration.Run(seed);
}

RelativeLinePose RefineRelativeLinePose(const MatchingView& view1,
                                        const std::vector<int>& segments1,
                                        const MatchingView& view2,
                                        const LineMatchingOptions& options,
                                        const Rigid3d& cam2_from_cam1) {
  Registration registration(view1, segments1, view2, options);
  return registration.RunFrom(cam2_from_cam1);
}

}  // namespace colmap_lidar
