// Fusion of all registered LIDAR scans into one voxel-downsampled cloud
// (paper section III-E, "we register all of the LIDAR point clouds onto a
// single point cloud S_fused and downsample it using a voxel grid ... we keep
// track of the number of LIDAR points that have been clustered in the same
// voxel", after Li et al.). The count is the visibility weight of the voxel
// for the depth-map initialisation and the Delaunay mesher. Voxels that other
// scans see through (moving objects) are dropped before the normals and the
// files (free_space.enabled; src/lidar/free_space_filter.h).
//
// Files written by `colmap-lidar lidar_fuser` into the dense workspace
// (readers: src/mvs for the depth initialisation, the Delaunay mesher):
//
//   <ws>/lidar_fused.ply       binary little-endian PLY, one vertex per
//                              occupied voxel: float x y z (centroid of the
//                              absorbed points, world frame, metres), float
//                              nx ny nz (unit normal of the plane fitted to
//                              the neighbouring voxel centroids, oriented
//                              towards the scanner centres that saw the
//                              voxel; (0, 0, 0) when no plane could be
//                              fitted), uint32 count (raw points absorbed).
//   <ws>/lidar_fused.ply.vis   COLMAP's fused.ply.vis layout (uint64 N, then
//                              per vertex uint32 n + n uint32 image indices):
//                              the frames whose scans hit the voxel, as
//                              0-based positions in the dense workspace's
//                              sparse model image order, the frames with the
//                              most points first, at most
//                              max_num_visible_images of them.
//   <ws>/lidar_origins.txt     one line per frame "IMAGE_NAME X Y Z": the
//                              LIDAR centre in the world,
//                              world_from_cam * cam_from_lidar * (0, 0, 0).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/mvs/fused_vis.h"
#include "colmap_ext/scene/rigid3.h"
#include "src/lidar/free_space_filter.h"
#include "src/lidar/lidar_scan.h"

namespace colmap_lidar {

struct LidarFusionOptions {
  // Edge of the cubic voxels, metres, > 0.
  double voxel_size_m = 0.05;
  // Points nearer to / farther from their scanner are ignored, metres.
  double min_range_m = 0.5;
  double max_range_m = 100.0;
  // Voxels that absorbed fewer raw points are dropped, >= 1.
  int min_points_per_voxel = 1;
  // Normals: plane fitted to the centroids of the voxels within this many
  // voxels (Chebyshev distance) around each voxel, >= 1.
  int normal_radius_voxels = 2;
  // Minimum number of voxel centroids for a plane fit, >= 3.
  int normal_min_neighbors = 5;
  // The normal stays unknown (zero) unless the neighbourhood spreads in two
  // directions: its second covariance eigenvalue at least this share of the
  // largest, [0, 1). Where one ring of a sparse scanner crosses the
  // neighbourhood alone (a line of centroids), the smallest eigenvector is
  // any direction across the line: 8 % of the corridor VLP-16's voxels gave
  // such an arbitrary normal (a wall's normal pointing up), which the depth
  // initialisation then trusted. 0: every fit is kept.
  double normal_min_eigenvalue_ratio = 0.1;
  // Frames kept per voxel in the .vis file (most points first), >= 1.
  int max_num_visible_images = 16;
  // Voxels that other scans see through (moving objects) are dropped, see
  // src/lidar/free_space_filter.h.
  FreeSpaceFilterOptions free_space;

  bool Check() const;
};

// One scan with its pose; `image_idx` is the frame's position in the dense
// workspace's sparse model image order (the .vis index).
struct LidarFusionInput {
  uint32_t image_idx = 0;
  const LidarScan* scan = nullptr;  // LIDAR frame.
  Rigid3d world_from_lidar;
};

struct FusedLidarCloud {
  std::vector<Eigen::Vector3f> points;   // World frame.
  std::vector<Eigen::Vector3f> normals;  // Unit or zero.
  std::vector<uint32_t> counts;
  FusedVisibility visibility;

  size_t size() const { return points.size(); }
};

// Registers and voxelises the scans. Deterministic: the output is sorted by
// voxel index. Throws on options that fail Check().
FusedLidarCloud FuseLidarScans(const std::vector<LidarFusionInput>& inputs,
                               const LidarFusionOptions& options);

// lidar_fused.ply + lidar_fused.ply.vis (atomic each).
void WriteFusedLidarCloud(const std::string& ply_path,
                          const FusedLidarCloud& cloud);
// Reads lidar_fused.ply and, when it exists, lidar_fused.ply.vis (else the
// visibility stays empty). Throws naming the file on a missing column or a
// .vis of another length.
FusedLidarCloud ReadFusedLidarCloud(const std::string& ply_path);

struct LidarOrigin {
  std::string image_name;
  Eigen::Vector3d position_in_world = Eigen::Vector3d::Zero();
};
void WriteLidarOrigins(const std::string& path,
                       const std::vector<LidarOrigin>& origins);
// (Named apart from src/mesh's ReadLidarOrigins, which reads the same file
// into name/position pairs.)
std::vector<LidarOrigin> ReadLidarOriginList(const std::string& path);

struct LidarFuserSummary {
  size_t num_frames = 0;
  size_t num_frames_without_scan = 0;
  size_t num_raw_points = 0;
  size_t num_voxels = 0;
};

// The lidar_fuser command: poses from the model in `input_path`, scans from
// the database (ext_lidar_scans; a relative scan path is relative to the
// database's folder), frame order for the .vis from `<output_path>/sparse`
// when that model exists (the dense workspace), else from `input_path`.
// Frames without a scan are skipped with a warning. Writes the three files
// above into `output_path` (created if needed).
LidarFuserSummary RunLidarFuser(const std::string& database_path,
                                const std::string& input_path,
                                const std::string& output_path,
                                const LidarFusionOptions& options);

}  // namespace colmap_lidar
