#include "src/mesh/line_validation.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "colmap_ext/util/logging.h"
#include "src/mesh/local_plane.h"

namespace colmap_lidar {
namespace {

// Points evaluated for the spacing estimate.
constexpr size_t kMaxSpacingSamples = 2000;
// Metres.
constexpr double kMinSpacing = 1e-4;

// Median distance of a point to its k-th nearest neighbour, over an evenly
// strided sample of `points`. A grid with cells of h finds every neighbour
// within h exactly; h doubles until more than half the sample has its k-th
// neighbour within h (the others are farther, so the median is exact).
double EstimateSpacing(const std::vector<Eigen::Vector3d>& points, int k) {
  const size_t num_samples = std::min(kMaxSpacingSamples, points.size());
  const size_t stride = points.size() / num_samples;
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& point : points) box.extend(point);
  // Points on surfaces: about diagonal / sqrt(N) apart.
  double cell_size = std::max(
      box.diagonal().norm() / std::sqrt(static_cast<double>(points.size())),
      kMinSpacing);
  std::vector<double> squared;
  for (int attempt = 0; attempt < 64; ++attempt, cell_size *= 2) {
    const RadiusGrid grid(points, cell_size);
    std::vector<double> known;
    for (size_t s = 0; s < num_samples; ++s) {
      const Eigen::Vector3d& point = points[s * stride];
      squared.clear();
      grid.ForEachNear(point, [&](uint32_t j) {
        squared.push_back((points[j] - point).squaredNorm());
      });
      // The point itself is its own 0-th neighbour.
      if (squared.size() <= static_cast<size_t>(k)) continue;
      std::nth_element(squared.begin(), squared.begin() + k, squared.end());
      const double distance = std::sqrt(squared[k]);
      if (distance <= cell_size) known.push_back(distance);
    }
    const size_t median_rank = num_samples / 2;
    if (known.size() > median_rank) {
      std::nth_element(known.begin(), known.begin() + median_rank,
                       known.end());
      return known[median_rank];
    }
  }
  THROW_ERROR("Line validation: cannot estimate the point spacing");
}

// Median, over an evenly strided sample of `points`, of the standard
// deviation of the points within `radius` of a sample point along the
// normal of their plane (principal components; at least 6 neighbours).
// Flat neighbourhoods, the majority on the surfaces we mesh, give the
// noise; those at creases and edges deviate more and fall above the
// median. 0 when no sample has enough neighbours. `grid`'s cells are at
// least `radius`.
double EstimateNoise(const std::vector<Eigen::Vector3d>& points,
                     const RadiusGrid& grid, double radius) {
  const size_t num_samples = std::min(kMaxSpacingSamples, points.size());
  const size_t stride = points.size() / num_samples;
  std::vector<double> deviations;
  for (size_t s = 0; s < num_samples; ++s) {
    const NeighbourhoodMoments moments =
        ComputeNeighbourhoodMoments(points, grid, points[s * stride], radius);
    if (moments.num_neighbors < 6) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(
        moments.covariance, Eigen::EigenvaluesOnly);
    deviations.push_back(std::sqrt(std::max(solver.eigenvalues()(0), 0.0)));
  }
  if (deviations.empty()) return 0;
  std::nth_element(deviations.begin(),
                   deviations.begin() + deviations.size() / 2,
                   deviations.end());
  return deviations[deviations.size() / 2];
}

// A line n . q = offset of the cross-section plane, |n| = 1.
struct SectionLine {
  Eigen::Vector2d normal = Eigen::Vector2d::UnitX();
  double offset = 0;
  double Distance(const Eigen::Vector2d& q) const {
    return std::abs(normal.dot(q) - offset);
  }
};

// The total least-squares line (principal components) of >= 2 points.
SectionLine FitLeastSquares(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& q : points) mean += q;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& q : points) {
    covariance += (q - mean) * (q - mean).transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(covariance);
  SectionLine line;
  line.normal = solver.eigenvectors().col(0).normalized();
  line.offset = line.normal.dot(mean);
  return line;
}

// Intersection of two non-parallel section lines.
Eigen::Vector2d Intersect(const SectionLine& a, const SectionLine& b) {
  Eigen::Matrix2d normals;
  normals.row(0) = a.normal.transpose();
  normals.row(1) = b.normal.transpose();
  return normals.inverse() * Eigen::Vector2d(a.offset, b.offset);
}

