// Input of the Delaunay mesher (Amblard et al., Sec. III-E, last paragraph):
// points of three sources, each with the sensor centres that observed it.
// - Visual points: the fused depth maps (<ws>/fused.ply + fused.ply.vis,
//   colmap-formats.md 4.7-4.8), seen from the camera centres of the
//   workspace model's images (vis index = image position in the model).
// - LIDAR voxels (optional, written by lidar_fuser into the workspace):
//   lidar_fused.ply (x y z nx ny nz, uint32 count = raw LIDAR points in the
//   voxel), lidar_fused.ply.vis (same layout as fused.ply.vis: the frames,
//   by image position, whose scans hit the voxel) and lidar_origins.txt
//   (lines "IMAGE_NAME X Y Z": the LIDAR centre of that frame in the world
//   frame). The rays go from those origins to the voxel.
// - Line samples (optional): points every line_sample_step_m (by default the
//   surface points' spacing) along the 3D
//   segments of a model's lines3D file, seen from the camera centres of the
//   images in the line's track (matched by image_id) that observed that part
//   of the line (line_observations.h; given the database of the 2D
//   segments, else every image of the track sees the whole line).
//   By default only the segments on a crease of the visual and LIDAR points
//   are sampled, moved onto it (line_validation.h), only where the other
//   points leave a gap (line_samples_only_in_gaps), and not those whose
//   crease is with a step's side face (kept in `creases` for the snapping
//   only).
// Each point carries the free-space weight of each of its rays.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/mvs/fused_vis.h"
#include "colmap_ext/scene/reconstruction.h"
#include "src/mesh/crease_snapping.h"
#include "src/mesh/lidar_denoising.h"
#include "src/mesh/line_observations.h"
#include "src/mesh/line_validation.h"

namespace colmap_lidar {

enum class MeshingPointSource : uint8_t { kVisual = 0, kLidar = 1, kLine = 2 };

struct MeshingSensor {
  Eigen::Vector3d position_in_world = Eigen::Vector3d::Zero();
  // Cameras project points for the pixel-distance vertex merging; LIDAR
  // origins do not.
  bool is_camera = false;
  // K * [R | t] (pinhole part of the camera; the dense workspace is PINHOLE).
  Eigen::Matrix3x4d proj_matrix = Eigen::Matrix3x4d::Zero();
  // Image size of a camera, pixels (0 for LIDAR origins); bounds the region
  // the images see (view_region.h).
  int image_width = 0;
  int image_height = 0;
};

struct MeshingInput {
  std::vector<MeshingSensor> sensors;
  std::vector<Eigen::Vector3d> positions;
  std::vector<MeshingPointSource> sources;
  // Weight of each ray from an observing sensor to the point (> 0).
  std::vector<float> ray_weights;
  // Indices into `sensors`, per point.
  FusedVisibility visibility;
  // The creases of the surface that the sampled line segments lie on
  // (validated lines only) and the point spacing s the validation measured,
  // metres (0 without creases): the mesher snaps the mesh onto them
  // (crease_snapping.h).
  std::vector<MeshCrease> creases;
  double crease_spacing_m = 0;

