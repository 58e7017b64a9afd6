#include "src/sfm/pose_guided_matching.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/parallel.h"
#include "src/lidar/scan_io.h"
#include "src/sfm/exact_feature_matcher.h"

namespace colmap_lidar {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Depths of the search without a LIDAR depth (the agreement test), metres.
constexpr double kMinSearchDepthM = 0.5;
constexpr double kMaxSearchDepthM = 1e4;
// A projection needs this much depth in the target camera, metres.
constexpr double kMinTargetDepthM = 0.05;

double DescriptorDistance(const FeatureDescriptorsBlob& d1, int row1,
                          const FeatureDescriptorsBlob& d2, int row2) {
  int dot = 0;
  const uint8_t* a = d1.data() + static_cast<size_t>(row1) * d1.cols();
  const uint8_t* b = d2.data() + static_cast<size_t>(row2) * d2.cols();
  for (int k = 0; k < d1.cols(); ++k) dot += int(a[k]) * int(b[k]);
  return DotToDistance(static_cast<float>(dot));
}

// Points (x, y) in a uniform grid of square cells over their bounding box.
class PointGrid {
 public:
  // Non-finite points are left out. The cell grows when the box would
  // need more than kMaxCells cells (a very wide camera).
  PointGrid(const std::vector<Eigen::Vector2d>& points, double cell)
      : points_(points), cell_(cell) {
    bool any = false;
    for (const Eigen::Vector2d& p : points) {
      if (!p.allFinite()) continue;
      min_ = any ? min_.cwiseMin(p) : p;
      max_ = any ? max_.cwiseMax(p) : p;
      any = true;
    }
    if (!any) return;
    constexpr double kMaxCells = 1 << 22;
    const Eigen::Vector2d extent = max_ - min_;
    cell_ = std::max(cell_, std::sqrt(extent.x() * extent.y() / kMaxCells));
    cell_ = std::max(cell_, std::max(extent.x(), extent.y()) / kMaxCells);
    nx_ = static_cast<int>(extent.x() / cell_) + 1;
    ny_ = static_cast<int>(extent.y() / cell_) + 1;
    starts_.assign(static_cast<size_t>(nx_) * ny_ + 1, 0);
    std::vector<int> cells(points.size(), -1);
    for (size_t i = 0; i < points.size(); ++i) {
      if (!points[i].allFinite()) continue;
      cells[i] = CellIndex(CellX(points[i].x()), CellY(points[i].y()));
      ++starts_[cells[i] + 1];
    }
    for (size_t c = 1; c < starts_.size(); ++c) starts_[c] += starts_[c - 1];
    order_.resize(starts_.back());
    std::vector<int> fill(starts_.begin(), starts_.end() - 1);
    for (size_t i = 0; i < points.size(); ++i) {
      if (cells[i] >= 0) order_[fill[cells[i]]++] = static_cast<int>(i);
    }
  }

  bool empty() const { return nx_ == 0; }
  const Eigen::Vector2d& min() const { return min_; }
  const Eigen::Vector2d& max() const { return max_; }
  double cell() const { return cell_; }

  // Calls visit(index) for the points of the cells within `radius` cells
  // of the cell holding p (each cell once per call).
  template <typename Visit>
  void VisitAround(const Eigen::Vector2d& p, int radius, Visit visit) const {
    if (empty() || !p.allFinite()) return;
    const int cx = CellX(p.x());
    const int cy = CellY(p.y());
    for (int y = std::max(0, cy - radius); y <= std::min(ny_ - 1, cy + radius);
         ++y) {
      for (int x = std::max(0, cx - radius);
           x <= std::min(nx_ - 1, cx + radius); ++x) {
        const int c = CellIndex(x, y);
        for (int k = starts_[c]; k < starts_[c + 1]; ++k) visit(order_[k]);
      }
    }
  }

 private:
  int CellX(double x) const {
    return std::clamp(static_cast<int>(std::floor((x - min_.x()) / cell_)), 0,
                      nx_ - 1);
  }
  int CellY(double y) const {
    return std::clamp(static_cast<int>(std::floor((y - min_.y()) / cell_)), 0,
                      ny_ - 1);
  }
  int CellIndex(int x, int y) const { return y * nx_ + x; }

