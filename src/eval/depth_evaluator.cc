#include "src/eval/depth_evaluator.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <mutex>
#include <numeric>
#include <sstream>
#include <utility>

#include "colmap_ext/mvs/workspace.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/parallel.h"
#include "src/dataset/calibration.h"
#include "src/eval/eval_stats.h"

namespace colmap_lidar {
namespace {

bool IsDistortionFree(CameraModelId model_id) {
  return model_id == CameraModelId::kSimplePinhole ||
         model_id == CameraModelId::kPinhole;
}

// The truth's z-depth at the truth pixel coordinates (x = col, y = row),
// or 0 when the nearest pixel is outside or invalid. See the header for
// the bilinear rule.
float SampleTruth(const DepthMap& truth, double x, double y,
                  double max_bilinear_spread) {
  const double width = static_cast<double>(truth.GetWidth());
  const double height = static_cast<double>(truth.GetHeight());
  const double col_nearest = std::round(x);
  const double row_nearest = std::round(y);
  if (!(col_nearest >= 0 && row_nearest >= 0 && col_nearest < width &&
        row_nearest < height)) {
    return 0.0f;
  }
  const float nearest = truth.Get(static_cast<size_t>(row_nearest),
                                  static_cast<size_t>(col_nearest));
  if (!(nearest > 0)) return 0.0f;
  const double col0 = std::floor(x);
  const double row0 = std::floor(y);
  if (max_bilinear_spread <= 0 || col0 < 0 || row0 < 0 ||
      col0 + 1 >= width || row0 + 1 >= height) {
    return nearest;
  }
  const size_t c = static_cast<size_t>(col0);
  const size_t r = static_cast<size_t>(row0);
  const float d00 = truth.Get(r, c);
  const float d01 = truth.Get(r, c + 1);
  const float d10 = truth.Get(r + 1, c);
  const float d11 = truth.Get(r + 1, c + 1);
  const float lo = std::min({d00, d01, d10, d11});
  const float hi = std::max({d00, d01, d10, d11});
  if (!(lo > 0) || hi - lo > max_bilinear_spread * lo) return nearest;
  const double a = x - col0;
  const double b = y - row0;
  return static_cast<float>((1 - b) * ((1 - a) * d00 + a * d01) +
                            b * ((1 - a) * d10 + a * d11));
}

// Unit normal of the true surface at truth pixel (col, row), from the truth
// map's back-projected neighbours (one-sided differences, each axis taking
// the side whose depth changes least, so that a depth edge on one side does
// not tilt it); false where a needed neighbour is invalid or both sides
// change by more than max_relative_step (a depth edge, a silhouette).
// rays[row * width + col] = CamFromImg of the truth pixel, z = 1.
bool TruthNormal(const DepthMap& truth, const std::vector<Eigen::Vector3d>& rays,
                 size_t row, size_t col, double max_relative_step,
                 Eigen::Vector3d* normal) {
  const size_t width = truth.GetWidth();
  const size_t height = truth.GetHeight();
  const double depth = truth.Get(row, col);
  const Eigen::Vector3d center = depth * rays[row * width + col];
  // The neighbour step along one axis: the valid side with the smaller
  // depth change.
  auto step = [&](bool horizontal, Eigen::Vector3d* delta) {
    double best = std::numeric_limits<double>::infinity();
    for (const int sign : {1, -1}) {
      const long r = static_cast<long>(row) + (horizontal ? 0 : sign);
      const long c = static_cast<long>(col) + (horizontal ? sign : 0);
      if (r < 0 || c < 0 || r >= static_cast<long>(height) ||
          c >= static_cast<long>(width)) {
        continue;
      }
      const double neighbour = truth.Get(r, c);
      if (!(neighbour > 0)) continue;
      const double change = std::abs(neighbour - depth);
      if (change > max_relative_step * depth || change >= best) continue;
      best = change;
      *delta = sign * (neighbour * rays[r * width + c] - center);
    }
    return std::isfinite(best);
  };
  Eigen::Vector3d along_col;
  Eigen::Vector3d along_row;
  if (!step(true, &along_col) || !step(false, &along_row)) return false;
  const Eigen::Vector3d cross = along_col.cross(along_row);
  const double norm = cross.norm();
  if (!(norm > 0)) return false;
  *normal = cross / norm;
  return true;
}

// "12.3 %".
std::string Percent(double share) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(1) << 100.0 * share << " %";
  return text.str();
}

std::string FrameOfImage(const std::string& image_name) {
  return std::filesystem::path(image_name).stem().string();
}

Json StatsToJson(const DepthStats& stats) {
  Json json;
  json["coverage"] = stats.coverage;
  for (size_t i = 0; i < stats.thresholds_m.size(); ++i) {
    json[DepthThresholdKey(stats.thresholds_m[i])] = stats.within[i];
  }
  for (size_t i = 0; i < stats.thresholds_m.size(); ++i) {
    json["surface_" + DepthThresholdKey(stats.thresholds_m[i])] =
        stats.surface_within[i];
  }
  json["median_abs_error_m"] = stats.median_abs_error_m;
  json["mean_abs_error_m"] = stats.mean_abs_error_m;
  json["num_pixels"] = stats.num_pixels;
  json["num_truth_valid"] = stats.num_truth_valid;
  json["num_covered"] = stats.num_covered;
  json["num_without_truth"] = stats.num_without_truth;
  return json;
}

}  // namespace

