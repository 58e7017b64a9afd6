#include "src/sfm/exact_feature_matcher.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>

#include <Eigen/Core>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/parallel.h"
#include "src/sfm/descriptor_dots.h"

namespace colmap_lidar {
namespace {

// Rows of image 1 per block of the dot-product matrix (memory: block x n2
// floats).
constexpr int kRowBlock = 512;

struct ImageFeatures {
  DatabaseImage image;
  Camera camera;
  FeatureKeypointsBlob keypoints;
  FeatureDescriptorsBlob descriptors;
};

struct PairResult {
  FeatureMatchesBlob matches;
  TwoViewGeometry geometry;
  bool verified = false;
};

// Essential matrix by RANSAC on undistorted keypoints; see the header.
TwoViewGeometry Verify(const ImageFeatures& features1,
                       const ImageFeatures& features2,
                       const FeatureMatchesBlob& matches,
                       const ExactMatchingOptions& options, bool* verified) {
  TwoViewGeometry geometry;
  geometry.config = TwoViewGeometryConfig::kDegenerate;
  *verified = false;
  const int num_matches = static_cast<int>(matches.rows());
  if (num_matches < options.min_num_inliers) return geometry;
  std::vector<cv::Point2d> points1(num_matches);
  std::vector<cv::Point2d> points2(num_matches);
  for (int i = 0; i < num_matches; ++i) {
    const Eigen::Vector2d x1 = features1.camera.CamFromImg(
        features1.keypoints.row(matches(i, 0)).head<2>().cast<double>());
    const Eigen::Vector2d x2 = features2.camera.CamFromImg(
        features2.keypoints.row(matches(i, 1)).head<2>().cast<double>());
    points1[i] = cv::Point2d(x1.x(), x1.y());
    points2[i] = cv::Point2d(x2.x(), x2.y());
  }
  const double focal = 0.5 * (features1.camera.MeanFocalLength() +
                              features2.camera.MeanFocalLength());
  cv::Mat inlier_mask;
  const cv::Mat E_stack = cv::findEssentialMat(
      points1, points2, cv::Mat::eye(3, 3, CV_64F), cv::RANSAC,
      options.confidence, options.max_error_px / focal,
      VerificationTrials(options), inlier_mask);
  if (E_stack.rows < 3 || inlier_mask.empty()) return geometry;
  int num_inliers = 0;
  for (int i = 0; i < num_matches; ++i) {
    num_inliers += inlier_mask.at<uint8_t>(i) != 0 ? 1 : 0;
  }
  if (num_inliers < options.min_num_inliers ||
      num_inliers < options.min_inlier_ratio * num_matches) {
    return geometry;
  }
  geometry.inlier_matches.resize(num_inliers, 2);
  for (int i = 0, k = 0; i < num_matches; ++i) {
    if (inlier_mask.at<uint8_t>(i) != 0) {
      geometry.inlier_matches.row(k++) = matches.row(i);
    }
  }
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) geometry.E(r, c) = E_stack.at<double>(r, c);
  }
  const Eigen::Matrix3d K1 = features1.camera.CalibrationMatrix();
  const Eigen::Matrix3d K2 = features2.camera.CalibrationMatrix();
  geometry.F = K2.inverse().transpose() * geometry.E * K1.inverse();
  geometry.config = TwoViewGeometryConfig::kCalibrated;
  *verified = true;
  return geometry;
}

}  // namespace

float DotToDistance(float dot) {
  // COLMAP's SIFT descriptors are unit vectors scaled by 512 and rounded.
  constexpr float kDescriptorNormSquared = 512.0f * 512.0f;
  return std::acos(std::min(dot / kDescriptorNormSquared, 1.0f));
}

bool ExactMatchingOptions::Check() const {
  bool ok = true;
  auto fail = [&ok](const std::string& message) {
    LOG(ERROR) << "ExactMatching." << message;
    ok = false;
  };
  if (!(max_ratio > 0 && max_ratio <= 1)) fail("max_ratio must be in (0, 1]");
  if (!(max_distance > 0 && max_distance <= M_PI)) {
    fail("max_distance must be in (0, pi]");
  }
  if (!(max_error_px > 0 && std::isfinite(max_error_px))) {
    fail("max_error_px must be > 0");
  }
  if (!(confidence > 0 && confidence < 1)) fail("confidence must be in (0, 1)");
  if (max_num_trials < 1) fail("max_num_trials must be >= 1");
  if (min_num_inliers < 5) fail("min_num_inliers must be >= 5");
  if (!(min_inlier_ratio >= 0 && min_inlier_ratio <= 1)) {
    fail("min_inlier_ratio must be in [0, 1]");
  }
  return ok;
}

