#include "src/lines/workspace_line_extractor.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include <opencv2/imgcodecs.hpp>

#include "colmap_ext/util/byte_stream.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/process_group.h"
#include "src/lidar/scan_io.h"
#include "src/lines/debug_overlay.h"

namespace colmap_lidar {
namespace {

struct Job {
  DatabaseImage image;
  Camera camera;
  LidarScanRecord scan;
};

// Images to process with their camera and scan; counts the database's
// images (and those without a scan) into `summary`.
std::vector<Job> ReadJobs(const Database& database,
                          const std::string& database_path,
                          const std::vector<std::string>& image_names,
                          WorkspaceLineExtractionSummary* summary) {
  std::vector<Job> jobs;
  auto add_job = [&](const DatabaseImage& image) {
    const std::optional<LidarScanRecord> scan =
        database.ReadLidarScan(image.image_id);
    if (!scan) {
      return false;
    }
    const std::optional<Camera> camera = database.ReadCamera(image.camera_id);
    THROW_CHECK(camera.has_value(),
                "Image " << image.name << " in " << database_path
                         << " refers to missing camera " << image.camera_id);
    jobs.push_back({image, *camera, *scan});
    return true;
  };
  if (image_names.empty()) {
    for (const DatabaseImage& image : database.ReadAllImages()) {
      ++summary->num_images;
      if (!add_job(image)) {
        ++summary->num_images_without_scan;
        LOG(WARNING) << "Image " << image.name << " has no LIDAR scan; skipped";
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
      ++summary->num_images;
    }
  }
  return jobs;
}

// What a rank sends rank 0 per image.
struct ImageResult {
  image_t image_id = kInvalidImageId;
  int num_lsd_segments = 0;
  int num_lifted_segments = 0;
  double total_ms = 0.0;
  std::vector<LineSegmentRecord> records;
};

std::string SerializeJobs(const std::vector<Job>& jobs) {
  std::string bytes;
  ByteWriter writer(&bytes);
  writer.Value<uint64_t>(jobs.size());
  for (const Job& job : jobs) {
    writer.Value(job.image.image_id);
    writer.String(job.image.name);
    writer.Value(job.image.camera_id);
    writer.Value(job.camera.camera_id);
    writer.Value(job.camera.model_id);
    writer.Value(job.camera.width);
    writer.Value(job.camera.height);
    writer.Value<uint64_t>(job.camera.params.size());
    for (const double param : job.camera.params) writer.Value(param);
    writer.String(job.scan.path);
    writer.Value(job.scan.num_points);
    const Eigen::Vector4d q = job.scan.cam_from_lidar.rotation.coeffs();
    for (int i = 0; i < 4; ++i) writer.Value(q(i));
    for (int i = 0; i < 3; ++i) {
      writer.Value(job.scan.cam_from_lidar.translation(i));
    }
  }
  return bytes;
}

std::vector<Job> DeserializeJobs(const std::string& bytes) {
  ByteReader reader(bytes);
  std::vector<Job> jobs(reader.Value<uint64_t>());
  for (Job& job : jobs) {
    job.image.image_id = reader.Value<image_t>();
    job.image.name = reader.String();
    job.image.camera_id = reader.Value<camera_t>();
    job.camera.camera_id = reader.Value<camera_t>();
    job.camera.model_id = reader.Value<CameraModelId>();
    job.camera.width = reader.Value<uint64_t>();
    job.camera.height = reader.Value<uint64_t>();
    job.camera.params.resize(reader.Value<uint64_t>());
    for (double& param : job.camera.params) param = reader.Value<double>();
    job.scan.image_id = job.image.image_id;
    job.scan.path = reader.String();
    job.scan.num_points = reader.Value<uint64_t>();
    Eigen::Vector4d q;
    for (int i = 0; i < 4; ++i) q(i) = reader.Value<double>();
    job.scan.cam_from_lidar.rotation.coeffs() = q;
    for (int i = 0; i < 3; ++i) {
      job.scan.cam_from_lidar.translation(i) = reader.Value<double>();
    }
  }
  THROW_CHECK(reader.AtEnd(), "trailing bytes in the jobs from rank 0");
  return jobs;
}

void AppendImageResult(const ImageResult& result, std::string* bytes) {
  ByteWriter writer(bytes);
  writer.Value(result.image_id);
  writer.Value(result.num_lsd_segments);
  writer.Value(result.num_lifted_segments);
  writer.Value(result.total_ms);
  writer.Value<uint64_t>(result.records.size());
  for (const LineSegmentRecord& record : result.records) {
    for (int i = 0; i < 2; ++i) writer.Value(record.start2D(i));
    for (int i = 0; i < 2; ++i) writer.Value(record.end2D(i));
    for (int i = 0; i < 3; ++i) writer.Value(record.start3D_in_cam(i));
    for (int i = 0; i < 3; ++i) writer.Value(record.end3D_in_cam(i));
    writer.Value(record.num_inliers);
    writer.Value(record.descriptor);
  }
}

std::vector<ImageResult> ParseImageResults(const std::string& bytes) {
  ByteReader reader(bytes);
  std::vector<ImageResult> results;
  while (!reader.AtEnd()) {
    ImageResult& result = results.emplace_back();
    result.image_id = reader.Value<image_t>();
    result.num_lsd_segments = reader.Value<int>();
    result.num_lifted_segments = reader.Value<int>();
    result.total_ms = reader.Value<double>();
    result.records.resize(reader.Value<uint64_t>());
    for (LineSegmentRecord& record : result.records) {
      for (int i = 0; i < 2; ++i) record.start2D(i) = reader.Value<double>();
      for (int i = 0; i < 2; ++i) record.end2D(i) = reader.Value<double>();
      for (int i = 0; i < 3; ++i) {
        record.start3D_in_cam(i) = reader.Value<double>();
      }
      for (int i = 0; i < 3; ++i) {
        record.end3D_in_cam(i) = reader.Value<double>();
      }
      record.num_inliers = reader.Value<uint32_t>();
      record.descriptor = reader.Value<std::array<uint8_t, 32>>();
    }
  }
  return results;
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
  // Under mpirun only rank 0 opens the database (SQLite's write-ahead log
  // needs shared memory, which ranks on different machines do not share):
  // it sends the others the jobs and receives their segments.
  const ProcessGroup& group = ProcessGroup::World();
  std::optional<Database> database;
  WorkspaceLineExtractionSummary summary;
  std::vector<Job> jobs;
  std::exception_ptr error;
  if (group.IsRoot()) {
    try {
      CheckFileExists(database_path, "database");
      CheckDirExists(image_path, "image folder");
      database.emplace(database_path);
      jobs = ReadJobs(*database, database_path, image_names, &summary);
    } catch (...) {
      error = std::current_exception();
    }
  }
  group.CheckAllOk(error, "line_extractor: reading " + database_path);
  if (group.Distributed()) {
    std::string bytes = group.IsRoot() ? SerializeJobs(jobs) : std::string();
    group.Broadcast(&bytes);
    if (!group.IsRoot()) jobs = DeserializeJobs(bytes);
  }
  std::vector<size_t> my_jobs;
  for (size_t j = 0; j < jobs.size(); ++j) {
    if (group.Owns(j)) my_jobs.push_back(j);
  }
  if (!debug_path.empty()) {
    CreateDirIfNotExists(debug_path);
  }

  const int num_threads = std::max(
      1,
      std::min<int>(options.num_threads > 0
                        ? options.num_threads
                        : static_cast<int>(std::thread::hardware_concurrency()),
                    static_cast<int>(my_jobs.size())));
  std::atomic<size_t> next_job(0);
  // Guards the database, the outbox, the summary and the log order.
  std::mutex mutex;
  size_t num_done = 0;
  double total_ms = 0.0;
  bool first_image = true;
  // The other ranks' results for rank 0 (ImageResult records).
  std::string outbox;
  auto add_to_summary = [&](const ImageResult& result) {
    ++num_done;
    const int num_segments = static_cast<int>(result.records.size());
    summary.num_lsd_segments += result.num_lsd_segments;
    summary.num_lifted_segments += result.num_lifted_segments;
    summary.num_segments += num_segments;
    summary.min_segments_per_image =
        first_image ? num_segments
                    : std::min(summary.min_segments_per_image, num_segments);
    summary.max_segments_per_image =
        std::max(summary.max_segments_per_image, num_segments);
    first_image = false;
    total_ms += result.total_ms;
  };

  auto worker = [&]() {
    while (true) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (error) {
          return;
        }
      }
      const size_t my_job_idx = next_job++;
      if (my_job_idx >= my_jobs.size()) {
        return;
      }
      const Job& job = jobs[my_jobs[my_job_idx]];
      try {
        const std::string image_file = JoinPaths(image_path, job.image.name);
        const cv::Mat image = cv::imread(image_file, cv::IMREAD_GRAYSCALE);
        THROW_CHECK(!image.empty(), "Cannot read image " << image_file);
        const LidarScan scan =
            ReadLidarScan(LidarScanFilePath(database_path, job.scan.path));
        const ViewLines lines = ExtractViewLines(
            image, scan, job.camera, job.scan.cam_from_lidar, options);
        ImageResult result;
        result.image_id = job.image.image_id;
        result.num_lsd_segments = lines.num_lsd_segments;
        result.num_lifted_segments = lines.num_lifted_segments;
        result.total_ms = lines.timings.TotalMs();
        result.records.reserve(lines.segments.size());
        for (const ViewLineSegment& segment : lines.segments) {
          result.records.push_back(ToLineSegmentRecord(segment));
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
        if (database) {
          WriteLineSegments(&*database, job.image.image_id, result.records);
        } else {
          AppendImageResult(result, &outbox);
        }
        add_to_summary(result);
        LOG(INFO)
            << "Lines [" << num_done << "/" << my_jobs.size() << "] "
            << job.image.name << ": " << result.records.size()
            << " 3D segments from " << lines.num_lsd_segments
            << " 2D segments, " << lines.visible_edge_point_idxs.size()
            << " visible edge points"
            << (options.planes.enabled
                    ? ", " + std::to_string(lines.num_plane_lifted_segments) +
                          " lifted by planes (range noise " +
                          std::to_string(lines.range_noise_m) + " m)"
                    : std::string())
            << ", " << static_cast<int>(result.total_ms) << " ms";
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) {
          error = std::current_exception();
        }
        return;
      }
    }
  };
  // All images' segments land together: an image or scan that fails (on
  // any rank) leaves the database as it was, not half of the workspace
  // re-extracted.
  std::optional<DatabaseTransaction> transaction;
  if (database) transaction.emplace(&*database);
  std::vector<std::thread> threads;
  for (int i = 0; i < num_threads; ++i) {
    threads.emplace_back(worker);
  }
  for (std::thread& thread : threads) {
    thread.join();
  }
  group.CheckAllOk(error, "line_extractor");
  const std::vector<std::string> parts = group.GatherToRoot(outbox);
  if (database) {
    for (size_t rank = 1; rank < parts.size(); ++rank) {
      const std::vector<ImageResult> results = ParseImageResults(parts[rank]);
      for (const ImageResult& result : results) {
        WriteLineSegments(&*database, result.image_id, result.records);
        add_to_summary(result);
      }
      LOG(INFO) << "Lines of rank " << rank << ": " << results.size()
                << " images";
    }
    transaction->Commit();
  }
  summary.mean_ms_per_image = num_done > 0 ? total_ms / num_done : 0.0;
  return summary;
}

}  // namespace colmap_lidar