bool DepthEvaluationOptions::Check() const {
  if (!CheckThresholds(thresholds_m, "DepthEvaluation.thresholds_m")) {
    return false;
  }
  if (!(max_bilinear_spread >= 0 && std::isfinite(max_bilinear_spread))) {
    LOG(ERROR) << "DepthEvaluation.max_bilinear_spread must be >= 0, got "
               << max_bilinear_spread;
    return false;
  }
  if (!(max_normal_relative_step > 0 && std::isfinite(max_normal_relative_step))) {
    LOG(ERROR) << "DepthEvaluation.max_normal_relative_step must be > 0, got "
               << max_normal_relative_step;
    return false;
  }
  if (map_types.empty()) {
    LOG(ERROR) << "DepthEvaluation.map_types must name at least one type";
    return false;
  }
  for (const std::string& type : map_types) {
    if (type != "photometric" && type != "geometric") {
      LOG(ERROR) << "DepthEvaluation.map_types: unknown type '" << type
                 << "' (photometric | geometric)";
      return false;
    }
  }
  return true;
}

DepthStats ComputeDepthStats(const DepthErrors& errors,
                             const std::vector<double>& thresholds_m) {
  DepthStats stats;
  stats.num_pixels = errors.num_pixels;
  stats.num_truth_valid = errors.num_truth_valid;
  stats.num_covered = errors.num_covered;
  stats.num_without_truth = errors.num_without_truth;
  stats.thresholds_m = thresholds_m;
  stats.within.assign(thresholds_m.size(), 0.0);
  if (errors.num_truth_valid > 0) {
    stats.coverage = static_cast<double>(errors.num_covered) /
                     static_cast<double>(errors.num_truth_valid);
  }
  const std::vector<float>& values = errors.abs_errors_m;
  if (values.empty()) return stats;
  const double count = static_cast<double>(values.size());
  auto share_below = [count](const std::vector<float>& errors_m,
                             double threshold) {
    return static_cast<double>(std::count_if(
               errors_m.begin(), errors_m.end(),
               [&](float error) { return error < threshold; })) /
           count;
  };
  stats.surface_within.assign(thresholds_m.size(), 0.0);
  for (size_t i = 0; i < thresholds_m.size(); ++i) {
    stats.within[i] = share_below(values, thresholds_m[i]);
    if (errors.surface_errors_m.size() == values.size()) {
      stats.surface_within[i] =
          share_below(errors.surface_errors_m, thresholds_m[i]);
    }
  }
  stats.mean_abs_error_m =
      std::accumulate(values.begin(), values.end(), 0.0) / count;
  std::vector<float> sorted = values;
  const size_t middle = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + middle, sorted.end());
  double median = sorted[middle];
  if (sorted.size() % 2 == 0) {
    median = 0.5 * (median + *std::max_element(sorted.begin(),
                                               sorted.begin() + middle));
  }
  stats.median_abs_error_m = median;
  return stats;
}

