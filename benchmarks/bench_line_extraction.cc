// Per-frame time of the line detection module (paper section III-B) on one
// core: the whole ExtractViewLines pipeline and its stages, on a synthetic
// 848x480 image + OS1-64-like scan (64 x 1024 beams, fixed seed) and, when
// the shared KITTI sample is found, on a real KITTI frame (1242x375 +
// HDL-64E, ~120k points). Target: <= 100 ms per synthetic frame.
//
//   build/benchmarks/bench_line_extraction [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "colmap_ext/util/file.h"
#include "src/dataset/kitti_raw.h"
#include "src/lidar/scan_io.h"
#include "src/lines/lbd_descriptor.h"
#include "src/lines/line_extractor.h"
#include "src/lines/synthetic_view.h"

namespace colmap_lidar {
namespace {

struct Frame {
  cv::Mat image;
  LidarScan scan;
  Camera camera;
  Rigid3d cam_from_lidar;
};

const Frame& SyntheticFrame() {
  static const Frame* frame = [] {
    SyntheticViewOptions options;  // 848x480, 64 x 1024 beams
    options.boxes = DefaultSyntheticBoxes();
    options.paint_stripe = true;
    options.range_noise = 0.01;
    options.seed = 7;
    const SyntheticView view = MakeSyntheticView(options);
    return new Frame{view.image, view.scan, view.camera, view.cam_from_lidar};
  }();
  return *frame;
}

// KITTI raw 2011_09_26 frame 0 of camera 02 with the sample's calibration
// (LoadKittiRawRecording), or nullptr when the sample is not there.
const Frame* KittiFrame() {
  static const Frame* frame = []() -> Frame* {
    const char* shared = std::getenv("COLMAP_LIDAR_SHARED_DIR");
    const std::string dir =
        JoinPaths(shared != nullptr ? shared : COLMAP_LIDAR_DEFAULT_SHARED_DIR,
                  "data/kitti_raw_2011_09_26_sample");
    if (!ExistsDir(dir)) {
      return nullptr;
    }
    const Recording recording = LoadKittiRawRecording(dir, 2);
    auto* kitti = new Frame;
    kitti->image =
        cv::imread(recording.frames.at(0).image_path, cv::IMREAD_GRAYSCALE);
    kitti->scan = ReadLidarScan(recording.frames.at(0).scan_path);
    kitti->camera = recording.calibration.camera;
    kitti->cam_from_lidar = recording.calibration.cam_from_lidar;
    return kitti;
  }();
  return frame;
}

void RunPipeline(benchmark::State& state, const Frame& frame) {
  cv::setNumThreads(1);
  const LineExtractionOptions options;
  LineExtractionTimings sum;
  size_t num_segments = 0;
  for (auto _ : state) {
    const ViewLines lines = ExtractViewLines(frame.image, frame.scan,
                                             frame.camera, frame.cam_from_lidar,
                                             options);
    benchmark::DoNotOptimize(lines.segments.data());
    num_segments = lines.segments.size();
    sum.lsd_ms += lines.timings.lsd_ms;
    sum.edges_ms += lines.timings.edges_ms;
    sum.projection_ms += lines.timings.projection_ms;
    sum.association_ms += lines.timings.association_ms;
    sum.fusion_ms += lines.timings.fusion_ms;
    sum.descriptor_ms += lines.timings.descriptor_ms;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["segments"] = static_cast<double>(num_segments);
  state.counters["points"] = static_cast<double>(frame.scan.size());
  state.counters["lsd_ms"] = sum.lsd_ms / n;
  state.counters["edges_ms"] = sum.edges_ms / n;
  state.counters["proj_ms"] = sum.projection_ms / n;
  state.counters["assoc_ms"] = sum.association_ms / n;
  state.counters["fusion_ms"] = sum.fusion_ms / n;
  state.counters["lbd_ms"] = sum.descriptor_ms / n;
}

void BM_ExtractViewLines_Synthetic848x480_OS1_64(benchmark::State& state) {
  RunPipeline(state, SyntheticFrame());
}
BENCHMARK(BM_ExtractViewLines_Synthetic848x480_OS1_64)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

void BM_ExtractViewLines_Kitti(benchmark::State& state) {
  const Frame* frame = KittiFrame();
  if (frame == nullptr) {
    state.SkipWithError("KITTI sample not found (COLMAP_LIDAR_SHARED_DIR)");
    for (auto _ : state) {
    }
    return;
  }
  RunPipeline(state, *frame);
}
BENCHMARK(BM_ExtractViewLines_Kitti)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_Lsd_Synthetic848x480(benchmark::State& state) {
  cv::setNumThreads(1);
  const Frame& frame = SyntheticFrame();
  for (auto _ : state) {
    benchmark::DoNotOptimize(DetectLineSegments(frame.image, LsdOptions()));
  }
}
BENCHMARK(BM_Lsd_Synthetic848x480)->Unit(benchmark::kMillisecond);

void BM_LidarEdges_OS1_64(benchmark::State& state) {
  const Frame& frame = SyntheticFrame();
  for (auto _ : state) {
    benchmark::DoNotOptimize(DetectLidarEdges(frame.scan, LidarEdgeOptions()));
  }
}
BENCHMARK(BM_LidarEdges_OS1_64)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace colmap_lidar

BENCHMARK_MAIN();
