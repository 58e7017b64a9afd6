// lidar_importer: a camera + LIDAR recording into a COLMAP workspace, or
// into an existing one.
//
// Produces (or completes) <workspace>/database.db with
//  - one camera from the calibration (an identical existing camera is
//    reused),
//  - one image per frame, its prior pose in COLMAP's prior columns as this
//    project defines them: prior_q* the world-to-camera rotation, prior_t*
//    the camera position in the world,
//  - one ext_lidar_scans row per frame (scan path, point count,
//    cam_from_lidar);
// plus <workspace>/images/, <workspace>/lidar/ (copies) and
// <workspace>/sparse/prior, a COLMAP model with the prior poses and no
// points, usable by stock `colmap point_triangulator`.
//
// A database that already holds images (a stock COLMAP workspace) is
// completed: frames are matched to images by name (exact, else a unique
// image with the same file stem) and only the prior columns, the camera
// (calibrate_matched_images) and our tables change; features and matches
// are never touched. Frames with no match are
// added as new images.
//
// All database changes happen in one transaction and all files are staged
// under temporary names: on any error the workspace is left as it was.
#pragma once

#include <cstdint>
#include <string>

namespace colmap_lidar {

struct ImporterOptions {
  // Recording layout: auto | rig | kitti_raw.
  std::string input_format = "auto";
  // Copy the images into <workspace>/images; otherwise the images stay in
  // the dataset, whose image folder is then the image_path.
  bool copy_images = true;
  // Copy the scans into <workspace>/lidar; otherwise the database stores
  // their absolute paths.
  bool copy_scans = true;
  // KITTI raw: which rectified camera (image_0N), 0..3.
  int kitti_camera = 2;
  // Replace the LIDAR rows, priors and copied files of frames imported
  // before; otherwise importing a frame twice is an error.
  bool overwrite = false;
  // Existing images matched to frames take the recording's calibrated
  // camera when theirs differs (stock feature_extractor guesses a
  // SIMPLE_RADIAL camera from the image size; keypoints are pixel positions
  // and stay valid). Off: they keep theirs. Either way a matched image whose
  // size differs from the calibration is an error.
  bool calibrate_matched_images = true;

  bool Check() const;
};

struct ImportSummary {
  std::string dataset_format;
  int num_frames = 0;
  int num_new_images = 0;
  int num_matched_images = 0;
  // Matched images moved to the calibrated camera.
  int num_recalibrated_images = 0;
  int num_frames_with_prior = 0;
  uint64_t num_lidar_points = 0;
  std::string database_path;
  // Folder to pass as --image_path to stock colmap.
  std::string image_path;
  // Empty when the recording has no prior poses (e.g. KITTI raw).
  std::string prior_model_path;
};

// Throws colmap_lidar::Error naming the file or option at fault; the
// workspace is then unchanged.
ImportSummary ImportDataset(const std::string& dataset_path,
                            const std::string& workspace_path,
                            const std::string& database_path,
                            const ImporterOptions& options);

// A few human-readable lines.
std::string FormatImportSummary(const ImportSummary& summary);

}  // namespace colmap_lidar