namespace {

// A non-negative float's bit pattern grows with its value; its top 20 bits
// (the sign bit is cleared) index the histogram.
constexpr int kHistogramShift = 11;
constexpr size_t kNumHistogramBins = size_t{1} << 20;

uint32_t FloatBits(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof(bits));
  return bits & 0x7FFFFFFFu;
}

float FloatFromBits(uint32_t bits) {
  float value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

size_t HistogramBin(float value) {
  return std::min<size_t>(FloatBits(value) >> kHistogramShift,
                          kNumHistogramBins - 1);
}

}  // namespace

DepthErrorAccumulator::DepthErrorAccumulator(std::vector<double> thresholds_m,
                                             size_t num_slots)
    : thresholds_m_(std::move(thresholds_m)),
      num_within_(thresholds_m_.size(), 0),
      num_surface_within_(thresholds_m_.size(), 0),
      slot_sums_m_(num_slots, 0.0),
      slot_used_(num_slots, 0),
      histogram_(kNumHistogramBins, 0) {}

void DepthErrorAccumulator::Add(size_t slot, const DepthErrors& errors) {
  THROW_CHECK(slot < slot_sums_m_.size() && !slot_used_[slot],
              "Depth error slot " << slot << " of " << slot_sums_m_.size()
                                  << " out of range or added twice");
  slot_used_[slot] = 1;
  num_pixels_ += errors.num_pixels;
  num_truth_valid_ += errors.num_truth_valid;
  num_covered_ += errors.num_covered;
  num_without_truth_ += errors.num_without_truth;
  const std::vector<float>& values = errors.abs_errors_m;
  num_errors_ += values.size();
  // As ComputeDepthStats sums: in the map's pixel order, in double.
  slot_sums_m_[slot] = std::accumulate(values.begin(), values.end(), 0.0);
  const bool has_surface = errors.surface_errors_m.size() == values.size();
  all_have_surface_errors_ = all_have_surface_errors_ && has_surface;
  for (size_t i = 0; i < thresholds_m_.size(); ++i) {
    const double threshold = thresholds_m_[i];
    num_within_[i] += std::count_if(values.begin(), values.end(),
                                    [&](float e) { return e < threshold; });
    if (has_surface) {
      num_surface_within_[i] += std::count_if(
          errors.surface_errors_m.begin(), errors.surface_errors_m.end(),
          [&](float e) { return e < threshold; });
    }
  }
  for (const float value : values) {
    ++histogram_[HistogramBin(value)];
  }
}

double DepthErrorAccumulator::ValueAtRank(size_t rank) const {
  THROW_CHECK(rank < num_errors_,
              "Rank " << rank << " of " << num_errors_ << " depth errors");
  size_t before = 0;
  for (size_t bin = 0; bin < histogram_.size(); ++bin) {
    const size_t count = histogram_[bin];
    if (rank < before + count) {
      const double low =
          FloatFromBits(static_cast<uint32_t>(bin << kHistogramShift));
      const double high =
          FloatFromBits(static_cast<uint32_t>((bin + 1) << kHistogramShift));
      // The bin's values taken as spread evenly over it.
      const double fraction =
          (static_cast<double>(rank - before) + 0.5) / static_cast<double>(count);
      return low + fraction * (high - low);
    }
    before += count;
  }
  return 0.0;  // Not reached: rank < num_errors_.
}

DepthStats DepthErrorAccumulator::Stats() const {
  DepthStats stats;
  stats.num_pixels = num_pixels_;
  stats.num_truth_valid = num_truth_valid_;
  stats.num_covered = num_covered_;
  stats.num_without_truth = num_without_truth_;
  stats.thresholds_m = thresholds_m_;
  stats.within.assign(thresholds_m_.size(), 0.0);
  if (num_truth_valid_ > 0) {
    stats.coverage = static_cast<double>(num_covered_) /
                     static_cast<double>(num_truth_valid_);
  }
  if (num_errors_ == 0) return stats;
  const double count = static_cast<double>(num_errors_);
  stats.surface_within.assign(thresholds_m_.size(), 0.0);
  for (size_t i = 0; i < thresholds_m_.size(); ++i) {
    stats.within[i] = static_cast<double>(num_within_[i]) / count;
    if (all_have_surface_errors_) {
      stats.surface_within[i] =
          static_cast<double>(num_surface_within_[i]) / count;
    }
  }
  stats.mean_abs_error_m =
      std::accumulate(slot_sums_m_.begin(), slot_sums_m_.end(), 0.0) / count;
  const size_t middle = num_errors_ / 2;
  stats.median_abs_error_m =
      num_errors_ % 2 == 0
          ? 0.5 * (ValueAtRank(middle - 1) + ValueAtRank(middle))
          : ValueAtRank(middle);
  return stats;
}

