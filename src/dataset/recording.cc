#include "src/dataset/recording.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"
#include "src/dataset/kitti_raw.h"
#include "src/dataset/poses.h"

namespace colmap_lidar {
namespace fs = std::filesystem;
namespace {

const std::vector<std::string> kImageExtensions = {".png", ".jpg", ".jpeg"};
const std::vector<std::string> kScanExtensions = {".ply", ".pcd", ".bin"};

// The frame a pose line refers to: the frame of that name, else (for
// timestamp-keyed trajectories) the frame whose name is the same number.
const RecordingFrame* FindFrameForPose(
    const std::vector<RecordingFrame>& frames, const std::string& key) {
  for (const RecordingFrame& frame : frames) {
    if (frame.name == key) {
      return &frame;
    }
  }
  double key_value = 0;
  try {
    key_value = ParseDouble(key, key);
  } catch (const Error&) {
    return nullptr;
  }
  const RecordingFrame* match = nullptr;
  for (const RecordingFrame& frame : frames) {
    double frame_value = 0;
    try {
      frame_value = ParseDouble(frame.name, frame.name);
    } catch (const Error&) {
      continue;
    }
    const double tolerance = 1e-9 * std::max(1.0, std::abs(key_value));
    if (std::abs(frame_value - key_value) <= tolerance) {
      THROW_CHECK(match == nullptr, "Pose '" << key
                                             << "' matches two frames: "
                                             << match->name << " and "
                                             << frame.name);
      match = &frame;
    }
  }
  return match;
}

Recording LoadRigRecording(const std::string& path) {
  Recording recording;
  recording.path = path;
  recording.format = "rig";
  recording.calibration = ReadCalibration(JoinPaths(path, "calibration.yaml"));

  const std::string image_dir = JoinPaths(path, "images");
  const std::string scan_dir = JoinPaths(path, "lidar");
  const auto images = ListFramesInDir(image_dir, kImageExtensions, "image");
  const auto scans = ListFramesInDir(scan_dir, kScanExtensions, "LIDAR scan");
  for (const auto& [stem, image_path] : images) {
    THROW_CHECK(scans.count(stem) > 0, image_path << ": frame '" << stem
                                                  << "' has no LIDAR scan in "
                                                  << scan_dir);
    RecordingFrame frame;
    frame.name = stem;
    frame.image_path = image_path;
    frame.scan_path = scans.at(stem);
    recording.frames.push_back(frame);
  }
  for (const auto& [stem, scan_path] : scans) {
    THROW_CHECK(images.count(stem) > 0, scan_path << ": frame '" << stem
                                                  << "' has no image in "
                                                  << image_dir);
  }
  THROW_CHECK(!recording.frames.empty(),
              image_dir << ": no frames (no .png/.jpg images)");

  const std::string prior_path = JoinPaths(path, "poses_prior.txt");
  CheckFileExists(prior_path, "Prior poses");
  for (const FramePose& pose : ReadPoses(prior_path)) {
    const RecordingFrame* frame = FindFrameForPose(recording.frames, pose.frame);
    THROW_CHECK(frame != nullptr, prior_path << ": pose '" << pose.frame
                                             << "' matches no frame");
    RecordingFrame& mutable_frame =
        recording.frames[frame - recording.frames.data()];
    THROW_CHECK(!mutable_frame.world_from_cam_prior,
                prior_path << ": two poses for frame '" << frame->name << "'");
    mutable_frame.world_from_cam_prior = pose.world_from_cam;
  }
  for (const RecordingFrame& frame : recording.frames) {
    THROW_CHECK(frame.world_from_cam_prior.has_value(),
                prior_path << ": no pose for frame '" << frame.name << "'");
  }

  if (ExistsFile(JoinPaths(path, "poses_gt.txt"))) {
    recording.ground_truth_poses_path = JoinPaths(path, "poses_gt.txt");
  }
  if (ExistsFile(JoinPaths(path, "reference.ply"))) {
    recording.reference_cloud_path = JoinPaths(path, "reference.ply");
  }
  return recording;
}

}  // namespace

std::map<std::string, std::string> ListFramesInDir(
    const std::string& dir, const std::vector<std::string>& extensions,
    const std::string& what) {
  CheckDirExists(dir, what);
  // Sorted, so that an error about two files of one frame names them in the
  // same order on every file system.
  std::vector<fs::directory_entry> entries(fs::directory_iterator(dir), {});
  std::sort(entries.begin(), entries.end());
  std::map<std::string, std::string> files;
  for (const fs::directory_entry& entry : entries) {
    if (!entry.is_regular_file()) {
      continue;
    }
    const std::string extension =
        StringToLower(entry.path().extension().string());
    if (std::find(extensions.begin(), extensions.end(), extension) ==
        extensions.end()) {
      continue;
    }
    const std::string stem = entry.path().stem().string();
    const auto [it, inserted] = files.emplace(stem, entry.path().string());
    THROW_CHECK(inserted, dir << ": two " << what << " files for frame '"
                              << stem << "': " << it->second << " and "
                              << entry.path().string());
  }
  return files;
}

std::string DetectRecordingFormat(const std::string& path) {
  CheckDirExists(path, "Dataset");
  if (ExistsFile(JoinPaths(path, "calibration.yaml"))) {
    return "rig";
  }
  if (!FindKittiCalibrationFolder(path).empty()) {
    return "kitti_raw";
  }
  THROW_ERROR(path << ": not a recording: neither calibration.yaml (rig "
                      "format) nor calib_cam_to_cam.txt (KITTI raw)");
}

Recording LoadRecording(const std::string& path, const std::string& format,
                        int kitti_camera) {
  CheckDirExists(path, "Dataset");
  const std::string resolved =
      format == "auto" ? DetectRecordingFormat(path) : format;
  if (resolved == "rig") {
    return LoadRigRecording(path);
  }
  if (resolved == "kitti_raw") {
    return LoadKittiRawRecording(path, kitti_camera);
  }
  THROW_ERROR("Unknown dataset format '" << format
                                         << "' (expected auto, rig or "
                                            "kitti_raw)");
}

}  // namespace colmap_lidar