  const std::vector<Eigen::Vector2d>& points_;
  double cell_;
  Eigen::Vector2d min_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d max_ = Eigen::Vector2d::Zero();
  int nx_ = 0;
  int ny_ = 0;
  std::vector<int> starts_;
  std::vector<int> order_;
};

// Clips the segment p0 + s (p1 - p0), s in [0, 1], to the box [lo, hi]
// (Liang-Barsky); false when nothing is left.
bool ClipSegment(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                 Eigen::Vector2d* p0, Eigen::Vector2d* p1) {
  const Eigen::Vector2d d = *p1 - *p0;
  double s0 = 0.0;
  double s1 = 1.0;
  for (int axis = 0; axis < 2; ++axis) {
    const double p[2] = {-d[axis], d[axis]};
    const double q[2] = {(*p0)[axis] - lo[axis], hi[axis] - (*p0)[axis]};
    for (int k = 0; k < 2; ++k) {
      if (p[k] == 0.0) {
        if (q[k] < 0.0) return false;
      } else {
        const double r = q[k] / p[k];
        if (p[k] < 0.0) {
          s0 = std::max(s0, r);
        } else {
          s1 = std::min(s1, r);
        }
      }
    }
  }
  if (s0 > s1) return false;
  const Eigen::Vector2d start = *p0 + s0 * d;
  *p1 = *p0 + s1 * d;
  *p0 = start;
  return true;
}

double PointSegmentDistance(const Eigen::Vector2d& x, const Eigen::Vector2d& a,
                            const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length_squared = ab.squaredNorm();
  const double s = length_squared > 0.0
                       ? std::clamp((x - a).dot(ab) / length_squared, 0.0, 1.0)
                       : 0.0;
  return (a + s * ab - x).norm();
}

// The keypoints' scales (pixels): column 2 of (x, y, scale, orientation),
// the square root of the affine shape's determinant of (x, y, a11, a12,
// a21, a22); empty for (x, y) or a non-positive scale.
std::vector<double> KeypointScales(const FeatureKeypointsBlob& keypoints) {
  std::vector<double> scales;
  if (keypoints.cols() != 4 && keypoints.cols() != 6) return scales;
  scales.resize(keypoints.rows());
  for (int i = 0; i < keypoints.rows(); ++i) {
    scales[i] = keypoints.cols() == 4
                    ? keypoints(i, 2)
                    : std::sqrt(std::abs(double(keypoints(i, 2)) * keypoints(i, 5) -
                                         double(keypoints(i, 3)) * keypoints(i, 4)));
    if (!(scales[i] > 0.0)) return {};
  }
  return scales;
}

// Normalised image coordinates of an image's keypoints.
std::vector<Eigen::Vector2d> NormalizedKeypoints(const GuidedMatchingImage& image) {
  std::vector<Eigen::Vector2d> points(image.keypoints.rows());
  for (int i = 0; i < image.keypoints.rows(); ++i) {
    points[i] = image.camera.CamFromImg(
        image.keypoints.row(i).head<2>().cast<double>());
  }
  return points;
}

// The projection into the target of a source ray between two depths, with
// its tolerance; false when no part lies in front of the target.
struct ProjectedRay {
  Eigen::Vector2d start;
  Eigen::Vector2d end;
  double tolerance = 0.0;  // normalised target units
};

bool ProjectRay(const Rigid3d& target_from_source, const Eigen::Vector2d& ray,
                double min_depth, double max_depth, double target_focal,
                const PoseGuidedMatchingOptions& options,
                ProjectedRay* projected) {
  const Eigen::Vector3d direction =
      target_from_source.rotation * ray.homogeneous();
  const Eigen::Vector3d& offset = target_from_source.translation;
  // Target depth z(d) = d direction.z + offset.z >= kMinTargetDepthM.
  if (direction.z() > 0.0) {
    min_depth = std::max(min_depth,
                         (kMinTargetDepthM - offset.z()) / direction.z());
  } else if (direction.z() < 0.0) {
    max_depth = std::min(max_depth,
                         (kMinTargetDepthM - offset.z()) / direction.z());
  } else if (offset.z() < kMinTargetDepthM) {
    return false;
  }
  if (!(min_depth < max_depth) || max_depth <= 0.0) return false;
  min_depth = std::max(min_depth, 1e-3);
  const Eigen::Vector3d near = min_depth * direction + offset;
  const Eigen::Vector3d far = max_depth * direction + offset;
  projected->start = near.hnormalized();
  projected->end = far.hnormalized();
  const double pose_px = options.num_pose_sigmas * target_focal *
                         (options.pose_sigma_m / min_depth +
                          options.pose_sigma_deg * kPi / 180.0);
  projected->tolerance = (options.max_error_px + pose_px) / target_focal;
  return true;
}

// z-depth in the target of the point where the source ray through
// `source_point` and the target ray through `target_point` pass closest
// (the middle of their common perpendicular); negative when the rays are
// parallel.
double TargetDepthOfMatch(const Rigid3d& target_from_source,
                          const Eigen::Vector2d& source_point,
                          const Eigen::Vector2d& target_point,
                          double* source_depth) {
  // o + l u = m v, least squares in (l, m); v has z = 1, so m is the depth.
  const Eigen::Vector3d u =
      target_from_source.rotation * source_point.homogeneous();
  const Eigen::Vector3d v = target_point.homogeneous();
  const Eigen::Vector3d& o = target_from_source.translation;
  const double uu = u.dot(u);
  const double uv = u.dot(v);
  const double vv = v.dot(v);
  const double determinant = uu * vv - uv * uv;
  *source_depth = -1.0;
  if (!(determinant > 1e-12 * uu * vv)) return -1.0;
  const double l = (uv * v.dot(o) - vv * u.dot(o)) / determinant;
  const double m = (uu * v.dot(o) - uv * u.dot(o)) / determinant;
  *source_depth = l;
  return 0.5 * (m + (o + l * u).z());
}

}  // namespace

