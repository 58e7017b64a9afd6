#include "src/dataset/importer.h"

#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/scene/reconstruction.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/dataset/recording.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace fs = std::filesystem;
namespace {

// Image and scan checks that stock colmap would only report much later (or
// abort on): readable image of the calibrated size, non-empty finite scan
// at plausible ranges with points in front of the camera.
uint64_t ValidateFrame(const RecordingFrame& frame,
                       const RigCalibration& calibration) {
  const Camera& camera = calibration.camera;
  const cv::Mat image = cv::imread(frame.image_path, cv::IMREAD_UNCHANGED);
  THROW_CHECK(!image.empty(), frame.image_path << ": cannot read the image");
  THROW_CHECK(static_cast<uint64_t>(image.cols) == camera.width &&
                  static_cast<uint64_t>(image.rows) == camera.height,
              frame.image_path << ": image is " << image.cols << "x"
                               << image.rows << " but the camera is "
                               << camera.width << "x" << camera.height);
  const LidarScan scan = ReadLidarScan(frame.scan_path);

  // A scan read with the wrong byte order (a big-endian .bin, a PLY whose
  // header declares the other endianness) is finite but meaningless: its
  // coordinates spread over dozens of decades. Metric LIDAR ranges do not.
  constexpr double kMinPlausibleRange = 1e-3;  // 1 mm.
  constexpr double kMaxPlausibleRange = 1e5;   // 100 km.
  size_t num_plausible = 0;
  size_t num_in_front = 0;
  for (const Eigen::Vector3f& point : scan.points) {
    const double range = point.cast<double>().norm();
    if (range >= kMinPlausibleRange && range <= kMaxPlausibleRange) {
      ++num_plausible;
    }
    if ((calibration.cam_from_lidar * point.cast<double>()).z() > 0.0) {
      ++num_in_front;
    }
  }
  THROW_CHECK(2 * num_plausible >= scan.size(),
              frame.scan_path << ": only " << num_plausible << " of its "
                              << scan.size()
                              << " points lie between 1 mm and 100 km from "
                                 "the sensor; wrong byte order (endianness) "
                                 "or unit?");
  // Every later stage projects the scan into the image; a scan with nothing
  // in front of the camera points at a wrong cam_from_lidar or a wrong file.
  THROW_CHECK(num_in_front > 0,
              frame.scan_path << ": none of its " << scan.size()
                              << " points is in front of the camera (z > 0 "
                                 "after cam_from_lidar); check the "
                                 "calibration's cam_from_lidar");
  return scan.size();
}

bool SameCamera(const Camera& a, const Camera& b) {
  if (a.model_id != b.model_id || a.width != b.width || a.height != b.height ||
      a.params.size() != b.params.size()) {
    return false;
  }
  for (size_t i = 0; i < a.params.size(); ++i) {
    if (std::abs(a.params[i] - b.params[i]) >
        1e-9 * std::max(1.0, std::abs(a.params[i]))) {
      return false;
    }
  }
  return true;
}

// The database image a frame refers to: same name, else the unique image
// whose file stem is the frame name (images in sub-folders or with another
// extension).
const DatabaseImage* MatchFrameToImage(
    const std::string& image_name, const std::string& frame_name,
    const std::map<std::string, DatabaseImage>& images_by_name) {
  const auto exact = images_by_name.find(image_name);
  if (exact != images_by_name.end()) {
    return &exact->second;
  }
  const DatabaseImage* match = nullptr;
  for (const auto& [name, image] : images_by_name) {
    if (fs::path(name).stem().string() == frame_name) {
      THROW_CHECK(match == nullptr,
                  "Frame '" << frame_name << "' matches two database images: "
                            << match->name << " and " << name);
      match = &image;
    }
  }
  return match;
}

// Removes the workspace folder again if this import created it and failed.
class CreatedDirGuard {
 public:
  explicit CreatedDirGuard(const std::string& path)
      : path_(path), created_(!ExistsDir(path)) {
    CreateDirIfNotExists(path);
  }
  ~CreatedDirGuard() {
    if (created_ && !released_) {
      std::error_code ec;
      fs::remove_all(path_, ec);
    }
  }
  void Release() { released_ = true; }