int VerificationTrials(const ExactMatchingOptions& options) {
  // Samples of 5 matches, all inliers with probability ratio^5.
  const double all_inliers = std::pow(options.min_inlier_ratio, 5.0);
  if (!(all_inliers > 0.0) || all_inliers >= 1.0) {
    return options.max_num_trials;
  }
  const double trials =
      std::ceil(std::log(1.0 - options.confidence) / std::log1p(-all_inliers));
  return static_cast<int>(
      std::min(static_cast<double>(options.max_num_trials), trials));
}

FeatureMatchesBlob MatchDescriptors(const FeatureDescriptorsBlob& descriptors1,
                                    const FeatureDescriptorsBlob& descriptors2,
                                    const ExactMatchingOptions& options) {
  const int n1 = static_cast<int>(descriptors1.rows());
  const int n2 = static_cast<int>(descriptors2.rows());
  if (n1 == 0 || n2 == 0) return FeatureMatchesBlob(0, 2);
  THROW_CHECK(descriptors1.cols() == descriptors2.cols(),
              "descriptors of " << descriptors1.cols() << " and "
                                << descriptors2.cols() << " dimensions");
  using RowMajorXf =
      Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int dims = static_cast<int>(descriptors1.cols());
  const RowMajorXf d1 = descriptors1.cast<float>();
  const Eigen::MatrixXf d2_t = descriptors2.cast<float>().transpose();
  // Integer dot products below 2^24 are exact in float whatever the order
  // of the sums: the results do not depend on the CPU's path
  // (descriptor_dots.h).
  std::vector<int> best2(n1, -1);
  std::vector<float> best_dot1(n1, -1.0f);
  std::vector<float> second_dot1(n1, -1.0f);
  std::vector<int> best1_of2(n2, -1);
  std::vector<float> best_dot2(n2, -1.0f);
  std::vector<float> dots(static_cast<size_t>(std::min(kRowBlock, n1)) * n2);
  for (int begin = 0; begin < n1; begin += kRowBlock) {
    const int rows = std::min(kRowBlock, n1 - begin);
    DescriptorDots(d1.data() + static_cast<size_t>(begin) * dims, rows,
                   d2_t.data(), n2, dims, dots.data());
    for (int r = 0; r < rows; ++r) {
      const int i = begin + r;
      const float* row = dots.data() + static_cast<size_t>(r) * n2;
      for (int j = 0; j < n2; ++j) {
        const float dot = row[j];
        if (dot > best_dot1[i]) {
          second_dot1[i] = best_dot1[i];
          best_dot1[i] = dot;
          best2[i] = j;
        } else if (dot > second_dot1[i]) {
          second_dot1[i] = dot;
        }
        if (dot > best_dot2[j]) {
          best_dot2[j] = dot;
          best1_of2[j] = i;
        }
      }
    }
  }
  std::vector<std::pair<int, int>> kept;
  for (int i = 0; i < n1; ++i) {
    const int j = best2[i];
    if (j < 0) continue;
    const float best = DotToDistance(best_dot1[i]);
    if (best > options.max_distance) continue;
    if (n2 > 1 && best >= options.max_ratio * DotToDistance(second_dot1[i])) {
      continue;
    }
    if (options.cross_check && best1_of2[j] != i) continue;
    kept.emplace_back(i, j);
  }
  FeatureMatchesBlob matches(kept.size(), 2);
  for (size_t k = 0; k < kept.size(); ++k) {
    matches(k, 0) = static_cast<point2D_t>(kept[k].first);
    matches(k, 1) = static_cast<point2D_t>(kept[k].second);
  }
  return matches;
}

