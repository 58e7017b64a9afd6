// Per-frame time of the line detection module (paper section III-B) on one
// core: the whole ExtractViewLines pipeline and its stages, on
//  - a frame of the quad walk as `colmap-lidar synthesize` renders it
//    (848x480, OS1-64: 64 x 1024 beams, ~65 k points; the cell
//    quad_os64_848 of the benchmark matrix), the frame issue 15's target
//    is set on: <= 50 ms;
//  - a synthetic box view (848x480 image + 64 x 1024 beams, fixed seed);
//  - when the shared KITTI sample is found, a real KITTI frame (1242x375 +
//    HDL-64E, ~120k points).
//
//   build/benchmarks/bench_line_extraction [--benchmark_filter=...]
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "colmap_ext/util/file.h"
#include "src/dataset/calibration.h"
#include "src/dataset/kitti_raw.h"
#include "src/lidar/scan_io.h"
#include "src/lines/lbd_descriptor.h"
#include "src/lines/line_extractor.h"
#include "src/lines/synthetic_view.h"
#include "src/synth/synthesize.h"
#include "src/synth/test_recordings.h"

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

// Frame 1 of a 3-frame quad walk at 848x480 with the synthesizer's
// defaults otherwise (OS1-64, supersampled image), written into a
// temporary folder that is removed once the frame is loaded.
const Frame& QuadFrame() {
  static const Frame* frame = [] {
    SynthesisOptions options = QuickTestRecording(3, 0.1, 848, 480);
    options.supersampling = SynthesisOptions().supersampling;
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() /
        ("bench_line_extraction_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    SynthesizeDataset(options, dir.string());
    const RigCalibration calibration =
        ReadCalibration((dir / "calibration.yaml").string());
    auto* quad = new Frame;
    quad->image =
        cv::imread((dir / "images" / "000001.png").string(), cv::IMREAD_COLOR);
    quad->scan = ReadLidarScan((dir / "lidar" / "000001.ply").string());
    quad->camera = calibration.camera;
    quad->cam_from_lidar = calibration.cam_from_lidar;
    std::filesystem::remove_all(dir);
    return quad;
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
    sum.noise_ms += lines.timings.noise_ms;
    sum.association_ms += lines.timings.association_ms;
    sum.planes_ms += lines.timings.planes_ms;
    sum.fusion_ms += lines.timings.fusion_ms;
    sum.descriptor_ms += lines.timings.descriptor_ms;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["segments"] = static_cast<double>(num_segments);
  state.counters["points"] = static_cast<double>(frame.scan.size());
  state.counters["lsd_ms"] = sum.lsd_ms / n;
  state.counters["edges_ms"] = sum.edges_ms / n;
  state.counters["proj_ms"] = sum.projection_ms / n;
  state.counters["noise_ms"] = sum.noise_ms / n;
  state.counters["assoc_ms"] = sum.association_ms / n;
  state.counters["planes_ms"] = sum.planes_ms / n;
  state.counters["fusion_ms"] = sum.fusion_ms / n;
  state.counters["lbd_ms"] = sum.descriptor_ms / n;
}

void BM_ExtractViewLines_Quad848x480_OS1_64(benchmark::State& state) {
  RunPipeline(state, QuadFrame());
}
BENCHMARK(BM_ExtractViewLines_Quad848x480_OS1_64)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

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
