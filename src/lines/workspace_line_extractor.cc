#include "src/lines/workspace_line_extractor.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <thread>

#include <opencv2/imgcodecs.hpp>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "src/lidar/scan_io.h"
#include "src/lines/debug_overlay.h"

namespace colmap_lidar {
namespace {

struct Job {
  DatabaseImage image;
  Camera camera;
  LidarScanRecord scan;
};

std::string ResolveScanPath(const std::string& database_path,
                            const std::string& scan_path) {
  const std::filesystem::path path(scan_path);
  if (path.is_absolute()) {
    return scan_path;
  }
  return (std::filesystem::path(database_path).parent_path() / path)
      .lexically_normal()
      .string();
}

}  // namespace

LineSegmentRecord ToLineSegmentRecord(const ViewLineSegment& segment) {
  LineSegmentRecord record;
  record.start2D = segment.segment2D.start;
  record.end2D = segment.segment2D.end;
  record.start3D_in_cam = segment.start3D_in_cam;
  record.end3D_in_cam = segment.end3D_in_cam;
  record.num_inliers = static_cast<uint32_t>(segment.NumInliers());
  record.descriptor = segment.descriptor;
  return record;
}

std::string WorkspaceLineExtractionSummary::Format() const {
  std::ostringstream out;
  const int num_processed = num_images - num_images_without_scan;
  out << "Line extraction: " << num_processed << " images";
  if (num_images_without_scan > 0) {
    out << " (" << num_images_without_scan << " without LIDAR scan skipped)";
  }
  out << "\n  3D segments: " << num_segments << " in total, "
      << (num_processed > 0 ? static_cast<double>(num_segments) / num_processed
                            : 0.0)
      << " per image (min " << min_segments_per_image << ", max "
      << max_segments_per_image << ")"
      << "\n  2D segments lifted to 3D: " << num_lifted_segments << " of "
      << num_lsd_segments << " ("
      << (num_lsd_segments > 0
              ? 100.0 * num_lifted_segments / num_lsd_segments
              : 0.0)
      << "%)"
      << "\n  Time: " << mean_ms_per_image << " ms per image";
  return out.str();
}

WorkspaceLineExtractionSummary ExtractWorkspaceLines(
    const std::string& database_path, const std::string& image_path,
    const std::vector<std::string>& image_names,
    const LineExtractionOptions& options, const std::string& debug_path) {
  THROW_CHECK(options.Check(), "Invalid line extraction options");
  CheckFileExists(database_path, "database");
  CheckDirExists(image_path, "image folder");
  Database database(database_path);

  WorkspaceLineExtractionSummary summary;
  std::vector<Job> jobs;
  auto add_job = [&](const DatabaseImage& image) {
    const std::optional<LidarScanRecord> scan =
        database.ReadLidarScan(image.image_id);
    if (!scan) {
      return false;
    }
    const std::optional<Camera> camera = database.ReadCamera(image.camera_id);
    THROW_CHECK(camera.has_value(), "Image " << image.name << " in "
                                             << database_path
                                             << " refers to missing camera "
                                             << image.camera_id);
    jobs.push_back({image, *camera, *scan});
    return true;
  };
  if (image_names.empty()) {
    for (const DatabaseImage& image : database.ReadAllImages()) {
      ++summary.num_images;
      if (!add_job(image)) {
        ++summary.num_images_without_scan;
        LOG(WARNING) << "Image " << image.name
                     << " has no LIDAR scan; skipped";
      }
    }
  } else {
    for (const std::string& name : image_names) {
      const std::optional<DatabaseImage> image =
          database.ReadImageWithName(name);
      THROW_CHECK(image.has_value(),
                  "Image " << name << " is not in " << database_path);
      THROW_CHECK(add_job(*image), "Image " << name << " has no LIDAR scan in "
                                            << database_path);
      ++summary.num_images;
    }
  }
  if (!debug_path.empty()) {
    CreateDirIfNotExists(debug_path);
  }

  const int num_threads = std::max(
      1, std::min<int>(options.num_threads > 0
                           ? options.num_threads
                           : static_cast<int>(std::thread::hardware_concurrency()),
                       static_cast<int>(jobs.size())));
  std::atomic<size_t> next_job(0);
  std::mutex mutex;  // Guards the database, the summary and the log order.
  std::exception_ptr error;
  size_t num_done = 0;
  double total_ms = 0.0;
  bool first_image = true;

  auto worker = [&]() {
    while (true) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (error) {
          return;
        }
      }
      const size_t job_idx = next_job++;
      if (job_idx >= jobs.size()) {
        return;
      }
      const Job& job = jobs[job_idx];
      try {
        const std::string image_file = JoinPaths(image_path, job.image.name);
        const cv::Mat image = cv::imread(image_file, cv::IMREAD_GRAYSCALE);
        THROW_CHECK(!image.empty(), "Cannot read image " << image_file);
        const LidarScan scan =
            ReadLidarScan(ResolveScanPath(database_path, job.scan.path));
        const ViewLines lines = ExtractViewLines(
            image, scan, job.camera, job.scan.cam_from_lidar, options);
        std::vector<LineSegmentRecord> records;
        records.reserve(lines.segments.size());
        for (const ViewLineSegment& segment : lines.segments) {
          records.push_back(ToLineSegmentRecord(segment));
        }
        if (!debug_path.empty()) {
          std::string file_name = job.image.name;
          std::replace(file_name.begin(), file_name.end(), '/', '_');
          const std::string stem =
              JoinPaths(debug_path,
                        std::filesystem::path(file_name).stem().string());
          WriteLineOverlay(stem + ".png",
                           DrawLineOverlay(image, lines, job.camera));
          WriteJsonFile(stem + ".json",
                        LineOutcomesToJson(job.image.name, lines));
        }
        std::lock_guard<std::mutex> lock(mutex);
        WriteLineSegments(&database, job.image.image_id, records);
        ++num_done;
        const int num_segments = static_cast<int>(lines.segments.size());
        summary.num_lsd_segments += lines.num_lsd_segments;
        summary.num_lifted_segments += lines.num_lifted_segments;
        summary.num_segments += num_segments;
        summary.min_segments_per_image =
            first_image ? num_segments
                        : std::min(summary.min_segments_per_image, num_segments);
        summary.max_segments_per_image =
            std::max(summary.max_segments_per_image, num_segments);
        first_image = false;
        total_ms += lines.timings.TotalMs();
        LOG(INFO) << "Lines [" << num_done << "/" << jobs.size() << "] "
                  << job.image.name << ": " << num_segments
                  << " 3D segments from " << lines.num_lsd_segments
                  << " 2D segments, " << lines.visible_edge_point_idxs.size()
                  << " visible edge points"
                  << (options.planes.enabled
                          ? ", " + std::to_string(lines.num_plane_lifted_segments) +
                                " lifted by planes (range noise " +
                                std::to_string(lines.range_noise_m) + " m)"
                          : std::string())
                  << ", " << static_cast<int>(lines.timings.TotalMs()) << " ms";
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) {
          error = std::current_exception();
        }
        return;
      }
    }
  };
  // All images' segments land together: an image or scan that fails leaves
  // the database as it was, not half of the workspace re-extracted.
  DatabaseTransaction transaction(&database);
  std::vector<std::thread> threads;
  for (int i = 0; i < num_threads; ++i) {
    threads.emplace_back(worker);
  }
  for (std::thread& thread : threads) {
    thread.join();
  }
  if (error) {
    std::rethrow_exception(error);
  }
  transaction.Commit();
  summary.mean_ms_per_image = num_done > 0 ? total_ms / num_done : 0.0;
  return summary;
}

}  // namespace colmap_lidar