// RANSAC of a line through the points with usable[i], then a least-squares
// (principal component) fit to its inliers; inliers (of the refined line,
// among the usable points) in `inliers`. Returns their number.
size_t FitSectionLine(const std::vector<Eigen::Vector2d>& section,
                      const std::vector<char>& usable, double tolerance,
                      int num_iterations, std::mt19937_64* rng,
                      SectionLine* line, std::vector<char>* inliers) {
  std::vector<uint32_t> candidates;
  for (size_t i = 0; i < section.size(); ++i) {
    if (usable[i]) candidates.push_back(static_cast<uint32_t>(i));
  }
  inliers->assign(section.size(), 0);
  if (candidates.size() < 2) return 0;
  std::uniform_int_distribution<size_t> pick(0, candidates.size() - 1);
  size_t best_count = 0;
  SectionLine best;
  for (int iteration = 0; iteration < num_iterations; ++iteration) {
    const Eigen::Vector2d& a = section[candidates[pick(*rng)]];
    const Eigen::Vector2d& b = section[candidates[pick(*rng)]];
    const Eigen::Vector2d direction = b - a;
    const double length = direction.norm();
    if (!(length > 0)) continue;
    SectionLine hypothesis;
    hypothesis.normal = Eigen::Vector2d(-direction.y(), direction.x()) / length;
    hypothesis.offset = hypothesis.normal.dot(a);
    size_t count = 0;
    for (const uint32_t i : candidates) {
      count += hypothesis.Distance(section[i]) < tolerance;
    }
    if (count > best_count) {
      best_count = count;
      best = hypothesis;
    }
  }
  if (best_count < 2) return 0;
  std::vector<Eigen::Vector2d> fit_points;
  for (const uint32_t i : candidates) {
    if (best.Distance(section[i]) < tolerance) fit_points.push_back(section[i]);
  }
  *line = FitLeastSquares(fit_points);
  size_t count = 0;
  for (const uint32_t i : candidates) {
    if (line->Distance(section[i]) < tolerance) {
      (*inliers)[i] = 1;
      ++count;
    }
  }
  return count;
}

// The crease of two faces of a segment's support (Validate): the faces'
// cross-sections in `section` (coordinates along e1 = axis.unitOrthogonal()
// and e2 = axis x e1 relative to `start`) with their inliers. `tolerance`
// is the plane band, `spacing` s, metres.
ValidatedLine ValidatePair(const LineValidationOptions& options, double spacing,
                           double tolerance, const Eigen::Vector3d& start,
                           const Eigen::Vector3d& end,
                           const std::vector<Eigen::Vector2d>& section,
                           SectionLine face1, std::vector<char> inliers1,
                           SectionLine face2, std::vector<char> inliers2) {
  ValidatedLine result;
  result.start = start;
  result.end = end;
  result.status = LineValidationStatus::kOnePlane;
  const Eigen::Vector3d axis = (end - start).normalized();
  const Eigen::Vector3d e1 = axis.unitOrthogonal();
  const Eigen::Vector3d e2 = axis.cross(e1);
  const size_t min_points = static_cast<size_t>(options.min_face_points);
  // Points of face 2 in face 1's band too lie at the crease: neither face's.
  size_t count1 = 0;
  size_t count2 = 0;
  for (size_t i = 0; i < section.size(); ++i) {
    const bool near2 = face2.Distance(section[i]) < tolerance;
    if (inliers1[i] && near2) inliers1[i] = 0;
    count1 += inliers1[i];
    count2 += inliers2[i];
  }
  if (count1 < min_points || count2 < min_points) return result;

  const double max_cos = std::cos(options.min_crease_angle_deg * M_PI / 180.0);
  if (std::abs(face1.normal.dot(face2.normal)) > max_cos) {
    result.status = LineValidationStatus::kParallelFaces;
    return result;
  }
  Eigen::Vector2d corner = Intersect(face1, face2);
  // Near the corner a point is within the band of both faces, and the
  // RANSAC line that gathers most points leans to take some of the other
  // face's (a bias of a quarter of the spacing towards the inside, in a
  // test): refit each face to its points away from the corner.
  const double exclusion = std::max(2.0 * tolerance, spacing);
  for (int round = 0; round < 2; ++round) {
    SectionLine refined[2];
    bool ok = true;
    for (int f = 0; f < 2; ++f) {
      const SectionLine& face = f == 0 ? face1 : face2;
      std::vector<Eigen::Vector2d> far;
      for (const Eigen::Vector2d& q : section) {
        if (face.Distance(q) < tolerance &&
            (q - corner).squaredNorm() > exclusion * exclusion) {
          far.push_back(q);
        }
      }
      if (far.size() < min_points) {
        ok = false;
        break;
      }
      refined[f] = FitLeastSquares(far);
    }
    if (!ok || std::abs(refined[0].normal.dot(refined[1].normal)) > max_cos) {
      break;
    }
    face1 = refined[0];
    face2 = refined[1];
    corner = Intersect(face1, face2);
  }
  // Each face lies on one side of the corner along its cross-section.
  Eigen::Vector2d face_directions[2];
  int face_idx = 0;
  for (const auto& [face, inliers] :
       {std::make_pair(&face1, &inliers1), std::make_pair(&face2, &inliers2)}) {
    const Eigen::Vector2d along(face->normal.y(), -face->normal.x());
    size_t positive = 0;
    size_t total = 0;
    for (size_t i = 0; i < section.size(); ++i) {
      if (!(*inliers)[i]) continue;
      positive += along.dot(section[i] - corner) > 0;
      ++total;
    }
    const double share =
        static_cast<double>(std::max(positive, total - positive)) / total;
    if (share < options.min_side_fraction) {
      result.status = LineValidationStatus::kNotACorner;
      return result;
    }
    face_directions[face_idx++] = 2 * positive > total ? along : -along;
  }
  result.offset_m = corner.norm();
  if (result.offset_m > options.max_offset_factor * spacing) {
    result.status = LineValidationStatus::kOffCrease;
    return result;
  }
  const Eigen::Vector3d shift = corner.x() * e1 + corner.y() * e2;
  result.status = LineValidationStatus::kCrease;
  result.start = start + shift;
  result.end = end + shift;
  for (int f = 0; f < 2; ++f) {
    result.face_directions[f] =
        face_directions[f].x() * e1 + face_directions[f].y() * e2;
  }
  return result;
}

}  // namespace

