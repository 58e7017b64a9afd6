// Accuracy and completeness of our MVS depth maps against the ground-truth
// depth maps of a synthesized recording (ground_truth/depth_maps/<frame>.bin).
//
// The two maps live on different cameras: ours on the undistorted PINHOLE
// camera of the dense workspace (dense/sparse), possibly at a reduced
// resolution; the truth on the recording's own (possibly distorted) camera
// of calibration.yaml. Both share the camera frame (undistortion keeps it),
// so every pixel of our map is compared along its own ray:
//   ray     = K_map^-1 [col, row, 1]            (MVS convention, no +0.5)
//   (x, y)  = ImgFromCam_truth(ray)             truth pixel (col = x, row = y),
//             the truth maps being written with the same convention;
//   truth   = bilinear z-depth at (x, y) when the 4 neighbours are valid and
//             agree within max_bilinear_spread (relative), else the nearest
//             pixel's (a depth edge is never blended across);
//   error   = |ours - truth| (camera-frame z, metres).
// Our depth is computed with our refined poses, so pose errors are part of
// the error, as they are part of what the reconstruction delivers.
//
// Figures per map type (photometric, geometric), per image and overall:
//   coverage   = covered / truth-valid pixels (pixels of our map whose ray
//                meets the scene in the truth, and of those the ones where
//                our map has a depth);
//   within(t)  = share of covered pixels with error < t;
//   surface_within(t) = share of covered pixels whose point lies within t
//                of the true surface's tangent plane: error * |r . n| with
//                r the ray (z = 1) and n the truth's normal at that pixel
//                (from its neighbours in the truth map); where the truth
//                has no normal (a depth edge) the depth error itself. At
//                grazing incidence a large depth error is a small offset
//                from the surface (ground 20 m ahead of a camera 1.5 m up:
//                5 cm of depth is 4 mm off the ground);
//   median / mean absolute error over covered pixels (per image exact; the
//                overall median read off a histogram, within 0.025 %, so
//                that no pixel is held past its image: see
//                DepthErrorAccumulator);
//   num_without_truth = pixels where we have a depth and the truth sees
//                nothing (sky, beyond the scene): invented depth.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/mvs/dense_maps.h"
#include "colmap_ext/scene/camera.h"

namespace colmap_lidar {

struct DepthEvaluationOptions {
  // Error thresholds t in metres; positive and strictly increasing. JSON
  // keys are within_<t in cm>cm (within_2cm, within_5cm, ...).
  std::vector<double> thresholds_m = {0.02, 0.05, 0.1};
  // Bilinear interpolation of the truth only where the 4 neighbours are
  // valid and (max - min) <= max_bilinear_spread * min; else the nearest
  // pixel. 5 % keeps grazing ground (about 3 % per pixel at 20 m for a
  // 424 px focal length at 1.5 m height) and rejects depth edges. 0 always
  // takes the nearest pixel. >= 0.
  double max_bilinear_spread = 0.05;
  // The truth's normal is taken only where its neighbours' depths differ
  // from the pixel's by at most this share (on one side per axis at least);
  // 0.05 keeps grazing ground as max_bilinear_spread does. > 0.
  double max_normal_relative_step = 0.05;
  // Map types to evaluate: "photometric" and/or "geometric"; a type whose
  // maps are missing for every image is skipped with a warning.
  std::vector<std::string> map_types = {"photometric", "geometric"};
  // Threads over the images; <= 0: all cores.
  int num_threads = -1;

  bool Check() const;
};

// Raw per-pixel outcome of one map (mergeable into an overall figure).
struct DepthErrors {
  size_t num_pixels = 0;
  size_t num_truth_valid = 0;
  size_t num_covered = 0;
  size_t num_without_truth = 0;
  // |ours - truth| of the covered pixels, metres.
  std::vector<float> abs_errors_m;
  // Their distances to the true surface's tangent plane (parallel).
  std::vector<float> surface_errors_m;
};

struct DepthStats {
  size_t num_pixels = 0;
  size_t num_truth_valid = 0;
  size_t num_covered = 0;
  size_t num_without_truth = 0;
  double coverage = 0.0;
  std::vector<double> thresholds_m;
  // Share of covered pixels with error < thresholds_m[i].
  std::vector<double> within;
  // Share of covered pixels within thresholds_m[i] of the true surface.
  std::vector<double> surface_within;
  double median_abs_error_m = 0.0;
  double mean_abs_error_m = 0.0;
};

DepthStats ComputeDepthStats(const DepthErrors& errors,
                             const std::vector<double>& thresholds_m);

// The overall figures of many maps without keeping their pixels (a 600-frame
// recording has 5e8 covered pixels per map type: 4 GB of errors): counts
// and shares exact; the mean's sum taken per map and added in slot order,
// so that it does not depend on the order of the calls (threads); the
// median read off a histogram of the errors' float bit patterns (the top 20
// bits of a non-negative float: its exponent and 12 bits of its mantissa),
// 2^20 bins each at most 2^-12 of its value wide, interpolated by rank
// within its bin: within 0.025 % of the exact median. 8 MiB whatever the
// number of maps.
class DepthErrorAccumulator {
 public:
  // `num_slots`: one per map that may be added (e.g. per image).
  DepthErrorAccumulator(std::vector<double> thresholds_m, size_t num_slots);

