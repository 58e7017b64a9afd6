// The folder level of model_io.h (format detection, whole models) and the
// checks shared by the formats; the per-file readers and writers are in
// model_io_binary.cc and model_io_text.cc.
#include "colmap_ext/model/model_io.h"

#include <cmath>
#include <filesystem>

#include "colmap_ext/model/model_io_internal.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

const char* const kModelFileNames[] = {"cameras", "images", "points3D",
                                       "lines3D"};

std::string FormatExtension(ModelFormat format) {
  return format == ModelFormat::kBinary ? ".bin" : ".txt";
}

void RemoveFileIfExists(const std::string& path) {
  std::error_code ec;
  std::filesystem::remove(path, ec);
  THROW_CHECK(
      !ec, "Cannot remove stale model file " << path << ": " << ec.message());
}

}  // namespace

namespace model_io_internal {

Eigen::Quaterniond NormalizedQuaternion(double w, double x, double y, double z,
                                        const std::string& where) {
  Eigen::Quaterniond q(w, x, y, z);
  const double squared_norm = q.squaredNorm();
  THROW_CHECK(squared_norm > 0, where << ": zero quaternion");
  if (std::abs(squared_norm - 1.0) > 1e-12) {
    q.normalize();
  }
  return q;
}

void CheckCamera(const Camera& camera, const std::string& where) {
  try {
    camera.Check();
  } catch (const Error& error) {
    THROW_ERROR(where << ": " << error.what());
  }
}

void CheckImageName(const Image& image, ModelFormat format,
                    const std::string& path) {
  THROW_CHECK(
      image.name.find('\0') == std::string::npos,
      path << ": image " << image.image_id << " has a NUL byte in its name");
  if (format == ModelFormat::kText) {
    // colmap splits on spaces and takes the last token as the name.
    THROW_CHECK(!image.name.empty() &&
                    image.name.find_first_of(" \t\r\n") == std::string::npos,
                path << ": image " << image.image_id << " name '" << image.name
                     << "' is empty or has white space, which colmap's text "
                        "format cannot store; write binary");
  }
}

}  // namespace model_io_internal

////////////////////////////////////////////////////////////////////////////////
// Folder level.
////////////////////////////////////////////////////////////////////////////////

bool ExistsModel(const std::string& dir) {
  for (const ModelFormat format : {ModelFormat::kBinary, ModelFormat::kText}) {
    const std::string ext = FormatExtension(format);
    if (ExistsFile(JoinPaths(dir, "cameras" + ext)) &&
        ExistsFile(JoinPaths(dir, "images" + ext)) &&
        ExistsFile(JoinPaths(dir, "points3D" + ext))) {
      return true;
    }
  }
  return false;
}

ModelFormat DetectModelFormat(const std::string& dir) {
  THROW_CHECK(ExistsDir(dir), "Model folder does not exist: " << dir);
  for (const ModelFormat format : {ModelFormat::kBinary, ModelFormat::kText}) {
    const std::string ext = FormatExtension(format);
    if (ExistsFile(JoinPaths(dir, "cameras" + ext)) &&
        ExistsFile(JoinPaths(dir, "images" + ext)) &&
        ExistsFile(JoinPaths(dir, "points3D" + ext))) {
      return format;
    }
  }
  THROW_ERROR("No COLMAP model in " << dir
                                    << ": cameras, images and points3D "
                                       "files (all .bin or all .txt) needed");
}

Reconstruction ReadReconstruction(const std::string& dir) {
  const ModelFormat format = DetectModelFormat(dir);
  const std::string ext = FormatExtension(format);
  const std::string other_ext =
      FormatExtension(format == ModelFormat::kBinary ? ModelFormat::kText
                                                     : ModelFormat::kBinary);
  Reconstruction reconstruction;
  const std::string lines_path = JoinPaths(dir, "lines3D" + ext);
  if (format == ModelFormat::kBinary) {
    ReadCamerasBinary(JoinPaths(dir, "cameras.bin"), &reconstruction);
    ReadImagesBinary(JoinPaths(dir, "images.bin"), &reconstruction);
    ReadPoints3DBinary(JoinPaths(dir, "points3D.bin"), &reconstruction);
    if (ExistsFile(lines_path)) {
      ReadLines3DBinary(lines_path, &reconstruction);
    }
  } else {
    ReadCamerasText(JoinPaths(dir, "cameras.txt"), &reconstruction);
    ReadImagesText(JoinPaths(dir, "images.txt"), &reconstruction);
    ReadPoints3DText(JoinPaths(dir, "points3D.txt"), &reconstruction);
    if (ExistsFile(lines_path)) {
      ReadLines3DText(lines_path, &reconstruction);
    }
  }
  const std::string other_lines_path = JoinPaths(dir, "lines3D" + other_ext);
  if (!ExistsFile(lines_path) && ExistsFile(other_lines_path)) {
    LOG(WARNING) << "Ignoring " << other_lines_path << ": the model in " << dir
                 << " is read in " << ext << " format";
  }
  LOG(INFO) << "Read model " << dir << " (" << ext
            << "): " << reconstruction.cameras.size() << " cameras, "
            << reconstruction.images.size() << " images, "
            << reconstruction.points3D.size() << " points, "
            << reconstruction.lines3D.size() << " lines";
  return reconstruction;
}

void WriteReconstruction(const std::string& dir,
                         const Reconstruction& reconstruction,
                         ModelFormat format) {
  reconstruction.CheckConsistency();
  CreateDirIfNotExists(dir);
  const std::string ext = FormatExtension(format);
  const std::string other_ext =
      FormatExtension(format == ModelFormat::kBinary ? ModelFormat::kText
                                                     : ModelFormat::kBinary);
  const std::string lines_path = JoinPaths(dir, "lines3D" + ext);
  if (format == ModelFormat::kBinary) {
    WriteCamerasBinary(JoinPaths(dir, "cameras.bin"), reconstruction);
    WriteImagesBinary(JoinPaths(dir, "images.bin"), reconstruction);
    WritePoints3DBinary(JoinPaths(dir, "points3D.bin"), reconstruction);
    if (!reconstruction.lines3D.empty()) {
      WriteLines3DBinary(lines_path, reconstruction);
    }
  } else {
    WriteCamerasText(JoinPaths(dir, "cameras.txt"), reconstruction);
    WriteImagesText(JoinPaths(dir, "images.txt"), reconstruction);
    WritePoints3DText(JoinPaths(dir, "points3D.txt"), reconstruction);
    if (!reconstruction.lines3D.empty()) {
      WriteLines3DText(lines_path, reconstruction);
    }
  }
  // Only now that the new model is complete: drop files that would hide it
  // (a .bin set wins over .txt) or go stale.
  if (reconstruction.lines3D.empty()) {
    RemoveFileIfExists(lines_path);
  }
  for (const char* name : kModelFileNames) {
    RemoveFileIfExists(JoinPaths(dir, name + other_ext));
  }
  LOG(INFO) << "Wrote model " << dir << " (" << ext
            << "): " << reconstruction.cameras.size() << " cameras, "
            << reconstruction.images.size() << " images, "
            << reconstruction.points3D.size() << " points, "
            << reconstruction.lines3D.size() << " lines";
}

}  // namespace colmap_lidar