bool LineValidationOptions::Check() const {
  if (spacing_neighbor < 1) {
    LOG(ERROR) << "Line validation spacing_neighbor must be >= 1";
    return false;
  }
  if (!(plane_tolerance_sigmas >= 0) ||
      !std::isfinite(plane_tolerance_sigmas)) {
    LOG(ERROR) << "Line validation plane_tolerance_sigmas must be >= 0";
    return false;
  }
  if (!(noise_radius_factor > 0) || !std::isfinite(noise_radius_factor)) {
    LOG(ERROR) << "Line validation noise_radius_factor must be > 0";
    return false;
  }
  if (!(support_radius_factor > 0) || !(plane_tolerance_factor > 0) ||
      !(max_offset_factor > 0) || !std::isfinite(support_radius_factor) ||
      !std::isfinite(plane_tolerance_factor) ||
      !std::isfinite(max_offset_factor)) {
    LOG(ERROR) << "Line validation support_radius_factor, "
                  "plane_tolerance_factor and max_offset_factor must be > 0";
    return false;
  }
  if (!(min_crease_angle_deg > 0 && min_crease_angle_deg <= 90)) {
    LOG(ERROR) << "Line validation min_crease_angle_deg must be in (0, 90]";
    return false;
  }
  if (min_face_points < 2) {
    LOG(ERROR) << "Line validation min_face_points must be >= 2";
    return false;
  }
  if (!(min_side_fraction > 0.5 && min_side_fraction <= 1)) {
    LOG(ERROR) << "Line validation min_side_fraction must be in (0.5, 1]";
    return false;
  }
  if (!(max_side_face_offset_factor > 0 &&
        max_side_face_offset_factor <= max_offset_factor)) {
    LOG(ERROR) << "Line validation max_side_face_offset_factor must be in "
                  "(0, max_offset_factor]";
    return false;
  }
  if (max_faces < 2) {
    LOG(ERROR) << "Line validation max_faces must be >= 2";
    return false;
  }
  if (num_ransac_iterations < 1) {
    LOG(ERROR) << "Line validation num_ransac_iterations must be >= 1";
    return false;
  }
  return true;
}

std::string LineValidationStatusName(const LineValidationStatus status) {
  switch (status) {
    case LineValidationStatus::kCrease:
      return "on a crease";
    case LineValidationStatus::kFewPoints:
      return "few points";
    case LineValidationStatus::kOnePlane:
      return "one face";
    case LineValidationStatus::kParallelFaces:
      return "parallel faces";
    case LineValidationStatus::kNotACorner:
      return "faces crossing";
    case LineValidationStatus::kOffCrease:
      return "off the crease";
  }
  return "unknown";
}

