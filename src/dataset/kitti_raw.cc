#include "src/dataset/kitti_raw.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {
namespace fs = std::filesystem;
namespace {

// Parses "KEY: v1 v2 ..." lines; non-numeric entries (calib_time) are kept
// out of the map.
std::map<std::string, std::vector<double>> ReadKittiCalibFile(
    const std::string& path) {
  CheckFileExists(path, "KITTI calibration");
  std::istringstream content(ReadTextFile(path));
  std::map<std::string, std::vector<double>> values;
  std::string line;
  while (std::getline(content, line)) {
    const size_t colon = line.find(':');
    if (colon == std::string::npos) {
      continue;
    }
    const std::string key = StringTrim(line.substr(0, colon));
    std::istringstream numbers(line.substr(colon + 1));
    std::vector<double> row;
    std::string token;
    bool numeric = true;
    while (numbers >> token) {
      try {
        row.push_back(ParseDouble(token, path));
      } catch (const Error&) {
        numeric = false;
        break;
      }
    }
    if (numeric) {
      values[key] = row;
    }
  }
  return values;
}

const std::vector<double>& RequireCalib(
    const std::map<std::string, std::vector<double>>& values,
    const std::string& key, size_t count, const std::string& path) {
  const auto it = values.find(key);
  THROW_CHECK(it != values.end(), path << ": missing '" << key << "'");
  THROW_CHECK(it->second.size() == count, path << ": '" << key << "' has "
                                               << it->second.size()
                                               << " values, expected "
                                               << count);
  return it->second;
}

}  // namespace

std::string FindKittiCalibrationFolder(const std::string& path) {
  if (ExistsFile(JoinPaths(path, "calib_cam_to_cam.txt"))) {
    return path;
  }
  if (!ExistsDir(path)) {
    return "";
  }
  std::vector<std::string> candidates;
  for (const auto& entry : fs::directory_iterator(path)) {
    if (entry.is_directory() &&
        ExistsFile((entry.path() / "calib_cam_to_cam.txt").string())) {
      candidates.push_back(entry.path().string());
    }
  }
  THROW_CHECK(candidates.size() <= 1,
              path << ": holds several KITTI date folders; point "
                      "--dataset_path at one of them");
  return candidates.empty() ? "" : candidates[0];
}

