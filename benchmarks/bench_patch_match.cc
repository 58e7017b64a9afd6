// Accuracy and speed of LIDAR-initialised vs random-initialised PatchMatch
// (paper section III-E) against ground-truth depth maps. Not a Google
// Benchmark: it prints tables.
//
//   bench_patch_match DATASET [NUM_REFS] [NUM_ITERATIONS]
//
// DATASET is a `colmap-lidar synthesize` output (calibration.yaml,
// poses_gt.txt, images/, lidar/, ground_truth/depth_maps/). For each of
// NUM_REFS reference frames (default 3) the 5 nearest frames are sources;
// the LIDAR scans of all frames are fused with the exact poses (5 cm voxels).
// Without features (LIDAR only). Prints, per iteration, the share of pixels
// with ground truth whose depth is within 5 cm, LIDAR vs random side by
// side, then the time per image of the default photometric run (5
// iterations, 2 threads) and the peak memory (getrusage).
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "colmap_ext/mvs/dense_maps.h"
#include "colmap_ext/util/file.h"
#include "src/dataset/calibration.h"
#include "src/dataset/poses.h"
#include "src/lidar/lidar_fusion.h"
#include "src/lidar/scan_io.h"
#include "src/mvs/lidar_patch_match_stereo.h"
#include "src/mvs/map_filter.h"
#include "src/mvs/mvs_test_scene.h"
#include "src/mvs/ncc_cost.h"
#include "src/mvs/patch_match.h"

using namespace colmap_lidar;

namespace {

double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

// BENCH_SET="name=value,..." overrides options (experiments); unknown
// names abort.
void ApplyOverrides(const char* text, LidarPatchMatchOptions* o) {
  if (text == nullptr) return;
  std::string rest = text;
  while (!rest.empty()) {
    const size_t comma = rest.find(',');
    const std::string item = rest.substr(0, comma);
    rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
    const size_t eq = item.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = item.substr(0, eq);
    const double v = std::stod(item.substr(eq + 1));
    if (key == "lidar_prior_weight") o->lidar_prior_weight = v;
    else if (key == "lidar_prior_tolerance") o->lidar_prior_tolerance = v;
    else if (key == "far_propagation") o->far_propagation = v != 0;
    else if (key == "window_radius") o->window_radius = static_cast<int>(v);
    else if (key == "window_step") o->window_step = static_cast<int>(v);
    else if (key == "sigma_color") o->sigma_color = v;
    else if (key == "sigma_spatial") o->sigma_spatial = v;
    else if (key == "best_views_fraction") o->best_views_fraction = v;
    else if (key == "filter_max_cost") o->filter_max_cost = v;
    else {
      std::cerr << "unknown BENCH_SET option " << key << "\n";
      std::exit(1);
    }
  }
}

struct FilteredStats {
  double completeness = 0.0;  // Valid after filtering / pixels with GT.
  double accuracy = 0.0;      // Within 5 cm / valid pixels with GT.
  double share = 0.0;         // Within 5 cm / pixels with GT.
};

FilteredStats Filtered(PlaneMap map, const std::vector<float>& gt,
                       const std::vector<float>& prior_depth,
                       const LidarPatchMatchOptions& options) {
  if (!prior_depth.empty() && options.lidar_prior_weight > 0) {
    FilterByCostOrPrior(static_cast<float>(options.filter_max_cost),
                        prior_depth,
                        static_cast<float>(options.lidar_prior_tolerance), &map);
  } else {
    FilterByCost(static_cast<float>(options.filter_max_cost), &map);
  }
  size_t num_gt = 0, num_valid = 0, num_good = 0;
  for (size_t i = 0; i < gt.size(); ++i) {
    if (!(gt[i] > 0)) continue;
    ++num_gt;
    if (!(map.depth[i] > 0)) continue;
    ++num_valid;
    num_good += std::abs(map.depth[i] - gt[i]) <= 0.05f;
  }
  FilteredStats stats;
  if (num_gt > 0) {
    stats.completeness = static_cast<double>(num_valid) / num_gt;
    stats.share = static_cast<double>(num_good) / num_gt;
  }
  if (num_valid > 0) stats.accuracy = static_cast<double>(num_good) / num_valid;
  return stats;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: bench_patch_match DATASET [NUM_REFS] [NUM_ITERATIONS]\n";
    return 1;
  }
  const std::string dataset = argv[1];
  const int num_refs = argc > 2 ? std::stoi(argv[2]) : 3;
  const int num_iterations = argc > 3 ? std::stoi(argv[3]) : 6;
  const RigCalibration calibration =
      ReadCalibration(JoinPaths(dataset, "calibration.yaml"));
  const std::vector<FramePose> poses =
      ReadPoses(JoinPaths(dataset, "poses_gt.txt"));
  const int n = static_cast<int>(poses.size());
  std::vector<MvsView> views;
  std::vector<LidarScan> scans(n);
  std::vector<LidarFusionInput> inputs;
  for (int i = 0; i < n; ++i) {
    Image image;
    image.name = poses[i].frame;
    image.cam_from_world = poses[i].world_from_cam.Inverse();
    views.push_back(LoadMvsView(
        JoinPaths(dataset, "images/" + poses[i].frame + ".png"),
        calibration.camera, image, -1));
    scans[i] = ReadLidarScan(JoinPaths(dataset, "lidar/" + poses[i].frame + ".ply"));
    // p_world = world_from_cam * cam_from_lidar * p_lidar.
    inputs.push_back({static_cast<uint32_t>(i), &scans[i],
                      poses[i].world_from_cam * calibration.cam_from_lidar});
  }
  const FusedLidarCloud lidar = FuseLidarScans(inputs, LidarFusionOptions());
  std::printf("%d frames %dx%d, %zu fused LIDAR voxels\n", n, views[0].width,
              views[0].height, lidar.size());

