#include "src/matching/matching_view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "colmap_ext/util/logging.h"
#include "src/lidar/scan_io.h"
#include "colmap_ext/util/parallel.h"

namespace colmap_lidar {

LidarDepthGrid::LidarDepthGrid(const std::vector<Eigen::Vector3d>& points_in_cam,
                               const Camera& camera, const int cell_px,
                               const double min_depth)
    : cell_px_(cell_px),
      num_x_(static_cast<int>((camera.width + cell_px - 1) / cell_px)),
      num_y_(static_cast<int>((camera.height + cell_px - 1) / cell_px)),
      depths_(static_cast<size_t>(num_x_) * num_y_,
              std::numeric_limits<float>::infinity()) {
  for (const Eigen::Vector3d& point : points_in_cam) {
    if (!(point.z() > min_depth)) continue;
    const Eigen::Vector2d pixel = camera.ImgFromCam(point);
    if (!(pixel.x() >= 0.0 && pixel.y() >= 0.0 &&
          pixel.x() < static_cast<double>(camera.width) &&
          pixel.y() < static_cast<double>(camera.height))) {
      continue;
    }
    float& depth = depths_[static_cast<int>(pixel.y()) / cell_px_ * num_x_ +
                           static_cast<int>(pixel.x()) / cell_px_];
    depth = std::min(depth, static_cast<float>(point.z()));
  }
}

double LidarDepthGrid::NearestDepth(const Eigen::Vector2d& pixel) const {
  if (depths_.empty() || !(pixel.x() >= 0.0 && pixel.y() >= 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  const int x = static_cast<int>(pixel.x()) / cell_px_;
  const int y = static_cast<int>(pixel.y()) / cell_px_;
  if (x >= num_x_ || y >= num_y_) {
    return std::numeric_limits<double>::infinity();
  }
  return depths_[y * num_x_ + x];
}

void UpdateMatchingViewPose(const Rigid3d& cam_from_world, MatchingView* view) {
  view->cam_from_world = cam_from_world;
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  for (MatchingSegment& segment : view->segments) {
    segment.start_in_world = world_from_cam * segment.start_in_cam;
    segment.end_in_world = world_from_cam * segment.end_in_cam;
  }
}

MatchingView MakeMatchingView(const image_t image_id, const std::string& name,
                              const Camera& camera,
                              const Rigid3d& cam_from_world,
                              const std::vector<LineSegmentRecord>& records) {
  MatchingView view;
  view.image_id = image_id;
  view.name = name;
  view.camera = camera;
  const int num_buckets =
      static_cast<int>(std::ceil(180.0 / MatchingView::kAngleBucketDeg));
  view.angle_buckets.resize(num_buckets);
  for (const LineSegmentRecord& record : records) {
    MatchingSegment segment;
    segment.start2D = record.start2D;
    segment.end2D = record.end2D;
    const Eigen::Vector2d delta = record.end2D - record.start2D;
    const double length = delta.norm();
    segment.direction2D =
        length > 0.0 ? Eigen::Vector2d(delta / length) : Eigen::Vector2d::UnitX();
    const Eigen::Vector2d normal(-segment.direction2D.y(),
                                 segment.direction2D.x());
    segment.line2D = Eigen::Vector3d(normal.x(), normal.y(),
                                     -normal.dot(record.start2D));
    double angle_deg =
        std::atan2(segment.direction2D.y(), segment.direction2D.x()) * 180.0 /
        M_PI;
    if (angle_deg < 0.0) angle_deg += 180.0;
    if (angle_deg >= 180.0) angle_deg -= 180.0;
    segment.angle_deg = angle_deg;
    segment.start_in_cam = record.start3D_in_cam;
    segment.end_in_cam = record.end3D_in_cam;
    segment.descriptor = record.descriptor;
    const int bucket = std::min(
        num_buckets - 1,
        static_cast<int>(angle_deg / MatchingView::kAngleBucketDeg));
    view.angle_buckets[bucket].push_back(static_cast<int>(view.segments.size()));
    view.segments.push_back(segment);
  }
  UpdateMatchingViewPose(cam_from_world, &view);
  return view;
}

std::vector<MatchingView> LoadMatchingViews(
    const Database& database, const Reconstruction& model,
    const LineMatchingOptions& options) {
  struct Job {
    const Image* image = nullptr;
    std::vector<LineSegmentRecord> segments;
    std::optional<LidarScanRecord> scan;
  };
  std::vector<Job> jobs;
  // Database reads stay on this thread (one SQLite connection).
  for (const Image& image : model.images) {
    const std::optional<DatabaseImage> db_image =
        database.ReadImage(image.image_id);
    if (!db_image) {
      LOG(WARNING) << "Model image " << image.image_id << " (" << image.name
                   << ") is not in " << database.path() << "; skipped";
      continue;
    }
    THROW_CHECK(db_image->name == image.name,
                "Model image " << image.image_id << " is named " << image.name
                               << " but " << database.path() << " names it "
                               << db_image->name);
    Job job;
    job.image = &image;
    job.segments = ReadLineSegments(database, image.image_id);
    if (job.segments.empty()) continue;
    if (options.use_lidar_visibility) {
      job.scan = database.ReadLidarScan(image.image_id);
    }
    jobs.push_back(std::move(job));
  }
  if (options.use_lidar_visibility) {
    const size_t num_without_scan =
        std::count_if(jobs.begin(), jobs.end(),
                      [](const Job& job) { return !job.scan.has_value(); });
    if (num_without_scan > 0) {
      LOG(WARNING) << num_without_scan << " of " << jobs.size()
                   << " images have no LIDAR scan in " << database.path()
                   << ": their candidate segments are not tested for "
                      "occlusion";
    }
  }
  std::vector<MatchingView> views(jobs.size());
  ParallelFor(0, static_cast<int>(jobs.size()), options.num_threads,
                      [&](int i) {
    const Job& job = jobs[i];
    const auto camera_it = model.cameras.find(job.image->camera_id);
    THROW_CHECK(camera_it != model.cameras.end(),
                "Camera " << job.image->camera_id << " of image "
                          << job.image->name << " missing in the model");
    views[i] = MakeMatchingView(job.image->image_id, job.image->name,
                                camera_it->second, job.image->cam_from_world,
                                job.segments);
    if (!options.use_lidar_visibility) return;
    if (!job.scan) return;
    const LidarScan scan =
        ReadLidarScan(LidarScanFilePath(database.path(), job.scan->path));
    std::vector<Eigen::Vector3d> points_in_cam;
    points_in_cam.reserve(scan.size());
    for (const Eigen::Vector3f& point : scan.points) {
      points_in_cam.push_back(job.scan->cam_from_lidar * point.cast<double>());
    }
    views[i].lidar_depth =
        LidarDepthGrid(points_in_cam, views[i].camera,
                       options.visibility_cell_px, options.min_depth_m);
  });
  return views;
}

}  // namespace colmap_lidar
