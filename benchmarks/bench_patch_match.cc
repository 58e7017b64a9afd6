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
#include "src/mvs/mvs_test_scene.h"
#include "src/mvs/ncc_cost.h"
#include "src/mvs/patch_match.h"

using namespace colmap_lidar;

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
  std::vector<std::vector<double>> lidar_shares, random_shares;
  double total_seconds = 0.0;
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
      options.init = init;
      // The depth range comes from the LIDAR for both (no features here).
      LidarPatchMatchOptions range_options = options;
      range_options.init = "lidar";
      ReferenceInit reference =
          InitializeReference(views[ref], {}, &lidar, range_options);
      if (init == "random") reference.state = PlaneMap(views[ref].width, views[ref].height);
      const PatchCostComputer cost(views[ref], srcs, options);
      PatchMatchProblem problem;
      problem.cost = &cost;
      problem.depth_min = reference.depth_min;
      problem.depth_max = reference.depth_max;
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
      const auto start = std::chrono::steady_clock::now();
      double seconds_at_5 = 0.0;
      RunPatchMatch(problem, options, num_iterations, 1, &reference.state,
                    [&](int iteration, const PlaneMap& map) {
                      if (iteration == 4) {
                        seconds_at_5 = std::chrono::duration<double>(
                                           std::chrono::steady_clock::now() - start)
                                           .count();
                      }
                      shares.push_back(ShareWithinTolerance(map.depth, gt, 0.05));
                    });
      if (init == "lidar") {
        lidar_shares.push_back(shares);
        if (seconds_at_5 > 0) {
          total_seconds += seconds_at_5;
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
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  if (num_timed > 0) {
    std::printf("\nPhotometric PatchMatch, 5 iterations, 5 sources, 2 threads: "
                "%.2f s per %dx%d image\n",
                total_seconds / num_timed, views[0].width, views[0].height);
  }
  std::printf("Peak memory (whole benchmark, all %d images and scans loaded): %.0f MB\n",
              n, usage.ru_maxrss / 1024.0);
  return 0;
}