Recording LoadKittiRawRecording(const std::string& path, int camera_index) {
  THROW_CHECK(camera_index >= 0 && camera_index <= 3,
              "KITTI camera index must be 0..3, got " << camera_index);
  const std::string calib_dir = FindKittiCalibrationFolder(path);
  THROW_CHECK(!calib_dir.empty(),
              path << ": no calib_cam_to_cam.txt here or in a sub-folder "
                      "(not a KITTI raw recording)");

  const std::string cam_calib_path =
      JoinPaths(calib_dir, "calib_cam_to_cam.txt");
  const std::string velo_calib_path =
      JoinPaths(calib_dir, "calib_velo_to_cam.txt");
  const auto cam_calib = ReadKittiCalibFile(cam_calib_path);
  const auto velo_calib = ReadKittiCalibFile(velo_calib_path);

  const std::string index = "0" + std::to_string(camera_index);
  const std::vector<double>& size =
      RequireCalib(cam_calib, "S_rect_" + index, 2, cam_calib_path);
  const std::vector<double>& p_rect =
      RequireCalib(cam_calib, "P_rect_" + index, 12, cam_calib_path);
  const std::vector<double>& r_rect =
      RequireCalib(cam_calib, "R_rect_00", 9, cam_calib_path);
  const std::vector<double>& r_velo =
      RequireCalib(velo_calib, "R", 9, velo_calib_path);
  const std::vector<double>& t_velo =
      RequireCalib(velo_calib, "T", 3, velo_calib_path);

  Eigen::Matrix<double, 3, 4, Eigen::RowMajor> projection;
  std::copy(p_rect.begin(), p_rect.end(), projection.data());
  const Eigen::Matrix3d K = projection.leftCols<3>();
  THROW_CHECK(K(0, 0) > 0 && K(1, 1) > 0,
              cam_calib_path << ": P_rect_" << index
                             << " has non-positive focal lengths");

  // S_rect is the image size in pixels; the upper bound keeps the conversion
  // to an integer defined for a corrupt file.
  constexpr double kMaxImageSize = 1 << 20;
  for (const double extent : size) {
    THROW_CHECK(extent >= 1 && extent <= kMaxImageSize &&
                    extent == std::floor(extent),
                cam_calib_path << ": S_rect_" << index
                               << " must be two positive integers (pixels), "
                                  "got "
                               << size[0] << " " << size[1]);
  }

  Recording recording;
  recording.path = path;
  recording.format = "kitti_raw";
  // KITTI pixel coordinates put the centre of the first pixel at 0; COLMAP's
  // at 0.5.
  recording.calibration.camera = Camera::FromModelName(
      "PINHOLE", static_cast<uint64_t>(size[0]),
      static_cast<uint64_t>(size[1]),
      {K(0, 0), K(1, 1), K(0, 2) + 0.5, K(1, 2) + 0.5});
  recording.calibration.camera.has_prior_focal_length = true;

  Eigen::Matrix4d rect = Eigen::Matrix4d::Identity();
  rect.topLeftCorner<3, 3>() =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
          r_rect.data());
  Eigen::Matrix4d cam0_from_velo = Eigen::Matrix4d::Identity();
  cam0_from_velo.topLeftCorner<3, 3>() =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
          r_velo.data());
  cam0_from_velo.topRightCorner<3, 1>() =
      Eigen::Vector3d(t_velo[0], t_velo[1], t_velo[2]);
  Eigen::Matrix4d camn_from_rect0 = Eigen::Matrix4d::Identity();
  camn_from_rect0.topRightCorner<3, 1>() = K.inverse() * projection.col(3);
  const Eigen::Matrix4d cam_from_velo = camn_from_rect0 * rect * cam0_from_velo;
  recording.calibration.cam_from_lidar =
      Rigid3d::FromMatrix(cam_from_velo.topRows<3>());

  // Images and scans live in the date folder (flattened sample) or in one
  // drive folder below it.
  std::string data_dir = calib_dir;
  const std::string image_subdir = "image_" + index + "/data";
  if (!ExistsDir(JoinPaths(data_dir, image_subdir))) {
    std::vector<std::string> drives;
    for (const auto& entry : fs::directory_iterator(calib_dir)) {
      if (entry.is_directory() &&
          ExistsDir((entry.path() / image_subdir).string())) {
        drives.push_back(entry.path().string());
      }
    }
    THROW_CHECK(!drives.empty(), calib_dir << ": no " << image_subdir
                                           << " folder (here or in a drive "
                                              "folder)");
    THROW_CHECK(drives.size() == 1,
                calib_dir << ": several drive folders; point --dataset_path "
                             "at a folder with one drive");
    data_dir = drives[0];
  }
  const std::string image_dir = JoinPaths(data_dir, image_subdir);
  const std::string scan_dir = JoinPaths(data_dir, "velodyne_points/data");
  CheckDirExists(scan_dir, "KITTI velodyne scans");

  const auto images = ListFramesInDir(image_dir, {".png", ".jpg", ".jpeg"}, "image");
  const auto scans = ListFramesInDir(scan_dir, {".bin"}, "LIDAR scan");
  for (const auto& [stem, image_path] : images) {
    THROW_CHECK(scans.count(stem) > 0,
                image_path << ": no LIDAR scan " << stem << ".bin in "
                           << scan_dir);
    RecordingFrame frame;
    frame.name = stem;
    frame.image_path = image_path;
    frame.scan_path = scans.at(stem);
    recording.frames.push_back(frame);
  }
  for (const auto& [stem, scan_path] : scans) {
    THROW_CHECK(images.count(stem) > 0,
                scan_path << ": no image for frame " << stem << " in "
                          << image_dir);
  }
  THROW_CHECK(!recording.frames.empty(), image_dir << ": no frames");
  return recording;
}

}  // namespace colmap_lidar
