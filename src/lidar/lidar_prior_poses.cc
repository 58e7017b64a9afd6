#include "src/lidar/lidar_prior_poses.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

#include <glog/logging.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/scene/reconstruction.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {

namespace fs = std::filesystem;

// world_from_cam of an image's prior columns, when both are set.
std::optional<Rigid3d> WorldFromCamPrior(const DatabaseImage& image) {
  if (!image.prior_q || !image.prior_t) {
    return std::nullopt;
  }
  return Rigid3d(image.prior_q->normalized().inverse(), *image.prior_t);
}

}  // namespace

LidarPriorPosesSummary RunLidarOdometryPriors(
    const std::string& database_path, const std::string& output_path,
    const LidarOdometryOptions& odometry_options,
    const LidarPriorPosesOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  THROW_CHECK(odometry_options.Check(), "invalid LidarOdometry options");
  THROW_CHECK(options.Check(), "invalid LidarPriorPoses options");
  CheckFileExists(database_path, "database");
  THROW_CHECK(!output_path.empty(), "lidar_odometry: empty output path");
  // The model folder is replaced as a whole: refuse a folder that holds
  // anything but a model (e.g. the workspace itself).
  if (ExistsDir(output_path) && !fs::is_empty(output_path)) {
    THROW_CHECK(ExistsModel(output_path),
                output_path << " exists and holds no sparse model; refusing "
                               "to replace it");
  }

  Database database(database_path);

  std::vector<DatabaseImage> images = database.ReadAllImages();
  std::sort(images.begin(), images.end(),
            [](const DatabaseImage& a, const DatabaseImage& b) {
              return a.name < b.name;
            });
  LidarPriorPosesSummary summary;
  std::vector<std::pair<DatabaseImage, LidarScanRecord>> frames;
  for (const DatabaseImage& image : images) {
    std::optional<LidarScanRecord> record =
        database.ReadLidarScan(image.image_id);
    if (!record) {
      LOG(WARNING) << "Image " << image.name << " has no LIDAR scan in "
                   << database_path << "; it gets no prior";
      ++summary.num_images_without_scan;
      continue;
    }
    frames.emplace_back(image, *record);
  }
  THROW_CHECK(!frames.empty(),
              "No image of " << database_path << " has a LIDAR scan");

  // The first camera is the world unless the first frame has a prior.
  const auto& [first_image, first_record] = frames.front();
  const Rigid3d world_from_first_cam =
      WorldFromCamPrior(first_image).value_or(Rigid3d());
  LidarOdometry odometry(odometry_options,
                         world_from_first_cam * first_record.cam_from_lidar);

  for (const auto& [image, record] : frames) {
    const LidarScan scan =
        ReadLidarScan(LidarScanFilePath(database_path, record.path));
    LidarPriorPose pose;
    pose.image_id = image.image_id;
    pose.image_name = image.name;
    pose.camera_id = image.camera_id;
    pose.odometry = odometry.AddScan(scan, image.name);
    pose.world_from_cam =
        pose.odometry.world_from_lidar * record.cam_from_lidar.Inverse();
    if (!pose.odometry.registered) {
      ++summary.num_failed_registrations;
    }
    if (!summary.poses.empty()) {
      summary.trajectory_length_m +=
          (pose.world_from_cam.translation -
           summary.poses.back().world_from_cam.translation)
              .norm();
    }
    LOG(INFO) << "LIDAR odometry " << image.name << ": overlap "
              << pose.odometry.overlap << ", rmse " << pose.odometry.rmse_m
              << " m, " << pose.odometry.num_points << " points, "
              << pose.odometry.seconds << " s";
    summary.poses.push_back(pose);
  }

  // Database priors, one transaction.
  DatabaseTransaction transaction(&database);
  std::map<camera_t, Camera> all_cameras;
  for (const Camera& camera : database.ReadAllCameras()) {
    all_cameras.emplace(camera.camera_id, camera);
  }
  Reconstruction model;
  for (size_t i = 0; i < frames.size(); ++i) {
    DatabaseImage image = frames[i].first;
    const LidarPriorPose& pose = summary.poses[i];
    const Rigid3d cam_from_world = pose.world_from_cam.Inverse();
    if (WorldFromCamPrior(image) && !options.overwrite_priors) {
      ++summary.num_priors_kept;
    } else {
      image.prior_q = cam_from_world.rotation;
      image.prior_t = pose.world_from_cam.translation;
      database.UpdateImage(image);
      ++summary.num_priors_written;
    }
    Image model_image;
    model_image.image_id = image.image_id;
    model_image.name = image.name;
    model_image.camera_id = image.camera_id;
    model_image.cam_from_world = cam_from_world;
    model.images.push_back(model_image);
    const auto camera = all_cameras.find(image.camera_id);
    THROW_CHECK(camera != all_cameras.end(),
                "Image " << image.name << " refers to camera "
                         << image.camera_id << ", which is not in "
                         << database_path);
    model.cameras.emplace(camera->first, camera->second);
  }

  // The model lands right after the database commit.
  const fs::path model_dir = fs::path(output_path).lexically_normal();
  if (model_dir.has_parent_path()) {
    CreateDirIfNotExists(model_dir.parent_path().string());
  }
  StagedDirectory staged_model(output_path);
  WriteReconstruction(staged_model.path(), model, ModelFormat::kBinary);
  transaction.Commit();
  staged_model.Commit();

  summary.seconds = std::chrono::duration<double>(
                        std::chrono::steady_clock::now() - start)
                        .count();
  LOG(INFO) << "LIDAR odometry: " << summary.poses.size() << " frames, "
            << summary.trajectory_length_m << " m, "
            << summary.num_priors_written << " priors written, "
            << summary.num_priors_kept << " kept, "
            << summary.num_failed_registrations << " failed registrations, "
            << summary.seconds << " s";
  return summary;
}

}  // namespace colmap_lidar