std::vector<std::pair<image_t, image_t>> MatchingPairs(
    const std::vector<DatabaseImage>& images, int exhaustive_max_num_images,
    int sequential_overlap, bool quadratic_overlap) {
  std::vector<DatabaseImage> sorted = images;
  std::sort(sorted.begin(), sorted.end(),
            [](const DatabaseImage& a, const DatabaseImage& b) {
              return a.name < b.name;
            });
  const int n = static_cast<int>(sorted.size());
  std::vector<std::pair<image_t, image_t>> pairs;
  auto add = [&](int a, int b) {
    const image_t id1 = std::min(sorted[a].image_id, sorted[b].image_id);
    const image_t id2 = std::max(sorted[a].image_id, sorted[b].image_id);
    pairs.emplace_back(id1, id2);
  };
  if (n <= exhaustive_max_num_images) {
    for (int a = 0; a < n; ++a) {
      for (int b = a + 1; b < n; ++b) add(a, b);
    }
  } else {
    for (int a = 0; a < n; ++a) {
      for (int k = 1; k <= sequential_overlap && a + k < n; ++k) add(a, a + k);
      if (quadratic_overlap) {
        for (int k = 0; k < std::min(sequential_overlap, 30); ++k) {
          const long long b = a + (1LL << k);
          if (b >= n) break;
          add(a, static_cast<int>(b));
        }
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

ExactMatchingSummary RunExactMatching(
    const std::string& database_path,
    const std::vector<std::pair<image_t, image_t>>& pairs,
    const ExactMatchingOptions& options) {
  THROW_CHECK(options.Check(), "invalid ExactMatching options");
  Database database(database_path);
  ExactMatchingSummary summary;
  std::vector<std::pair<image_t, image_t>> todo;
  for (const auto& pair : pairs) {
    if (database.ExistsMatches(pair.first, pair.second)) {
      ++summary.num_pairs_skipped;
    } else {
      todo.push_back(pair);
    }
  }
  std::map<image_t, ImageFeatures> features;
  for (const auto& [id1, id2] : todo) {
    for (const image_t id : {id1, id2}) {
      if (features.count(id) > 0) continue;
      ImageFeatures entry;
      const std::optional<DatabaseImage> image = database.ReadImage(id);
      THROW_CHECK(image.has_value(),
                  "exact matching: no image " << id << " in " << database_path);
      entry.image = *image;
      const std::optional<Camera> camera = database.ReadCamera(image->camera_id);
      THROW_CHECK(camera.has_value(), "exact matching: image "
                                          << image->name << " of "
                                          << database_path << " has no camera");
      entry.camera = *camera;
      entry.keypoints = database.ReadKeypoints(id);
      entry.descriptors = database.ReadDescriptors(id);
      THROW_CHECK(entry.keypoints.rows() == entry.descriptors.rows() &&
                      (entry.keypoints.rows() == 0 ||
                       entry.keypoints.cols() >= 2),
                  "exact matching: image "
                      << image->name << " of " << database_path << " has "
                      << entry.keypoints.rows() << " keypoints and "
                      << entry.descriptors.rows() << " descriptors");
      features.emplace(id, std::move(entry));
    }
  }
  LOG(INFO) << "exact matching: " << todo.size() << " pairs of "
            << features.size() << " images (" << summary.num_pairs_skipped
            << " pairs matched before, left as they are; dot products on the "
            << DescriptorDotsPath() << " path, verification in at most "
            << VerificationTrials(options) << " RANSAC trials)";

  std::vector<PairResult> results(todo.size());
  std::atomic<int> num_done(0);
  std::mutex log_mutex;
  const auto start = std::chrono::steady_clock::now();
  auto last_log = start;
  ParallelFor(0, static_cast<int>(todo.size()), options.num_threads,
              [&](int p) {
                const ImageFeatures& f1 = features.at(todo[p].first);
                const ImageFeatures& f2 = features.at(todo[p].second);
                PairResult& result = results[p];
                result.matches =
                    MatchDescriptors(f1.descriptors, f2.descriptors, options);
                result.geometry =
                    Verify(f1, f2, result.matches, options, &result.verified);
                const int done = ++num_done;
                std::lock_guard<std::mutex> lock(log_mutex);
                const auto now = std::chrono::steady_clock::now();
                if (now - last_log > std::chrono::seconds(20)) {
                  last_log = now;
                  LOG(INFO) << "exact matching: " << done << " of "
                            << todo.size() << " pairs, "
                            << std::chrono::duration<double>(now - start).count()
                            << " s";
                }
              });

  DatabaseTransaction transaction(&database);
  for (size_t p = 0; p < todo.size(); ++p) {
    const auto [id1, id2] = todo[p];
    database.WriteMatches(id1, id2, results[p].matches);
    if (database.ExistsTwoViewGeometry(id1, id2)) {
      database.DeleteTwoViewGeometry(id1, id2);
    }
    database.WriteTwoViewGeometry(id1, id2, results[p].geometry);
    ++summary.num_pairs;
    summary.num_matches += results[p].matches.rows();
    if (results[p].verified) {
      ++summary.num_verified_pairs;
      summary.num_inlier_matches += results[p].geometry.inlier_matches.rows();
    }
  }
  transaction.Commit();
  LOG(INFO) << "exact matching: " << summary.num_pairs << " pairs, "
            << summary.num_verified_pairs << " verified, "
            << summary.num_matches << " matches, "
            << summary.num_inlier_matches << " inliers, "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                             start)
                   .count()
            << " s";
  return summary;
}

}  // namespace colmap_lidar