bool PoseGuidedMatchingOptions::Check() const {
  bool ok = true;
  auto check = [&ok](bool condition, const char* what) {
    if (!condition) {
      LOG(ERROR) << "PoseGuidedMatching." << what;
      ok = false;
    }
  };
  check(num_nearest_images >= 0, "num_nearest_images must be >= 0");
  check(num_depth_neighbors >= 1, "num_depth_neighbors must be >= 1");
  check(max_depth_neighbor_angle_deg > 0.0 &&
            max_depth_neighbor_angle_deg < 90.0,
        "max_depth_neighbor_angle_deg must be in (0, 90)");
  check(depth_margin >= 0.0 && std::isfinite(depth_margin),
        "depth_margin must be >= 0");
  check(max_error_px > 0.0 && std::isfinite(max_error_px),
        "max_error_px must be > 0");
  check(pose_sigma_m >= 0.0 && std::isfinite(pose_sigma_m),
        "pose_sigma_m must be >= 0");
  check(pose_sigma_deg >= 0.0 && std::isfinite(pose_sigma_deg),
        "pose_sigma_deg must be >= 0");
  check(num_pose_sigmas > 0.0 && std::isfinite(num_pose_sigmas),
        "num_pose_sigmas must be > 0");
  check(max_scale_ratio == 0.0 || max_scale_ratio >= 1.0,
        "max_scale_ratio must be 0 or >= 1");
  check(max_ratio > 0.0 && max_ratio <= 1.0, "max_ratio must be in (0, 1]");
  check(max_distance > 0.0 && max_distance <= kPi,
        "max_distance must be in (0, pi]");
  check(min_num_matches >= 1, "min_num_matches must be >= 1");
  check(min_agreement >= 0.0 && min_agreement <= 1.0,
        "min_agreement must be in [0, 1]");
  return ok;
}

