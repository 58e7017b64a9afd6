// A synthetic test scene for the Delaunay mesher: an axis-aligned box
// standing on a square ground plane, seen by a ring of PINHOLE cameras and
// scanned by LIDARs near them. Visibility is exact (facing, in the image,
// not occluded by the box). Used by the tests and benchmarks of src/mesh.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/mvs/fused_vis.h"
#include "colmap_ext/scene/reconstruction.h"
#include "src/mesh/meshing_input.h"
#include "src/mesh/triangle_mesh.h"

namespace colmap_lidar {

struct SyntheticBoxSceneOptions {
  Eigen::Vector3d box_min = Eigen::Vector3d(-0.6, -0.4, 0.0);
  Eigen::Vector3d box_max = Eigen::Vector3d(0.6, 0.4, 0.8);
  // The ground is z = 0 for |x|, |y| <= ground_half_size_m.
  double ground_half_size_m = 2.5;
  // Mean spacing of the random surface samples, metres.
  double box_spacing_m = 0.02;
  double ground_spacing_m = 0.05;
  // Gaussian noise along each axis, metres.
  double noise_m = 0.0;
  int num_cameras = 12;
  double ring_radius_m = 3.0;
  double camera_height_m = 1.6;
  int image_width = 640;
  int image_height = 480;
  double focal_length_px = 400;
  unsigned seed = 1;
};

struct SyntheticPoints {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;
  // Image positions in the model (= camera index) that see each point.
  FusedVisibility visibility;
};

class SyntheticBoxScene {
 public:
  explicit SyntheticBoxScene(const SyntheticBoxSceneOptions& options);

  const SyntheticBoxSceneOptions& Options() const { return options_; }
  // Cameras and images (ids 1..n, names "image_XXX.png") in ring order.
  const Reconstruction& Model() const { return model_; }

  // Random samples on the box (top, sides) and ground, with noise, each
  // kept only if seen by at least `min_num_views` cameras.
  SyntheticPoints SampleVisualPoints(int min_num_views = 2) const;
  // Noise-free grid samples of the true surface with their normals and
  // visibility (for coverage checks).
  SyntheticPoints SampleTrueSurface(double spacing_m,
                                    int min_num_views = 2) const;
  // The cameras that see a surface point with this normal.
  std::vector<uint32_t> VisibleCameras(const Eigen::Vector3d& point,
                                       const Eigen::Vector3d& normal) const;
  // True if the open segment from `from` to `to` passes through the box.
  bool SegmentHitsBox(const Eigen::Vector3d& from,
                      const Eigen::Vector3d& to) const;
  // Distance to the true surface (box boundary without its bottom, ground).
  double DistanceToSurface(const Eigen::Vector3d& point) const;

  // LIDAR origin of frame i: below camera i by lidar_drop_m.
  Eigen::Vector3d LidarOrigin(int frame, double lidar_drop_m = 0.3) const;
  // A LIDAR simulation from the first `num_frames` origins (rays every
  // angular_step_deg in azimuth and elevation over [-60, 10] deg), voxelised
  // at voxel_size_m: voxel centroids, raw point counts and the frames.
  struct LidarVoxels {
    std::vector<Eigen::Vector3d> positions;
    std::vector<uint32_t> counts;
    FusedVisibility frames;
  };
  LidarVoxels SimulateLidar(int num_frames, double angular_step_deg,
                            double voxel_size_m, double range_noise_m) const;
  // The 12 box edges as 3D lines, each with the cameras that see its middle.
  // Bottom edges are included.
  std::vector<Line3D> BoxEdgeLines() const;

  // Writes a dense workspace: sparse/ (text model), fused.ply + .vis from
  // `points`, and, when `lidar` is not null, lidar_fused.ply + .vis +
  // lidar_origins.txt.
  void WriteWorkspace(const std::string& workspace_path,
                      const SyntheticPoints& points,
                      const LidarVoxels* lidar = nullptr) const;

 private:
  SyntheticBoxSceneOptions options_;
  Reconstruction model_;
};

// Exact point-to-mesh distances (CGAL AABB tree over the triangles).
class MeshDistance {
 public:
  explicit MeshDistance(const TriangleMesh& mesh);
  ~MeshDistance();
  double Distance(const Eigen::Vector3d& point) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Test measures of a mesh of the scene.
// The `percent` percentile of `values` (0 when empty).
double Percentile(std::vector<double> values, double percent);
// Distances of points sampled on the faces (centroid and the three edge
// midpoints) to the true surface.
std::vector<double> FaceDistancesToSurface(const SyntheticBoxScene& scene,
                                           const TriangleMesh& mesh);
// Fraction of the true-surface samples (every `spacing` metres, seen by two
// cameras) within `threshold` of the mesh.
double SurfaceCoverage(const SyntheticBoxScene& scene, const TriangleMesh& mesh,
                       double threshold, double spacing = 0.05);

// Meshing input from scene points: camera sensors of the model, then the
// visual points (AddVisualPoints with default weights).
MeshingInput MakeVisualMeshingInput(const SyntheticBoxScene& scene,
                                    const SyntheticPoints& points);

}  // namespace colmap_lidar