std::vector<Eigen::Vector3d> TruthPixelRays(const Camera& truth_camera) {
  std::vector<Eigen::Vector3d> rays(truth_camera.width * truth_camera.height);
  for (size_t row = 0; row < truth_camera.height; ++row) {
    for (size_t col = 0; col < truth_camera.width; ++col) {
      rays[row * truth_camera.width + col] =
          truth_camera
              .CamFromImg(Eigen::Vector2d(static_cast<double>(col),
                                          static_cast<double>(row)))
              .homogeneous();
    }
  }
  return rays;
}

DepthErrors CompareDepthMaps(const DepthMap& estimate,
                             const Eigen::Matrix3d& K_estimate,
                             const DepthMap& truth, const Camera& truth_camera,
                             const DepthEvaluationOptions& options,
                             const std::vector<Eigen::Vector3d>* truth_rays) {
  truth_camera.Check();
  THROW_CHECK(truth.GetWidth() == truth_camera.width &&
                  truth.GetHeight() == truth_camera.height,
              "Ground-truth depth map of " << truth.GetWidth() << " x "
                                           << truth.GetHeight()
                                           << " for a camera of "
                                           << truth_camera.width << " x "
                                           << truth_camera.height);
  const bool check_fold = !IsDistortionFree(truth_camera.model_id);
  // The truth's rays, for its normals (surface distances).
  std::vector<Eigen::Vector3d> own_rays;
  if (truth_rays == nullptr) {
    own_rays = TruthPixelRays(truth_camera);
    truth_rays = &own_rays;
  }
  THROW_CHECK(truth_rays->size() == truth.GetWidth() * truth.GetHeight(),
              truth_rays->size() << " truth rays for a map of "
                                 << truth.GetWidth() << " x "
                                 << truth.GetHeight());
  DepthErrors errors;
  errors.num_pixels = estimate.GetWidth() * estimate.GetHeight();
  for (size_t row = 0; row < estimate.GetHeight(); ++row) {
    for (size_t col = 0; col < estimate.GetWidth(); ++col) {
      const Eigen::Vector3d ray = MvsPixelRay(K_estimate, row, col);
      if (!(ray.z() > 0)) continue;
      const Eigen::Vector2d pixel = truth_camera.ImgFromCam(ray);
      // A distortion polynomial folds some rays from outside its field of
      // view back into the image: those pixels do not see along this ray.
      if (check_fold &&
          (truth_camera.CamFromImg(pixel) - ray.hnormalized()).norm() >
              1e-6) {
        continue;
      }
      const float truth_depth = SampleTruth(truth, pixel.x(), pixel.y(),
                                            options.max_bilinear_spread);
      const bool has_estimate = estimate.IsValid(row, col);
      if (!(truth_depth > 0)) {
        errors.num_without_truth += has_estimate ? 1 : 0;
        continue;
      }
      ++errors.num_truth_valid;
      if (!has_estimate) continue;
      ++errors.num_covered;
      const float depth_error = std::abs(estimate.Get(row, col) - truth_depth);
      errors.abs_errors_m.push_back(depth_error);
      // Our point and the true one lie on the same ray r (z = 1): their
      // offset is depth_error * r, its component along the true normal
      // depth_error * |r . n|.
      Eigen::Vector3d normal;
      const size_t truth_row = static_cast<size_t>(std::round(pixel.y()));
      const size_t truth_col = static_cast<size_t>(std::round(pixel.x()));
      errors.surface_errors_m.push_back(
          TruthNormal(truth, *truth_rays, truth_row, truth_col,
                      options.max_normal_relative_step, &normal)
              ? static_cast<float>(depth_error * std::abs(ray.dot(normal)))
              : depth_error);
    }
  }
  return errors;
}