std::string PoseGuidedMatchingSummary::ToString() const {
  std::ostringstream out;
  out << num_pairs << " pairs, " << num_pairs_gained << " gained "
      << num_added << " matches (" << num_verified_before
      << " verified before), " << num_pairs_disagreeing
      << " left as they were (their matches disagree with the poses), "
      << seconds << " s";
  return out.str();
}

std::vector<KeypointDepth> KeypointDepthIntervals(
    const Camera& camera, const FeatureKeypointsBlob& keypoints,
    const std::vector<Eigen::Vector3f>& points_in_cam,
    const PoseGuidedMatchingOptions& options) {
  std::vector<KeypointDepth> depths(keypoints.rows());
  // The scan in the image: pixel and depth of each point in front.
  std::vector<Eigen::Vector2d> pixels;
  std::vector<float> point_depths;
  pixels.reserve(points_in_cam.size());
  point_depths.reserve(points_in_cam.size());
  for (const Eigen::Vector3f& point : points_in_cam) {
    if (!(point.z() > 0.1f) || !point.allFinite()) continue;
    const Eigen::Vector2d pixel = camera.ImgFromCam(point.cast<double>());
    if (pixel.x() < 0.0 || pixel.y() < 0.0 ||
        pixel.x() > static_cast<double>(camera.width) ||
        pixel.y() > static_cast<double>(camera.height)) {
      continue;
    }
    pixels.push_back(pixel);
    point_depths.push_back(point.z());
  }
  if (pixels.empty()) return depths;
  const double radius_px =
      camera.MeanFocalLength() *
      std::tan(options.max_depth_neighbor_angle_deg * kPi / 180.0);
  const double cell = std::max(4.0, radius_px / 4.0);
  const PointGrid grid(pixels, cell);
  const int cell_radius = static_cast<int>(std::ceil(radius_px / cell));
  const size_t k = static_cast<size_t>(options.num_depth_neighbors);
  std::vector<std::pair<double, float>> near;  // (squared px distance, depth)
  for (int i = 0; i < keypoints.rows(); ++i) {
    const Eigen::Vector2d pixel = keypoints.row(i).head<2>().cast<double>();
    near.clear();
    grid.VisitAround(pixel, cell_radius, [&](int p) {
      const double d2 = (pixels[p] - pixel).squaredNorm();
      if (d2 <= radius_px * radius_px) near.emplace_back(d2, point_depths[p]);
    });
    if (near.size() < k) continue;
    std::partial_sort(near.begin(), near.begin() + k, near.end());
    float lo = near[0].second;
    float hi = near[0].second;
    for (size_t n = 1; n < k; ++n) {
      lo = std::min(lo, near[n].second);
      hi = std::max(hi, near[n].second);
    }
    depths[i].min_depth = static_cast<float>(lo * (1.0 - options.depth_margin));
    depths[i].max_depth = static_cast<float>(hi * (1.0 + options.depth_margin));
  }
  return depths;
}