  size_t NumPoints() const { return positions.size(); }
  size_t NumRays() const;
  size_t NumPoints(MeshingPointSource source) const;
  // Appends one point; throws if a sensor index is out of range.
  void AddPoint(const Eigen::Vector3d& position, MeshingPointSource source,
                float ray_weight, std::vector<uint32_t> sensor_indices);
  // Throws on inconsistent array lengths or sensor indices.
  void Check() const;
};

enum class LidarCountMapping { kNone, kLinear, kLog };
// "none" | "linear" | "log" (case-insensitive); throws otherwise.
LidarCountMapping LidarCountMappingFromString(const std::string& name);

struct MeshingInputOptions {
  // Use <ws>/fused.ply (then it and fused.ply.vis must exist).
  bool use_visual = true;
  // Use <ws>/lidar_fused.ply when it exists (then its .vis and
  // lidar_origins.txt must exist too).
  bool use_lidar = true;
  // Weight of a visual ray, times COLMAP's visibility probability
  // 1 - exp(-n^2 / (2 visibility_sigma^2)) of a point seen in n images.
  double visual_weight = 1.0;
  double visibility_sigma = 3.0;
  // Weight of a LIDAR voxel, spread equally over the frames that saw it:
  // lidar_weight * g(count) / num_frames, with g = 1 ("none"), count
  // ("linear", every raw return is one ray) or 1 + ln(count) ("log").
  double lidar_weight = 1.0;
  std::string lidar_count_mapping = "log";
  // Rays of a LIDAR voxel: from at most this many of the frames that saw it,
  // the nearest scanner positions (the shortest rays, the least grazing),
  // carrying its whole weight; 0 keeps all. A voxel of the default scene is
  // seen by about 9 of the 60 360-degree scans: casting all of them was 80 %
  // of the meshing time.
  int max_lidar_rays_per_point = 3;
  // Weight of a line sample's ray, times the visibility probability above
  // of a point seen in as many images as observed the sample (as a visual
  // ray: the line is placed no better than a fused depth).
  double line_weight = 1.0;
  // Spacing of the samples along a 3D segment, metres (>= 0); both end points
  // are always sampled. 0 takes the spacing s of the surface points that the
  // line validation measures (the median distance to the spacing_neighbor-th
  // neighbour, 4.6-6.4 cm on the benchmark matrix): samples denser than the
  // points around them cost precision near the crease on the square (near-
  // crease precision at 0.02 m against no lines: -0.0003 at a step of 2 cm,
  // +0.0012 at the spacing; every cell gains at the spacing, matrix.md).
  double line_sample_step_m = 0;
  // Sample only the segments that lie on a crease of the visual and LIDAR
  // points, moved onto it (line_validation.h); false samples every segment
  // where it was estimated (the paper).
  bool validate_lines = true;
  // With validate_lines: a crease is sampled only where no surface point
  // lies within the validation's plane band of the sample. Where the points
  // reach the crease already, a sample adds its own placement error (the
  // crease is known to about a centimetre) and nothing else; it fills the
  // gaps, where the mesh would cut the corner. The snapping uses the crease
  // either way.
  bool line_samples_only_in_gaps = true;
  LineValidationOptions line_validation;
  // LIDAR voxels are projected onto their local plane when it is planar
  // (lidar_denoising.h); radius 0 keeps the centroids as fused.
  LidarDenoisingOptions lidar_denoising;
  // Threads of the denoising; <= 0 uses all cores (MeshDenseWorkspace sets
  // it to DelaunayMeshingOptions::num_threads).
  int num_threads = -1;

  bool Check() const;
};

// The LIDAR files of a dense workspace.
std::string LidarFusedPlyPath(const std::string& workspace_path);
std::string LidarFusedVisPath(const std::string& workspace_path);
std::string LidarOriginsPath(const std::string& workspace_path);

// Reads lidar_origins.txt ("IMAGE_NAME X Y Z" per line, '#' comments; the
// name may contain spaces). Throws naming the file and line on a malformed
// line or a duplicate name.
std::vector<std::pair<std::string, Eigen::Vector3d>> ReadLidarOrigins(
    const std::string& path);
void WriteLidarOrigins(
    const std::string& path,
    const std::vector<std::pair<std::string, Eigen::Vector3d>>& origins);

// Gathers the input from a dense workspace and, when `lines_model_path` is
// not empty, the lines3D of the model there; `database_path` (optional, the
// database whose ext_line_segments the lines' tracks index) restricts each
// sample's rays to the images that observed it. Throws colmap_lidar::Error
// naming the file on a missing or inconsistent file (vis count differs from
// the PLY vertex count, vis index beyond the model's images, LIDAR frame
// without an origin). No input point at all is an error too.
MeshingInput ReadMeshingInput(const MeshingInputOptions& options,
                              const std::string& workspace_path,
                              const std::string& lines_model_path = "",
                              const std::string& database_path = "");

// The building blocks of ReadMeshingInput. AddCameraSensors must come first:
// sensor i is then the camera of image i of `model`.
void AddCameraSensors(const Reconstruction& model, MeshingInput* input);
void AddVisualPoints(const MeshingInputOptions& options,
                     const std::vector<Eigen::Vector3d>& positions,
                     const FusedVisibility& visibility, MeshingInput* input);
// `origins` by image position (empty optional = no origin); `counts` per
// voxel.
void AddLidarPoints(const MeshingInputOptions& options,
                    const std::vector<Eigen::Vector3d>& positions,
                    const std::vector<uint32_t>& counts,
                    const FusedVisibility& frames,
                    const std::vector<Eigen::Vector3d>& origins,
                    const std::vector<bool>& has_origin,
                    const std::string& path_for_errors, MeshingInput* input);
// `observations` (ReadLineObservations) restrict the rays of a sample to the
// images whose observed interval, widened by one sample step, contains it; a
// sample that no image observed is not added. nullptr: every image of the
// track sees every sample. With options.validate_lines, only the segments on
// a crease of the points already in `input` are sampled, moved onto it
// (line_validation.h), and every validated segment that an image observed
// joins input->creases; one whose crease is with a step's side face
// (ValidatedLine::with_side_face) is not sampled, and with
// options.line_samples_only_in_gaps neither is a sample within the plane
// band of a point already in `input`. Returns the number of samples added.
size_t AddLineSamples(
    const MeshingInputOptions& options, const Reconstruction& dense_model,
    const Reconstruction& lines_model,
    const std::map<line3D_t, std::vector<LineObservedInterval>>* observations,
    MeshingInput* input);

}  // namespace colmap_lidar