DepthEvaluation EvaluateDepthMaps(const std::string& dense_path,
                                  const std::string& dataset_path,
                                  const DepthEvaluationOptions& options) {
  THROW_CHECK(options.Check(), "Invalid depth evaluation options");
  const std::string truth_dir =
      JoinPaths(dataset_path, "ground_truth/depth_maps");
  THROW_CHECK(ExistsDir(truth_dir),
              "No ground-truth depth maps: " << truth_dir << " is missing");
  const Camera truth_camera =
      ReadCalibration(JoinPaths(dataset_path, "calibration.yaml")).camera;
  const DenseWorkspace workspace(dense_path);
  const Reconstruction model = workspace.ReadModel();

  DepthEvaluation evaluation;
  evaluation.thresholds_m = options.thresholds_m;
  std::vector<DenseMapType> types;
  for (const std::string& name : options.map_types) {
    const DenseMapType type = DenseMapTypeFromString(name);
    bool any = false;
    for (const Image& image : model.images) {
      any = any || ExistsFile(workspace.DepthMapPath(image.name, type));
    }
    if (!any) {
      LOG(WARNING) << "depth evaluation: no " << name << " depth map in "
                   << workspace.DepthMapsDir() << "; skipped";
      continue;
    }
    types.push_back(type);
    evaluation.map_types.push_back(name);
  }
  THROW_CHECK(!types.empty(), "No depth maps of the types asked for in "
                                  << workspace.DepthMapsDir());

  std::vector<const Image*> images;
  for (const Image& image : model.images) {
    if (ExistsFile(
            JoinPaths(truth_dir, FrameOfImage(image.name) + ".bin"))) {
      images.push_back(&image);
    } else {
      ++evaluation.num_images_without_truth;
    }
  }
  std::sort(images.begin(), images.end(),
            [](const Image* a, const Image* b) { return a->name < b->name; });
  THROW_CHECK(!images.empty(), "No image of " << workspace.SparseDir()
                                              << " has a ground-truth depth "
                                                 "map in "
                                              << truth_dir);
  if (evaluation.num_images_without_truth > 0) {
    LOG(WARNING) << "depth evaluation: " << evaluation.num_images_without_truth
                 << " images without a ground-truth depth map; skipped";
  }

  const std::vector<Eigen::Vector3d> truth_rays = TruthPixelRays(truth_camera);
  // Each image's errors are reduced to its figures as soon as they are
  // computed; the overall figures accumulate without the pixels.
  std::vector<DepthErrorAccumulator> overall;
  for (size_t t = 0; t < types.size(); ++t) {
    overall.emplace_back(options.thresholds_m, images.size());
  }
  std::mutex overall_mutex;
  evaluation.images.resize(images.size());
  ParallelFor(0, static_cast<int>(images.size()), options.num_threads,
              [&](int i) {
                const Image& image = *images[i];
                const auto camera_it = model.cameras.find(image.camera_id);
                THROW_CHECK(camera_it != model.cameras.end(),
                            "Image " << image.name << " of "
                                     << workspace.SparseDir()
                                     << " has no camera");
                const Camera& camera = camera_it->second;
                const DepthMap truth = DepthMap::Read(JoinPaths(
                    truth_dir, FrameOfImage(image.name) + ".bin"));
                DepthImageEvaluation& image_evaluation =
                    evaluation.images[i];
                image_evaluation.image_name = image.name;
                for (size_t t = 0; t < types.size(); ++t) {
                  const std::string path =
                      workspace.DepthMapPath(image.name, types[t]);
                  DepthErrors errors;
                  if (ExistsFile(path)) {
                    const DepthMap estimate = DepthMap::Read(path);
                    const Eigen::Matrix3d K = ScaleCalibrationToMap(
                        camera.CalibrationMatrix(), camera.width,
                        camera.height, estimate.GetWidth(),
                        estimate.GetHeight());
                    errors = CompareDepthMaps(estimate, K, truth,
                                              truth_camera, options,
                                              &truth_rays);
                  }
                  image_evaluation.stats.push_back(
                      ComputeDepthStats(errors, options.thresholds_m));
                  std::lock_guard<std::mutex> lock(overall_mutex);
                  overall[t].Add(static_cast<size_t>(i), errors);
                }
              });
  for (const DepthErrorAccumulator& accumulator : overall) {
    evaluation.overall.push_back(accumulator.Stats());
  }
  return evaluation;
}