FeatureMatchesBlob GuidedMatchesOneWay(const GuidedMatchingImage& source,
                                       const GuidedMatchingImage& target,
                                       const PoseGuidedMatchingOptions& options) {
  const int num_source = static_cast<int>(source.keypoints.rows());
  const int num_target = static_cast<int>(target.keypoints.rows());
  if (num_source == 0 || num_target == 0) return FeatureMatchesBlob(0, 2);
  THROW_CHECK(source.descriptors.rows() == num_source &&
                  target.descriptors.rows() == num_target &&
                  source.descriptors.cols() == target.descriptors.cols() &&
                  static_cast<int>(source.depths.size()) == num_source &&
                  static_cast<int>(target.depths.size()) == num_target,
              "guided matching: keypoints, descriptors and depths disagree");
  const std::vector<Eigen::Vector2d> source_points =
      NormalizedKeypoints(source);
  const std::vector<Eigen::Vector2d> target_points =
      NormalizedKeypoints(target);
  const double target_focal = target.camera.MeanFocalLength();
  const double source_focal = source.camera.MeanFocalLength();
  const std::vector<double> source_scales = KeypointScales(source.keypoints);
  const std::vector<double> target_scales = KeypointScales(target.keypoints);
  const bool check_scales = !source_scales.empty() && !target_scales.empty() &&
                            options.max_scale_ratio > 0.0;
  const double max_log_scale_ratio =
      check_scales ? std::log(options.max_scale_ratio) : 0.0;
  const PointGrid grid(target_points, 2.0 * options.max_error_px / target_focal);
  const Rigid3d target_from_source =
      target.cam_from_world * source.cam_from_world.Inverse();

  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<int> best_target(num_source, -1);
  // Per target keypoint: the source keypoint of smallest distance among
  // those that took it as a candidate.
  std::vector<int> best_source(num_target, -1);
  std::vector<double> best_source_distance(num_target, kInf);
  std::vector<int> stamp(num_target, -1);
  for (int a = 0; a < num_source; ++a) {
    const KeypointDepth& depth = source.depths[a];
    if (!(depth.max_depth > 0.0f)) continue;
    ProjectedRay ray;
    if (!ProjectRay(target_from_source, source_points[a], depth.min_depth,
                    depth.max_depth, target_focal, options, &ray)) {
      continue;
    }
    Eigen::Vector2d start = ray.start;
    Eigen::Vector2d end = ray.end;
    const Eigen::Vector2d margin = Eigen::Vector2d::Constant(ray.tolerance);
    if (!ClipSegment(grid.min() - margin, grid.max() + margin, &start, &end)) {
      continue;
    }
    const int cell_radius =
        static_cast<int>(std::ceil(ray.tolerance / grid.cell()));
    const double step = 0.5 * grid.cell();
    const int num_steps =
        1 + static_cast<int>(std::ceil((end - start).norm() / step));
    double best = kInf;
    double second = kInf;
    int best_b = -1;
    for (int s = 0; s <= num_steps; ++s) {
      const Eigen::Vector2d sample =
          start + (end - start) * (static_cast<double>(s) / num_steps);
      grid.VisitAround(sample, cell_radius, [&](int b) {
        if (stamp[b] == a) return;
        stamp[b] = a;
        if (PointSegmentDistance(target_points[b], ray.start, ray.end) >
            ray.tolerance) {
          return;
        }
        // A target keypoint with a LIDAR depth of its own must see the
        // match at that depth (not a surface in front of or behind it).
        double source_z = -1.0;
        const double target_z = TargetDepthOfMatch(
            target_from_source, source_points[a], target_points[b], &source_z);
        const KeypointDepth& target_depth = target.depths[b];
        if (target_depth.max_depth > 0.0f &&
            (target_z < target_depth.min_depth ||
             target_z > target_depth.max_depth)) {
          return;
        }
        // The features' scales must agree with the depths: a patch at
        // depth z appears at a scale proportional to f / z.
        if (check_scales && source_z > 0.0 && target_z > 0.0) {
          const double predicted = std::log(target_focal * source_z /
                                            (source_focal * target_z));
          const double observed = std::log(target_scales[b] / source_scales[a]);
          if (std::abs(observed - predicted) > max_log_scale_ratio) return;
        }
        const double distance =
            DescriptorDistance(source.descriptors, a, target.descriptors, b);
        if (distance < best_source_distance[b]) {
          best_source_distance[b] = distance;
          best_source[b] = a;
        }
        if (distance < best) {
          second = best;
          best = distance;
          best_b = b;
        } else if (distance < second) {
          second = distance;
        }
      });
    }
    if (best_b < 0 || best > options.max_distance) continue;
    if (best >= options.max_ratio * std::min(second, options.max_distance)) {
      continue;
    }
    best_target[a] = best_b;
  }
  std::vector<std::pair<int, int>> kept;
  for (int a = 0; a < num_source; ++a) {
    const int b = best_target[a];
    if (b >= 0 && best_source[b] == a) kept.emplace_back(a, b);
  }
  FeatureMatchesBlob matches(kept.size(), 2);
  for (size_t m = 0; m < kept.size(); ++m) {
    matches(m, 0) = static_cast<point2D_t>(kept[m].first);
    matches(m, 1) = static_cast<point2D_t>(kept[m].second);
  }
  return matches;
}