LineValidator::LineValidator(const LineValidationOptions& options,
                             const std::vector<Eigen::Vector3d>& points)
    : options_(options), points_(points) {
  THROW_CHECK(options_.Check(), "Invalid line validation options");
  THROW_CHECK(points_.size() > static_cast<size_t>(options_.spacing_neighbor),
              "Line validation needs more than "
                  << options_.spacing_neighbor << " points, got "
                  << points_.size());
  spacing_ = EstimateSpacing(points_, options_.spacing_neighbor);
  // Coincident points give a spacing of 0: a floor of 0.1 mm keeps the
  // support radius and the grid's cells finite.
  spacing_ = std::max(spacing_, kMinSpacing);
  grid_ = std::make_unique<RadiusGrid>(
      points_, options_.support_radius_factor * spacing_);
  const double noise_radius = options_.noise_radius_factor * spacing_;
  if (options_.plane_tolerance_sigmas > 0) {
    noise_ = noise_radius <= options_.support_radius_factor * spacing_
                 ? EstimateNoise(points_, *grid_, noise_radius)
                 : EstimateNoise(points_, RadiusGrid(points_, noise_radius),
                                 noise_radius);
  }
  plane_tolerance_ = std::max(options_.plane_tolerance_factor * spacing_,
                              options_.plane_tolerance_sigmas * noise_);
}

ValidatedLine LineValidator::Validate(const Eigen::Vector3d& start,
                                      const Eigen::Vector3d& end,
                                      const uint64_t seed) const {
  ValidatedLine result;
  result.start = start;
  result.end = end;
  const double length = (end - start).norm();
  if (!(length > 0)) return result;
  const Eigen::Vector3d axis = (end - start) / length;
  const Eigen::Vector3d e1 = axis.unitOrthogonal();
  const Eigen::Vector3d e2 = axis.cross(e1);
  const double radius = options_.support_radius_factor * spacing_;
  const double tolerance = plane_tolerance_;

  // The support's cross-section: coordinates in the plane orthogonal to
  // the segment, relative to it.
  std::vector<Eigen::Vector2d> section;
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(radius);
  grid_->ForEachInBox(
      start.cwiseMin(end) - margin, start.cwiseMax(end) + margin,
      [&](uint32_t i) {
        const Eigen::Vector3d p = points_[i] - start;
        const double t = p.dot(axis);
        if (t < 0 || t > length) return;
        const Eigen::Vector2d q(p.dot(e1), p.dot(e2));
        if (q.squaredNorm() <= radius * radius) section.push_back(q);
      });
  const size_t min_points = static_cast<size_t>(options_.min_face_points);
  if (section.size() < 2 * min_points) return result;

  std::mt19937_64 rng(seed);
  // Faces by sequential RANSAC, largest first. A step (a door frame, a
  // recess's lip) shows two large parallel faces and, between them, a
  // smaller side face that meets one of them at the segment: when the two
  // largest faces make no crease, up to max_faces faces are fitted and the
  // pairs with the smaller ones are tried.
  std::vector<SectionLine> faces;
  std::vector<std::vector<char>> face_inliers;
  std::vector<char> usable(section.size(), 1);
  const auto fit_next_face = [&]() {
    SectionLine face;
    std::vector<char> inliers;
    if (FitSectionLine(section, usable, tolerance,
                       options_.num_ransac_iterations, &rng, &face,
                       &inliers) < min_points) {
      return false;
    }
    for (size_t i = 0; i < section.size(); ++i) {
      if (inliers[i]) usable[i] = 0;
    }
    faces.push_back(face);
    face_inliers.push_back(std::move(inliers));
    return true;
  };
  result.status = LineValidationStatus::kOnePlane;
  if (!fit_next_face() || !fit_next_face()) return result;

  // The two largest faces first: where they make a crease it is kept (the
  // most supported fit), and their refusal is the one reported. Else a
  // pair with a smaller face may make a crease, the one nearest the
  // segment, when the segment lies at it already (max_side_face_offset):
  // the smallest face's direction is the least certain, and so is its
  // crease's position.
  ValidatedLine best =
      ValidatePair(options_, spacing_, tolerance, start, end, section, faces[0],
                   face_inliers[0], faces[1], face_inliers[1]);
  if (best.status == LineValidationStatus::kCrease) return best;
  while (static_cast<int>(faces.size()) < options_.max_faces &&
         fit_next_face()) {
  }
  double best_offset = std::numeric_limits<double>::infinity();
  const double max_side_face_offset =
      options_.max_side_face_offset_factor * spacing_;
  for (size_t a = 0; a < faces.size(); ++a) {
    for (size_t b = std::max(a + 1, size_t{2}); b < faces.size(); ++b) {
      const ValidatedLine pair =
          ValidatePair(options_, spacing_, tolerance, start, end, section,
                       faces[a], face_inliers[a], faces[b], face_inliers[b]);
      if (pair.status == LineValidationStatus::kCrease &&
          pair.offset_m <= max_side_face_offset &&
          pair.offset_m < best_offset) {
        best_offset = pair.offset_m;
        best = pair;
        best.with_side_face = true;
      }
    }
  }
  return best;
}

}  // namespace colmap_lidar