std::string DepthThresholdKey(double threshold_m) {
  std::ostringstream key;
  key << "within_" << std::setprecision(6) << threshold_m * 100.0 << "cm";
  return key.str();
}

std::string DepthSummary(const DepthEvaluation& evaluation,
                         const std::string& map_type) {
  const auto it = std::find(evaluation.map_types.begin(),
                            evaluation.map_types.end(), map_type);
  if (it == evaluation.map_types.end()) return "";
  const DepthStats& stats =
      evaluation.overall[it - evaluation.map_types.begin()];
  std::ostringstream text;
  text << map_type << ":";
  for (size_t i = 0; i < stats.thresholds_m.size(); ++i) {
    text << (i > 0 ? "," : "") << " " << Percent(stats.within[i])
         << " within " << std::setprecision(6)
         << stats.thresholds_m[i] * 100.0 << " cm";
  }
  text << ", coverage " << Percent(stats.coverage) << ", median "
       << std::fixed << std::setprecision(2)
       << stats.median_abs_error_m * 100.0 << " cm";
  return text.str();
}

std::string FormatDepthEvaluation(const DepthEvaluation& evaluation) {
  std::ostringstream text;
  text << "Depth maps against the ground truth (" << evaluation.images.size()
       << " images; coverage = share of truth pixels with a depth, within = "
          "share of covered pixels; surf = within the distance of the "
          "true surface, along its normal)\n";
  text << std::left << std::setw(14) << "type" << std::right << std::setw(10)
       << "coverage";
  for (const double threshold : evaluation.thresholds_m) {
    std::ostringstream header;
    header << "<" << std::setprecision(6) << threshold * 100.0 << "cm";
    text << std::setw(10) << header.str();
  }
  for (const double threshold : evaluation.thresholds_m) {
    std::ostringstream header;
    header << "surf<" << std::setprecision(6) << threshold * 100.0 << "cm";
    text << std::setw(13) << header.str();
  }
  text << std::setw(12) << "median_cm" << std::setw(10) << "mean_cm"
       << std::setw(14) << "no_truth_px" << "\n";
  for (size_t t = 0; t < evaluation.map_types.size(); ++t) {
    const DepthStats& stats = evaluation.overall[t];
    text << std::left << std::setw(14) << evaluation.map_types[t]
         << std::right << std::setw(10) << Percent(stats.coverage);
    for (const double share : stats.within) {
      text << std::setw(10) << Percent(share);
    }
    for (const double share : stats.surface_within) {
      text << std::setw(13) << Percent(share);
    }
    text << std::fixed << std::setprecision(2) << std::setw(12)
         << stats.median_abs_error_m * 100.0 << std::setw(10)
         << stats.mean_abs_error_m * 100.0 << std::setw(14)
         << stats.num_without_truth << "\n";
    text.unsetf(std::ios::fixed);
  }
  return text.str();
}

void WriteDepthEvaluationJson(const std::string& path,
                              const DepthEvaluation& evaluation) {
  Json json;
  json["evaluator"] = "depth_maps";
  json["thresholds_m"] = evaluation.thresholds_m;
  json["num_images"] = evaluation.images.size();
  json["num_images_without_truth"] = evaluation.num_images_without_truth;
  Json overall = Json::object();
  for (size_t t = 0; t < evaluation.map_types.size(); ++t) {
    overall[evaluation.map_types[t]] = StatsToJson(evaluation.overall[t]);
  }
  json["overall"] = std::move(overall);
  Json images = Json::array();
  for (const DepthImageEvaluation& image : evaluation.images) {
    Json& image_json = images.emplace_back();
    image_json["name"] = image.image_name;
    for (size_t t = 0; t < evaluation.map_types.size(); ++t) {
      if (image.stats[t].num_pixels == 0) continue;
      image_json[evaluation.map_types[t]] = StatsToJson(image.stats[t]);
    }
  }
  json["images"] = std::move(images);
  WriteJsonFile(path, json);
}

}  // namespace colmap_lidar
