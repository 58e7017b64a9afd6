#include "colmap_ext/mvs/workspace.h"

#include <filesystem>
#include <set>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/mvs/mat.h"
#include "colmap_ext/mvs/stereo_config.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {
namespace {

bool HasModelFiles(const std::string& dir, const std::string& extension) {
  return ExistsFile(JoinPaths(dir, "cameras" + extension)) &&
         ExistsFile(JoinPaths(dir, "images" + extension)) &&
         ExistsFile(JoinPaths(dir, "points3D" + extension));
}

}  // namespace

std::string DenseMapTypeToString(DenseMapType type) {
  return type == DenseMapType::kPhotometric ? "photometric" : "geometric";
}

DenseMapType DenseMapTypeFromString(const std::string& name) {
  const std::string lower = StringToLower(name);
  if (lower == "photometric") {
    return DenseMapType::kPhotometric;
  }
  THROW_CHECK(lower == "geometric", "Unknown dense map type '"
                                        << name
                                        << "' (photometric or geometric)");
  return DenseMapType::kGeometric;
}

DenseWorkspace::DenseWorkspace(std::string path) : path_(std::move(path)) {}

std::string DenseWorkspace::ImagesDir() const {
  return JoinPaths(path_, "images");
}
std::string DenseWorkspace::SparseDir() const {
  return JoinPaths(path_, "sparse");
}
std::string DenseWorkspace::StereoDir() const {
  return JoinPaths(path_, "stereo");
}
std::string DenseWorkspace::DepthMapsDir() const {
  return JoinPaths(StereoDir(), "depth_maps");
}
std::string DenseWorkspace::NormalMapsDir() const {
  return JoinPaths(StereoDir(), "normal_maps");
}
std::string DenseWorkspace::ConsistencyGraphsDir() const {
  return JoinPaths(StereoDir(), "consistency_graphs");
}
std::string DenseWorkspace::PatchMatchConfigPath() const {
  return JoinPaths(StereoDir(), "patch-match.cfg");
}
std::string DenseWorkspace::FusionConfigPath() const {
  return JoinPaths(StereoDir(), "fusion.cfg");
}
std::string DenseWorkspace::FusedPlyPath() const {
  return JoinPaths(path_, "fused.ply");
}
std::string DenseWorkspace::FusedVisPath() const {
  return FusedPlyPath() + ".vis";
}
std::string DenseWorkspace::PoissonMeshPath() const {
  return JoinPaths(path_, "meshed-poisson.ply");
}
std::string DenseWorkspace::DelaunayMeshPath() const {
  return JoinPaths(path_, "meshed-delaunay.ply");
}

std::string DenseWorkspace::ImagePath(const std::string& image_name) const {
  return JoinPaths(ImagesDir(), image_name);
}

std::string DenseWorkspace::DepthMapPath(const std::string& image_name,
                                         DenseMapType type) const {
  return JoinPaths(DepthMapsDir(),
                   image_name + "." + DenseMapTypeToString(type) + ".bin");
}

std::string DenseWorkspace::NormalMapPath(const std::string& image_name,
                                          DenseMapType type) const {
  return JoinPaths(NormalMapsDir(),
                   image_name + "." + DenseMapTypeToString(type) + ".bin");
}

std::string DenseWorkspace::ConsistencyGraphPath(const std::string& image_name,
                                                 DenseMapType type) const {
  return JoinPaths(ConsistencyGraphsDir(),
                   image_name + "." + DenseMapTypeToString(type) + ".bin");
}

Reconstruction DenseWorkspace::ReadModel() const {
  return ReadReconstruction(SparseDir());
}

std::vector<std::string> DenseWorkspace::ReadFusionImageNames() const {
  return ReadFusionConfig(FusionConfigPath());
}