double EpipolarAgreement(const GuidedMatchingImage& image1,
                         const GuidedMatchingImage& image2,
                         const FeatureMatchesBlob& matches,
                         const PoseGuidedMatchingOptions& options) {
  if (matches.rows() == 0) return 0.0;
  const Rigid3d cam2_from_cam1 =
      image2.cam_from_world * image1.cam_from_world.Inverse();
  const double focal2 = image2.camera.MeanFocalLength();
  int num_agreeing = 0;
  for (int m = 0; m < matches.rows(); ++m) {
    const Eigen::Vector2d x1 = image1.camera.CamFromImg(
        image1.keypoints.row(matches(m, 0)).head<2>().cast<double>());
    const Eigen::Vector2d x2 = image2.camera.CamFromImg(
        image2.keypoints.row(matches(m, 1)).head<2>().cast<double>());
    ProjectedRay ray;
    if (ProjectRay(cam2_from_cam1, x1, kMinSearchDepthM, kMaxSearchDepthM,
                   focal2, options, &ray) &&
        PointSegmentDistance(x2, ray.start, ray.end) <= ray.tolerance) {
      ++num_agreeing;
    }
  }
  return static_cast<double>(num_agreeing) / matches.rows();
}

std::vector<std::pair<image_t, image_t>> NearestImagePairs(
    const Reconstruction& model,
    const std::vector<std::pair<image_t, image_t>>& pairs,
    int num_nearest_images) {
  if (num_nearest_images <= 0) return pairs;
  // Per image, its pairs by the distance of the two camera centres (ties by
  // id, so that the choice does not depend on the input order).
  std::map<image_t, std::vector<std::pair<double, image_t>>> by_distance;
  for (const auto& [id1, id2] : pairs) {
    const Image* image1 = model.FindImage(id1);
    const Image* image2 = model.FindImage(id2);
    if (image1 == nullptr || image2 == nullptr) continue;
    const double distance =
        (image1->ProjectionCenter() - image2->ProjectionCenter()).norm();
    by_distance[id1].emplace_back(distance, id2);
    by_distance[id2].emplace_back(distance, id1);
  }
  std::set<std::pair<image_t, image_t>> kept;
  for (auto& [id, others] : by_distance) {
    std::sort(others.begin(), others.end());
    const size_t count =
        std::min(others.size(), static_cast<size_t>(num_nearest_images));
    for (size_t n = 0; n < count; ++n) {
      kept.emplace(std::min(id, others[n].second),
                   std::max(id, others[n].second));
    }
  }
  std::vector<std::pair<image_t, image_t>> nearest;
  for (const auto& pair : pairs) {
    if (kept.count({std::min(pair.first, pair.second),
                    std::max(pair.first, pair.second)}) > 0) {
      nearest.push_back(pair);
    }
  }
  return nearest;
}