  LidarPatchMatchOptions options;
  options.num_threads = 2;
  ApplyOverrides(getenv("BENCH_SET"), &options);
  std::vector<std::vector<double>> lidar_shares, random_shares;
  FilteredStats lidar_filtered, random_filtered;
  double total_seconds = 0.0;
  double total_cpu_seconds = 0.0;
  int num_timed = 0;
  for (int k = 0; k < num_refs; ++k) {
    const int ref = std::min(n - 1, 2 + k * std::max(1, (n - 4) / std::max(1, num_refs)));
    const DepthMap gt_map = DepthMap::Read(JoinPaths(
        dataset, "ground_truth/depth_maps/" + poses[ref].frame + ".bin"));
    std::vector<float> gt(gt_map.GetMat().GetData());
    if (getenv("BENCH_DEBUG")) {
      std::vector<float> errors;
      for (const Eigen::Vector3f& p : scans[ref].points) {
        const Eigen::Vector3d in_cam = calibration.cam_from_lidar * p.cast<double>();
        if (in_cam.z() < 0.5) continue;
        const Eigen::Vector3d uv = calibration.camera.CalibrationMatrix() * in_cam / in_cam.z();
        const int c = std::lround(uv.x()), r = std::lround(uv.y());
        if (c < 0 || r < 0 || c >= views[ref].width || r >= views[ref].height) continue;
        const float g = gt[r * views[ref].width + c];
        if (g > 0) errors.push_back(std::abs(g - in_cam.z()));
      }
      std::sort(errors.begin(), errors.end());
      if (!errors.empty()) std::printf("own scan: %zu pts, median |z - gt| %.3f\n", errors.size(), errors[errors.size()/2]);
    }
    std::vector<const MvsView*> srcs;
    for (int d = 1; srcs.size() < 5 && d < n; ++d) {
      if (ref - d >= 0) srcs.push_back(&views[ref - d]);
      if (srcs.size() < 5 && ref + d < n) srcs.push_back(&views[ref + d]);
    }
    for (const std::string init : {"lidar", "random"}) {
      // BENCH_ONLY=lidar|random skips the other run (experiments).
      if (getenv("BENCH_ONLY") && init != getenv("BENCH_ONLY")) {
        (init == "lidar" ? lidar_shares : random_shares)
            .push_back(std::vector<double>(num_iterations + 1, 0.0));
        continue;
      }
      options.init = init;
      // The depth range comes from the LIDAR for both (no features here).
      LidarPatchMatchOptions range_options = options;
      range_options.init = "lidar";
      ReferenceInit reference = InitializeReference(
          views[ref], {}, &lidar, static_cast<int>(ref), range_options);
      if (init == "random") reference.state = PlaneMap(views[ref].width, views[ref].height);
      const PatchCostComputer cost(views[ref], srcs, options);
      PatchMatchProblem problem;
      problem.cost = &cost;
      problem.depth_min = reference.depth_min;
      problem.depth_max = reference.depth_max;
      if (init == "lidar" && !reference.prior_depth.empty()) {
        problem.prior_depth = &reference.prior_depth;
      }
      std::vector<double> shares;
      if (init == "random") {
        RandomizePlaneMap(views[ref], problem.depth_min, problem.depth_max, 1,
                          &reference.state);
      }
      shares.push_back(ShareWithinTolerance(reference.state.depth, gt, 0.05));
      if (getenv("BENCH_DEBUG")) {
        std::vector<float> errors, truths;
        for (size_t i = 0; i < gt.size(); ++i) {
          if (gt[i] > 0 && reference.state.depth[i] > 0) {
            errors.push_back(std::abs(reference.state.depth[i] - gt[i]));
            truths.push_back(gt[i]);
          }
        }
        std::sort(errors.begin(), errors.end());
        std::sort(truths.begin(), truths.end());
        if (!errors.empty()) {
          std::printf("%s init: %zu px, median |error| %.3f m, median depth %.2f m\n",
                      init.c_str(), errors.size(), errors[errors.size() / 2],
                      truths[truths.size() / 2]);
        }
      }
      const std::vector<float> initial_depth = reference.state.depth;
      const auto start = std::chrono::steady_clock::now();
      const double cpu_start = CpuSeconds();
      double seconds_at_5 = 0.0;
      double cpu_seconds_at_5 = 0.0;
      RunPatchMatch(problem, options, num_iterations, 1, &reference.state,
                    [&](int iteration, const PlaneMap& map) {
                      if (iteration == 4) {
                        seconds_at_5 = std::chrono::duration<double>(
                                           std::chrono::steady_clock::now() - start)
                                           .count();
                        cpu_seconds_at_5 = CpuSeconds() - cpu_start;
                      }
                      shares.push_back(ShareWithinTolerance(map.depth, gt, 0.05));
                    });
      if (getenv("BENCH_DEBUG") && init == "lidar") {
        // Reference-window standard deviation of the pixels PatchMatch moved
        // away from a correct initial depth, against all pixels with GT.
        std::vector<float> lost_std, all_std, lost_cost;
        RefPatch patch;
        for (int row = 0; row < views[ref].height; ++row) {
          for (int col = 0; col < views[ref].width; ++col) {
            const size_t i = reference.state.Index(row, col);
            if (!(gt[i] > 0)) continue;
            cost.PrepareRefPatch(row, col, &patch);
            const float sd = std::sqrt(std::max(0.0f, patch.variance));
            all_std.push_back(sd);
            if (std::abs(initial_depth[i] - gt[i]) <= 0.05f &&
                !(std::abs(reference.state.depth[i] - gt[i]) <= 0.05f)) {
              lost_std.push_back(sd);
              lost_cost.push_back(reference.state.cost[i]);
            }
          }
        }
        auto pct = [](std::vector<float> v, double f) {
          if (v.empty()) return 0.0f;
          std::sort(v.begin(), v.end());
          return v[std::min(v.size() - 1, static_cast<size_t>(f * v.size()))];
        };
        std::printf("lost %zu px: window std p25/50/75 %.4f %.4f %.4f, cost "
                    "p50 %.3f; all px std p10/25/50 %.4f %.4f %.4f\n",
                    lost_std.size(), pct(lost_std, 0.25), pct(lost_std, 0.5),
                    pct(lost_std, 0.75), pct(lost_cost, 0.5), pct(all_std, 0.1),
                    pct(all_std, 0.25), pct(all_std, 0.5));
      }
      const FilteredStats filtered =
          Filtered(reference.state, gt,
                   init == "lidar" ? reference.prior_depth : std::vector<float>(),
                   options);
      FilteredStats& sum = init == "lidar" ? lidar_filtered : random_filtered;
      sum.completeness += filtered.completeness / num_refs;
      sum.accuracy += filtered.accuracy / num_refs;
      sum.share += filtered.share / num_refs;
      if (init == "lidar") {
        lidar_shares.push_back(shares);
        if (seconds_at_5 > 0) {
          total_seconds += seconds_at_5;
          total_cpu_seconds += cpu_seconds_at_5;
          ++num_timed;
        }
      } else {
        random_shares.push_back(shares);
      }
    }
    std::printf("ref %s (%zu sources)\n", poses[ref].frame.c_str(), srcs.size());
  }
  std::printf("\nShare of pixels within 5 cm of the ground truth (mean over %d refs)\n",
              num_refs);
  std::printf("%-10s %-12s %-12s %-8s\n", "iteration", "lidar-init", "random-init",
              "ratio");
  for (int it = 0; it <= num_iterations; ++it) {
    double l = 0, r = 0;
    for (int k = 0; k < num_refs; ++k) {
      l += lidar_shares[k][it] / num_refs;
      r += random_shares[k][it] / num_refs;
    }
    std::printf("%-10d %-12.3f %-12.3f %-8.2f\n", it, l, r, r > 0 ? l / r : 0.0);
  }
  std::printf("\nAfter %d iterations and the photometric filter (cost <= %.2f; "
              "a filtered pixel counts as a failure in the share)\n",
              num_iterations, options.filter_max_cost);
  std::printf("%-12s %-12s %-12s %-12s\n", "init", "completeness", "accuracy",
              "share");
  std::printf("%-12s %-12.3f %-12.3f %-12.3f\n", "lidar",
              lidar_filtered.completeness, lidar_filtered.accuracy,
              lidar_filtered.share);
  std::printf("%-12s %-12.3f %-12.3f %-12.3f\n", "random",
              random_filtered.completeness, random_filtered.accuracy,
              random_filtered.share);
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  if (num_timed > 0) {
    std::printf("\nPhotometric PatchMatch, 5 iterations, 5 sources, 2 threads: "
                "%.2f s per %dx%d image\n",
                total_seconds / num_timed, views[0].width, views[0].height);
    std::printf("  CPU time %.2f s per image (= wall time on 2 idle cores x 2)\n",
                total_cpu_seconds / num_timed);
  }
  std::printf("Peak memory (whole benchmark, all %d images and scans loaded): %.0f MB\n",
              n, usage.ru_maxrss / 1024.0);
  return 0;
}
