// A camera + LIDAR recording on disk, resolved into frames: the rig dataset
// format (shared docs/dataset-format.md) or the KITTI raw layout.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "src/dataset/calibration.h"

namespace colmap_lidar {

struct RecordingFrame {
  // The stem shared by the image and the scan ("000042").
  std::string name;
  // Absolute or dataset-relative paths of the two files.
  std::string image_path;
  std::string scan_path;
  // Camera-to-world prior pose, when the recording has one for this frame.
  std::optional<Rigid3d> world_from_cam_prior;
};

struct Recording {
  std::string path;
  // "rig" or "kitti_raw".
  std::string format;
  RigCalibration calibration;
  // Sorted by name.
  std::vector<RecordingFrame> frames;
  // poses_gt.txt and reference.ply when present (rig format only).
  std::string ground_truth_poses_path;
  std::string reference_cloud_path;
};

// Loads a recording. `format` is "auto", "rig" or "kitti_raw"; `kitti_camera`
// picks image_0N of a KITTI recording. Throws colmap_lidar::Error naming the
// file on: missing calibration or folders, frames with an image but no scan
// (or the reverse), two images or two scans for one frame, prior poses that
// match no frame or a frame without a prior pose (rig format requires
// poses_prior.txt with one pose per frame).
Recording LoadRecording(const std::string& path, const std::string& format,
                        int kitti_camera = 2);

// The files of `dir` whose lower-cased extension is one of `extensions`
// (with the dot), keyed by file stem. Throws naming the folder when it does
// not exist or when two files share a stem ("what" names their kind).
std::map<std::string, std::string> ListFramesInDir(
    const std::string& dir, const std::vector<std::string>& extensions,
    const std::string& what);

// Detects the format of a folder: "rig" when calibration.yaml exists,
// "kitti_raw" when a calib_cam_to_cam.txt exists in it or in one of its
// sub-folders; throws otherwise.
std::string DetectRecordingFormat(const std::string& path);

}  // namespace colmap_lidar