 private:
  std::string path_;
  bool created_;
  bool released_ = false;
};

// Removes the files and folders of an existing workspace that this import
// created (database, images/, lidar/, sparse/) if it fails; declared before
// the Database so that the database is closed first.
class CreatedPathsGuard {
 public:
  explicit CreatedPathsGuard(const std::vector<std::string>& paths) {
    for (const std::string& path : paths) {
      if (!fs::exists(path)) {
        created_.push_back(path);
      }
    }
  }
  ~CreatedPathsGuard() {
    if (released_) {
      return;
    }
    for (const std::string& path : created_) {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  }
  void Release() { released_ = true; }

 private:
  std::vector<std::string> created_;
  bool released_ = false;
};

}  // namespace

bool ImporterOptions::Check() const {
  if (input_format != "auto" && input_format != "rig" &&
      input_format != "kitti_raw") {
    LOG(ERROR) << "LidarImport.input_format must be auto, rig or kitti_raw, "
                  "got '"
               << input_format << "'";
    return false;
  }
  if (kitti_camera < 0 || kitti_camera > 3) {
    LOG(ERROR) << "LidarImport.kitti_camera must be in [0, 3], got "
               << kitti_camera;
    return false;
  }
  return true;
}

ImportSummary ImportDataset(const std::string& dataset_path,
                            const std::string& workspace_path,
                            const std::string& database_path,
                            const ImporterOptions& options) {
  THROW_CHECK(options.Check(), "Invalid LidarImport options");
  THROW_CHECK(!workspace_path.empty(), "--workspace_path is empty");

  const Recording recording =
      LoadRecording(dataset_path, options.input_format, options.kitti_camera);
  const Camera& camera = recording.calibration.camera;
  LOG(INFO) << "Importing " << recording.frames.size() << " frames of a "
            << recording.format << " recording from " << dataset_path;

  ImportSummary summary;
  summary.dataset_format = recording.format;
  summary.num_frames = static_cast<int>(recording.frames.size());

  std::vector<uint64_t> num_points(recording.frames.size());
  for (size_t i = 0; i < recording.frames.size(); ++i) {
    num_points[i] = ValidateFrame(recording.frames[i], recording.calibration);
    summary.num_lidar_points += num_points[i];
  }
  LOG(INFO) << "Validated " << recording.frames.size() << " images and scans ("
            << summary.num_lidar_points << " LIDAR points)";

  CreatedDirGuard workspace_guard(workspace_path);
  summary.database_path = database_path.empty()
                              ? JoinPaths(workspace_path, "database.db")
                              : database_path;
  const std::string workspace_image_dir = JoinPaths(workspace_path, "images");
  const std::string workspace_scan_dir = JoinPaths(workspace_path, "lidar");

  CreatedPathsGuard created_paths_guard(
      {summary.database_path, summary.database_path + "-wal",
       summary.database_path + "-shm", workspace_image_dir,
       workspace_scan_dir, JoinPaths(workspace_path, "sparse")});
  Database database(summary.database_path);
  std::map<std::string, DatabaseImage> images_by_name;
  for (const DatabaseImage& image : database.ReadAllImages()) {
    images_by_name.emplace(image.name, image);
  }
  const bool existing_workspace = !images_by_name.empty();

  StagedFiles staged_files;
  DatabaseTransaction transaction(&database);

  // One camera for the recording, reused when an identical one exists.
  camera_t camera_id = kInvalidCameraId;
  std::map<camera_t, Camera> cameras;
  for (const Camera& existing : database.ReadAllCameras()) {
    cameras.emplace(existing.camera_id, existing);
    if (camera_id == kInvalidCameraId && SameCamera(existing, camera)) {
      camera_id = existing.camera_id;
    }
  }

  // The recording's camera, written on first use.
  const auto recording_camera_id = [&]() {
    if (camera_id == kInvalidCameraId) {
      Camera new_camera = camera;
      camera_id = database.WriteCamera(new_camera);
      new_camera.camera_id = camera_id;
      cameras.emplace(camera_id, new_camera);
    }
    return camera_id;
  };

  Reconstruction prior_model;
  for (size_t i = 0; i < recording.frames.size(); ++i) {
    const RecordingFrame& frame = recording.frames[i];
    const std::string image_file = fs::path(frame.image_path).filename();
    const std::string scan_file = fs::path(frame.scan_path).filename();

    DatabaseImage image;
    const DatabaseImage* matched =
        MatchFrameToImage(image_file, frame.name, images_by_name);
    if (matched != nullptr) {
      image = *matched;
      THROW_CHECK(options.overwrite || !database.ExistsLidarScan(image.image_id),
                  "Frame '" << frame.name << "' (image " << image.name
                            << ") already has a LIDAR scan in "
                            << summary.database_path
                            << "; pass --LidarImport.overwrite 1 to replace it");
      ++summary.num_matched_images;
      const auto current_it = cameras.find(image.camera_id);
      THROW_CHECK(current_it != cameras.end(),
                  "Image " << image.name << " of " << summary.database_path
                           << " refers to camera " << image.camera_id
                           << ", which the database lacks");
      const Camera& current = current_it->second;
      // The scan is projected with this image's camera and cam_from_lidar:
      // an image of another size than the calibration (a resized copy, another
      // camera) cannot take the LIDAR, whatever its intrinsics.
      const std::string workspace_image =
          JoinPaths(workspace_image_dir, image.name);
      THROW_CHECK(current.width == camera.width &&
                      current.height == camera.height,
                  (ExistsFile(workspace_image) ? workspace_image
                                               : "Image " + image.name)
                      << ": the workspace image (camera " << current.camera_id
                      << " of " << summary.database_path << ") is "
                      << current.width << "x" << current.height
                      << " pixels but the recording's calibration is for "
                      << camera.width << "x" << camera.height
                      << "; import into a workspace of the recording's images");
      if (options.calibrate_matched_images && !SameCamera(current, camera)) {
        image.camera_id = recording_camera_id();
        ++summary.num_recalibrated_images;
      }
    } else {
      image.camera_id = recording_camera_id();
      image.name = image_file;
      ++summary.num_new_images;
    }

    if (frame.world_from_cam_prior) {
      const Rigid3d cam_from_world = frame.world_from_cam_prior->Inverse();
      image.prior_q = cam_from_world.rotation;
      image.prior_t = frame.world_from_cam_prior->translation;
      ++summary.num_frames_with_prior;
    }
    if (matched != nullptr) {
      database.UpdateImage(image);
    } else {
      image.image_id = database.WriteImage(image);
    }

    // Images of an existing workspace stay where they are; new ones are
    // copied unless they are there already with the same content.
    if (options.copy_images && matched == nullptr) {
      const std::string target = JoinPaths(workspace_image_dir, image.name);
      if (!FilesHaveSameContent(frame.image_path, target)) {
        THROW_CHECK(!ExistsFile(target) || options.overwrite,
                    target << " exists with other content; pass "
                              "--LidarImport.overwrite 1 to replace it");
        staged_files.Copy(frame.image_path, target);
      }
    }

    LidarScanRecord scan;
    scan.image_id = image.image_id;
    scan.num_points = num_points[i];
    scan.cam_from_lidar = recording.calibration.cam_from_lidar;
    if (options.copy_scans) {
      const std::string target = JoinPaths(workspace_scan_dir, scan_file);
      if (!FilesHaveSameContent(frame.scan_path, target)) {
        THROW_CHECK(!ExistsFile(target) || options.overwrite,
                    target << " exists with other content; pass "
                              "--LidarImport.overwrite 1 to replace it");
        staged_files.Copy(frame.scan_path, target);
      }
      scan.path = "lidar/" + scan_file;
    } else {
      scan.path = fs::absolute(frame.scan_path).lexically_normal().string();
    }
    database.WriteLidarScan(scan);

    if (frame.world_from_cam_prior) {
      Image model_image;
      model_image.image_id = image.image_id;
      model_image.name = image.name;
      model_image.camera_id = image.camera_id;
      model_image.cam_from_world = frame.world_from_cam_prior->Inverse();
      prior_model.images.push_back(model_image);
      prior_model.cameras.emplace(image.camera_id, cameras.at(image.camera_id));
    }
  }

  // The prior model is staged too, so that it lands with the database.
  std::unique_ptr<StagedDirectory> staged_model;
  if (!prior_model.images.empty()) {
    summary.prior_model_path = JoinPaths(workspace_path, "sparse/prior");
    CreateDirIfNotExists(JoinPaths(workspace_path, "sparse"));
    staged_model = std::make_unique<StagedDirectory>(summary.prior_model_path);
    WriteReconstruction(staged_model->path(), prior_model, ModelFormat::kBinary);
  } else {
    LOG(WARNING) << "The recording has no prior poses: no sparse/prior model";
  }

  transaction.Commit();
  staged_files.Commit();
  if (staged_model) {
    staged_model->Commit();
  }
  workspace_guard.Release();
  created_paths_guard.Release();

  summary.image_path = (options.copy_images || existing_workspace)
                           ? workspace_image_dir
                           : fs::path(recording.frames[0].image_path)
                                 .parent_path()
                                 .string();
  LOG(INFO) << "Imported " << summary.num_frames << " frames into "
            << summary.database_path;
  return summary;
}

std::string FormatImportSummary(const ImportSummary& summary) {
  std::ostringstream out;
  out << "Imported " << summary.num_frames << " frames (" << summary.dataset_format
      << " recording)\n"
      << "  new images:         " << summary.num_new_images << "\n"
      << "  matched images:     " << summary.num_matched_images << " ("
      << summary.num_recalibrated_images << " moved to the calibrated camera)\n"
      << "  frames with prior:  " << summary.num_frames_with_prior << "\n"
      << "  LIDAR points:       " << summary.num_lidar_points << "\n"
      << "  database:           " << summary.database_path << "\n"
      << "  image path:         " << summary.image_path << "\n"
      << "  prior model:        "
      << (summary.prior_model_path.empty() ? "(none: no prior poses)"
                                           : summary.prior_model_path)
      << "\n";
  return out.str();
}

}  // namespace colmap_lidar
