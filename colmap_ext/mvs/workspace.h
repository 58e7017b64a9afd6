// The dense workspace layout of `colmap image_undistorter --output_type
// COLMAP` (colmap-formats.md 3.1, 4.1, 5):
//
//   <ws>/images/<name>                               undistorted images
//   <ws>/sparse/{cameras,images,points3D}.{bin,txt}  PINHOLE model with tracks
//   <ws>/stereo/{depth_maps,normal_maps,consistency_graphs}/<name>.<type>.bin
//   <ws>/stereo/patch-match.cfg, <ws>/stereo/fusion.cfg
//   <ws>/fused.ply, <ws>/fused.ply.vis, <ws>/meshed-{poisson,delaunay}.ply
//
// <name> keeps its extension and sub-folders; <type> is "photometric" or
// "geometric" and is chosen only by stereo_fusion's --input_type.
#pragma once

#include <string>
#include <vector>

#include "colmap_ext/scene/reconstruction.h"

namespace colmap_lidar {

enum class DenseMapType { kPhotometric, kGeometric };

// "photometric" / "geometric".
std::string DenseMapTypeToString(DenseMapType type);
// Case-insensitive, like COLMAP's --input_type; throws on anything else.
DenseMapType DenseMapTypeFromString(const std::string& name);

class DenseWorkspace {
 public:
  explicit DenseWorkspace(std::string path);

  const std::string& Path() const { return path_; }
  std::string ImagesDir() const;
  std::string SparseDir() const;
  std::string StereoDir() const;
  std::string DepthMapsDir() const;
  std::string NormalMapsDir() const;
  std::string ConsistencyGraphsDir() const;
  std::string PatchMatchConfigPath() const;
  std::string FusionConfigPath() const;
  std::string FusedPlyPath() const;
  // fused.ply.vis: COLMAP appends ".vis" to the PLY path.
  std::string FusedVisPath() const;
  std::string PoissonMeshPath() const;
  std::string DelaunayMeshPath() const;

  std::string ImagePath(const std::string& image_name) const;
  std::string DepthMapPath(const std::string& image_name,
                           DenseMapType type) const;
  std::string NormalMapPath(const std::string& image_name,
                            DenseMapType type) const;
  std::string ConsistencyGraphPath(const std::string& image_name,
                                   DenseMapType type) const;

  // The workspace model (binary wins over text, as in COLMAP).
  Reconstruction ReadModel() const;
  // The names in stereo/fusion.cfg.
  std::vector<std::string> ReadFusionImageNames() const;

  // Checks the minimal input of stock `stereo_fusion --input_type <type>`
  // (colmap-formats.md 5) and throws colmap_lidar::Error naming the first
  // missing or inconsistent item: images/ and sparse/ folders; a complete
  // .bin or .txt model whose cameras are all PINHOLE or SIMPLE_PINHOLE and
  // which has 3D points with tracks (without them fusion finds no overlap
  // and outputs nothing); a non-empty fusion.cfg whose names are all in the
  // model; and, for every such name, the image, the depth map (1 channel)
  // and the normal map (3 channels, same size) of that type. Logs a warning
  // when both .bin and .txt models exist (the .bin one is used).
  void Validate(DenseMapType type) const;

 private:
  std::string path_;
};

// Creates images/, sparse/ and stereo/{depth_maps,normal_maps,
// consistency_graphs}/ under `workspace_path`, plus, in each stereo folder,
// the sub-folders of the image names (e.g. "cam0/0001.png" -> cam0/), as the
// undistorter does. Existing content is kept. Throws on failure.
void CreateDenseWorkspaceLayout(const std::string& workspace_path,
                                const std::vector<std::string>& image_names);

// Writes stereo/patch-match.cfg ("__auto__, <num_src_images>" per image) and
// stereo/fusion.cfg (all names) as the undistorter does.
void WriteDefaultStereoConfigs(const DenseWorkspace& workspace,
                               const std::vector<std::string>& image_names,
                               int num_src_images = 20);

}  // namespace colmap_lidar