void DenseWorkspace::Validate(DenseMapType type) const {
  CheckDirExists(path_, "Dense workspace");
  CheckDirExists(ImagesDir(), "Dense workspace images");
  CheckDirExists(SparseDir(), "Dense workspace sparse model");
  const bool has_bin = HasModelFiles(SparseDir(), ".bin");
  const bool has_txt = HasModelFiles(SparseDir(), ".txt");
  THROW_CHECK(has_bin || has_txt,
              "Dense workspace sparse model: no complete cameras/images/"
              "points3D .bin or .txt set in "
                  << SparseDir());
  if (has_bin && has_txt) {
    LOG(WARNING) << "Both .bin and .txt models in " << SparseDir()
                 << "; COLMAP uses the .bin one";
  }
  const Reconstruction model = ReadModel();
  for (const auto& [camera_id, camera] : model.cameras) {
    THROW_CHECK(camera.model_id == CameraModelId::kPinhole ||
                    camera.model_id == CameraModelId::kSimplePinhole,
                "Dense workspace camera " << camera_id << " in "
                                          << SparseDir() << " is "
                                          << camera.ModelName()
                                          << ", stereo needs PINHOLE");
  }
  bool has_tracks = false;
  for (const auto& [point3D_id, point3D] : model.points3D) {
    if (!point3D.track.empty()) {
      has_tracks = true;
      break;
    }
  }
  THROW_CHECK(has_tracks, "Dense workspace sparse model "
                              << SparseDir()
                              << " has no 3D points with tracks; "
                                 "stereo_fusion needs them for image overlap");

  const std::vector<std::string> names = ReadFusionImageNames();
  THROW_CHECK(!names.empty(), "Empty " << FusionConfigPath());
  std::set<std::string> model_names;
  for (const Image& image : model.images) {
    model_names.insert(image.name);
  }
  for (const std::string& name : names) {
    THROW_CHECK(model_names.count(name) > 0,
                "Image '" << name << "' of " << FusionConfigPath()
                          << " is not in the model " << SparseDir());
    CheckFileExists(ImagePath(name), "Dense workspace image");
    const std::string depth_path = DepthMapPath(name, type);
    const std::string normal_path = NormalMapPath(name, type);
    CheckFileExists(depth_path, "Depth map");
    CheckFileExists(normal_path, "Normal map");
    const MatHeader depth = ReadMatHeader(depth_path);
    const MatHeader normal = ReadMatHeader(normal_path);
    THROW_CHECK(depth.depth == 1,
                "Depth map " << depth_path << " has " << depth.depth
                             << " channels, expected 1");
    THROW_CHECK(normal.depth == 3,
                "Normal map " << normal_path << " has " << normal.depth
                              << " channels, expected 3");
    THROW_CHECK(depth.width == normal.width && depth.height == normal.height,
                "Depth map " << depth_path << " is " << depth.width << "x"
                             << depth.height << " but normal map "
                             << normal_path << " is " << normal.width << "x"
                             << normal.height);
  }
}

void CreateDenseWorkspaceLayout(const std::string& workspace_path,
                                const std::vector<std::string>& image_names) {
  const DenseWorkspace workspace(workspace_path);
  CreateDirIfNotExists(workspace.ImagesDir());
  CreateDirIfNotExists(workspace.SparseDir());
  for (const std::string& dir :
       {workspace.DepthMapsDir(), workspace.NormalMapsDir(),
        workspace.ConsistencyGraphsDir()}) {
    CreateDirIfNotExists(dir);
    for (const std::string& name : image_names) {
      const std::filesystem::path parent =
          std::filesystem::path(name).parent_path();
      if (!parent.empty()) {
        CreateDirIfNotExists(JoinPaths(dir, parent.string()));
        CreateDirIfNotExists(JoinPaths(workspace.ImagesDir(), parent.string()));
      }
    }
  }
}

void WriteDefaultStereoConfigs(const DenseWorkspace& workspace,
                               const std::vector<std::string>& image_names,
                               int num_src_images) {
  std::vector<PatchMatchEntry> entries(image_names.size());
  for (size_t i = 0; i < image_names.size(); ++i) {
    entries[i].ref_image_name = image_names[i];
    entries[i].source_kind = PatchMatchEntry::SourceKind::kAuto;
    entries[i].num_auto_src_images = num_src_images;
  }
  CreateDirIfNotExists(workspace.StereoDir());
  WritePatchMatchConfig(workspace.PatchMatchConfigPath(), entries);
  WriteFusionConfig(workspace.FusionConfigPath(), image_names);
}

}  // namespace colmap_lidar