PoseGuidedMatchingSummary RunPoseGuidedMatching(
    const std::string& database_path,
    const Reconstruction& model, const std::unordered_set<image_t>& trusted,
    const std::vector<std::pair<image_t, image_t>>& pairs,
    const PoseGuidedMatchingOptions& options,
    const std::string& output_database_path) {
  THROW_CHECK(options.Check(), "invalid PoseGuidedMatching options");
  const auto start = std::chrono::steady_clock::now();
  PoseGuidedMatchingSummary summary;
  std::vector<std::pair<image_t, image_t>> todo;
  for (const auto& pair : pairs) {
    if (trusted.count(pair.first) > 0 && trusted.count(pair.second) > 0 &&
        model.FindImage(pair.first) != nullptr &&
        model.FindImage(pair.second) != nullptr) {
      todo.push_back(pair);
    }
  }
  todo = NearestImagePairs(model, todo, options.num_nearest_images);
  std::vector<image_t> image_ids;
  for (const auto& [id1, id2] : todo) {
    image_ids.push_back(id1);
    image_ids.push_back(id2);
  }
  std::sort(image_ids.begin(), image_ids.end());
  image_ids.erase(std::unique(image_ids.begin(), image_ids.end()),
                  image_ids.end());

  // Inputs, read on this thread (one database connection).
  std::map<image_t, GuidedMatchingImage> images;
  std::vector<std::vector<Eigen::Vector3f>> scans(image_ids.size());
  std::vector<std::optional<TwoViewGeometry>> geometries(todo.size());
  {
    const Database database(database_path);
    for (size_t n = 0; n < image_ids.size(); ++n) {
      const image_t id = image_ids[n];
      const Image& image = *model.FindImage(id);
      const auto camera = model.cameras.find(image.camera_id);
      THROW_CHECK(camera != model.cameras.end(),
                  "guided matching: image " << image.name << " has no camera");
      GuidedMatchingImage& entry = images[id];
      entry.camera = camera->second;
      entry.cam_from_world = image.cam_from_world;
      entry.keypoints = database.ReadKeypoints(id);
      entry.descriptors = database.ReadDescriptors(id);
      THROW_CHECK(entry.keypoints.rows() == entry.descriptors.rows() &&
                      (entry.keypoints.rows() == 0 ||
                       entry.keypoints.cols() >= 2),
                  "guided matching: image " << image.name << " of "
                                            << database_path << " has "
                                            << entry.keypoints.rows()
                                            << " keypoints and "
                                            << entry.descriptors.rows()
                                            << " descriptors");
      const std::optional<LidarScanRecord> record = database.ReadLidarScan(id);
      if (!record) continue;
      const LidarScan scan =
          ReadLidarScan(LidarScanFilePath(database_path, record->path));
      const Eigen::Matrix3f rotation =
          record->cam_from_lidar.rotation.toRotationMatrix().cast<float>();
      const Eigen::Vector3f translation =
          record->cam_from_lidar.translation.cast<float>();
      scans[n].reserve(scan.size());
      for (const Eigen::Vector3f& point : scan.points) {
        scans[n].push_back(rotation * point + translation);
      }
    }
    for (size_t p = 0; p < todo.size(); ++p) {
      geometries[p] = database.ReadTwoViewGeometry(todo[p].first, todo[p].second);
    }
  }
  ParallelFor(0, static_cast<int>(image_ids.size()), options.num_threads,
              [&](int n) {
                GuidedMatchingImage& image = images.at(image_ids[n]);
                image.depths = KeypointDepthIntervals(
                    image.camera, image.keypoints, scans[n], options);
                std::vector<Eigen::Vector3f>().swap(scans[n]);
              });

  // Per pair: the merged geometry, or nothing when the pair stays as it is.
  struct PairOutcome {
    bool disagrees = false;
    size_t verified_before = 0;
    size_t added = 0;
    TwoViewGeometry geometry;
  };
  std::vector<PairOutcome> outcomes(todo.size());
  ParallelFor(0, static_cast<int>(todo.size()), options.num_threads,
              [&](int p) {
    const GuidedMatchingImage& image1 = images.at(todo[p].first);
    const GuidedMatchingImage& image2 = images.at(todo[p].second);
    PairOutcome& outcome = outcomes[p];
    const bool has_geometry =
        geometries[p].has_value() && geometries[p]->inlier_matches.rows() > 0;
    const FeatureMatchesBlob verified =
        has_geometry ? geometries[p]->inlier_matches : FeatureMatchesBlob(0, 2);
    outcome.verified_before = verified.rows();
    if (verified.rows() >= options.min_num_matches &&
        EpipolarAgreement(image1, image2, verified, options) <
            options.min_agreement) {
      outcome.disagrees = true;
      return;
    }
    const FeatureMatchesBlob forward =
        GuidedMatchesOneWay(image1, image2, options);
    const FeatureMatchesBlob backward =
        GuidedMatchesOneWay(image2, image1, options);
    std::vector<char> used1(image1.keypoints.rows(), 0);
    std::vector<char> used2(image2.keypoints.rows(), 0);
    std::vector<std::pair<point2D_t, point2D_t>> merged;
    for (int m = 0; m < verified.rows(); ++m) {
      merged.emplace_back(verified(m, 0), verified(m, 1));
      used1[verified(m, 0)] = 1;
      used2[verified(m, 1)] = 1;
    }
    size_t added = 0;
    auto add = [&](point2D_t i1, point2D_t i2) {
      if (used1[i1] || used2[i2]) return;
      used1[i1] = used2[i2] = 1;
      merged.emplace_back(i1, i2);
      ++added;
    };
    for (int m = 0; m < forward.rows(); ++m) add(forward(m, 0), forward(m, 1));
    for (int m = 0; m < backward.rows(); ++m) {
      add(backward(m, 1), backward(m, 0));
    }
    if (added < static_cast<size_t>(options.min_num_matches)) return;
    outcome.added = added;
    outcome.geometry = has_geometry ? *geometries[p] : TwoViewGeometry();
    outcome.geometry.inlier_matches.resize(merged.size(), 2);
    for (size_t m = 0; m < merged.size(); ++m) {
      outcome.geometry.inlier_matches(m, 0) = merged[m].first;
      outcome.geometry.inlier_matches(m, 1) = merged[m].second;
    }
    if (!has_geometry ||
        outcome.geometry.config != TwoViewGeometryConfig::kCalibrated) {
      // E = [t]x R of cam2_from_cam1; F = K2^-T E K1^-1.
      const Rigid3d cam2_from_cam1 =
          image2.cam_from_world * image1.cam_from_world.Inverse();
      const Eigen::Vector3d& t = cam2_from_cam1.translation;
      Eigen::Matrix3d t_cross;
      t_cross << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
      outcome.geometry.E =
          t_cross * cam2_from_cam1.rotation.toRotationMatrix();
      outcome.geometry.F =
          image2.camera.CalibrationMatrix().inverse().transpose() *
          outcome.geometry.E * image1.camera.CalibrationMatrix().inverse();
      outcome.geometry.config = TwoViewGeometryConfig::kCalibrated;
    }
  });

  // The triangulation database: the tables the triangulator reads, then the
  // gained pairs' geometries.
  for (const char* suffix : {"", "-wal", "-shm", "-journal"}) {
    std::filesystem::remove(output_database_path + suffix);
  }
  {
    Database output(output_database_path);
    std::string source = database_path;
    for (size_t at = source.find('\''); at != std::string::npos;
         at = source.find('\'', at + 2)) {
      source.insert(at, 1, '\'');
    }
    output.Execute("ATTACH DATABASE '" + source + "' AS source;");
    {
      DatabaseTransaction transaction(&output);
      output.Execute(
          "INSERT INTO cameras SELECT * FROM source.cameras;"
          "INSERT INTO images SELECT * FROM source.images;"
          "INSERT INTO keypoints SELECT * FROM source.keypoints;"
          "INSERT INTO two_view_geometries SELECT * FROM "
          "source.two_view_geometries;");
      transaction.Commit();
    }
    output.Execute("DETACH DATABASE source;");
    DatabaseTransaction transaction(&output);
    for (size_t p = 0; p < todo.size(); ++p) {
      const PairOutcome& outcome = outcomes[p];
      ++summary.num_pairs;
      summary.num_verified_before += outcome.verified_before;
      if (outcome.disagrees) ++summary.num_pairs_disagreeing;
      if (outcome.added == 0) continue;
      ++summary.num_pairs_gained;
      summary.num_added += outcome.added;
      const auto [id1, id2] = todo[p];
      if (output.ExistsTwoViewGeometry(id1, id2)) {
        output.DeleteTwoViewGeometry(id1, id2);
      }
      output.WriteTwoViewGeometry(id1, id2, outcome.geometry);
    }
    transaction.Commit();
  }
  summary.seconds = std::chrono::duration<double>(
                        std::chrono::steady_clock::now() - start)
                        .count();
  return summary;
}

}  // namespace colmap_lidar