  // Adds one map's errors in slot `slot` (< num_slots, each slot once).
  // Not thread-safe: callers serialize.
  void Add(size_t slot, const DepthErrors& errors);

  // The figures over everything added, as ComputeDepthStats of all the
  // errors appended would give them but for the median's rounding.
  DepthStats Stats() const;

  // The value of the 0-based `rank` in the sorted errors, from the histogram
  // (rank < the number of errors added).
  double ValueAtRank(size_t rank) const;

 private:
  std::vector<double> thresholds_m_;
  size_t num_pixels_ = 0;
  size_t num_truth_valid_ = 0;
  size_t num_covered_ = 0;
  size_t num_without_truth_ = 0;
  size_t num_errors_ = 0;
  // Per threshold: errors below it, surface errors below it.
  std::vector<size_t> num_within_;
  std::vector<size_t> num_surface_within_;
  // Whether every map added had a surface error per pixel.
  bool all_have_surface_errors_ = true;
  // Per slot: the sum of its absolute errors, metres.
  std::vector<double> slot_sums_m_;
  std::vector<char> slot_used_;
  // Counts per bin of the errors' bit patterns >> kHistogramShift.
  std::vector<uint64_t> histogram_;
};

// Compares `estimate` (K_estimate at the estimate's resolution, MVS pixel
// convention) with `truth` taken by `truth_camera` (its full resolution;
// throws colmap_lidar::Error when the truth map's size differs from the
// camera's). Invalid estimate pixels are those with depth <= 0 or not
// finite; invalid truth pixels are those with depth <= 0. `truth_rays`
// (optional) is TruthPixelRays(truth_camera), computed once for many maps
// of one camera; null: computed here.
DepthErrors CompareDepthMaps(
    const DepthMap& estimate, const Eigen::Matrix3d& K_estimate,
    const DepthMap& truth, const Camera& truth_camera,
    const DepthEvaluationOptions& options,
    const std::vector<Eigen::Vector3d>* truth_rays = nullptr);

// CamFromImg of every pixel (col, row) of the camera, z = 1, row-major: the
// rays of the truth maps, for their normals.
std::vector<Eigen::Vector3d> TruthPixelRays(const Camera& truth_camera);

struct DepthImageEvaluation {
  std::string image_name;
  // Parallel to DepthEvaluation::map_types; num_pixels = 0 when that map
  // is missing for this image.
  std::vector<DepthStats> stats;
};

struct DepthEvaluation {
  std::vector<std::string> map_types;
  std::vector<double> thresholds_m;
  std::vector<DepthImageEvaluation> images;
  // Over all pixels of all images, parallel to map_types.
  std::vector<DepthStats> overall;
  // Images of the workspace without a truth map (skipped).
  size_t num_images_without_truth = 0;
};

// Evaluates every image of a dense workspace (`dense_path`: images/,
// sparse/, stereo/depth_maps/) against <dataset_path>/ground_truth/
// depth_maps/<frame>.bin, frame = the image name's file stem, with the
// camera of <dataset_path>/calibration.yaml. Throws naming the file when
// the calibration, the model or a map is unreadable, when no image has both
// a truth map and one of our maps, or on invalid options.
DepthEvaluation EvaluateDepthMaps(const std::string& dense_path,
                                  const std::string& dataset_path,
                                  const DepthEvaluationOptions& options);

// "within_5cm" for 0.05.
std::string DepthThresholdKey(double threshold_m);
// The overall figures of one type, e.g. "geometric: 97.9 % within 5 cm,
// coverage 88.1 %, median 0.8 cm"; empty when the type was not evaluated.
std::string DepthSummary(const DepthEvaluation& evaluation,
                         const std::string& map_type);
std::string FormatDepthEvaluation(const DepthEvaluation& evaluation);
// {"evaluator": "depth_maps", "thresholds_m": [...], "overall":
//  {"<type>": {coverage, within_2cm, ..., median_abs_error_m, ...}},
//  "images": [{"name": ..., "<type>": {...}}, ...]}.
void WriteDepthEvaluationJson(const std::string& path,
                              const DepthEvaluation& evaluation);

}  // namespace colmap_lidar
