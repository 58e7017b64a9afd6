// The synthetic dataset generator (issue 3): renders a scene preset along
// its walk path into a rig dataset (docs/dataset-format.md) plus ground
// truth for the benchmarks:
//
//   <output>/calibration.yaml          camera (model + params), cam_from_lidar,
//                                      lidar (rings, vertical FOV, noise)
//   <output>/images/<frame>.png        8-bit RGB, frames 000000, 000001, ...
//   <output>/lidar/<frame>.ply         x y z intensity ring, LIDAR frame
//   <output>/poses_gt.txt              exact world_from_cam
//   <output>/poses_prior.txt           noisy world_from_cam (seeded)
//   <output>/reference.ply             simulated survey, world frame
//   <output>/ground_truth/README.md    what everything is, the noise models
//                                      and every option of the run
//   <output>/ground_truth/scene.ply    the scene mesh (x y z material, faces)
//   <output>/ground_truth/crease_edges.txt  3D crease segments
//   <output>/ground_truth/depth_maps/<frame>.bin  COLMAP Mat z-depth, MVS
//                                      pixel convention, 0 = no surface
//
// Everything is written into a staged folder renamed into place at the end
// (StagedDirectory), so an interrupted run leaves no partial dataset.
#pragma once

#include <string>
#include <vector>

#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/rigid3.h"
#include "src/synth/scene_mesh.h"
#include "src/synth/synthesis_options.h"

namespace colmap_lidar {

struct SynthesisSummary {
  int num_frames = 0;
  size_t num_lidar_points = 0;
  size_t num_reference_points = 0;
  size_t num_crease_edges = 0;
  size_t num_paint_edges = 0;
  size_t num_triangles = 0;
  double seconds = 0.0;
};

// The camera of the options: model options.camera_model, f = fx = fy =
// (width / 2) / tan(hfov / 2), principal point at the image centre
// (width / 2, height / 2), then the model's distortion coefficients:
//   PINHOLE        fx, fy, cx, cy
//   SIMPLE_RADIAL  f, cx, cy, k1
//   RADIAL         f, cx, cy, k1, k2
//   OPENCV         fx, fy, cx, cy, k1, k2, p1, p2
// Throws colmap_lidar::Error naming Synthesis.camera_model for another model.
Camera SynthCamera(const SynthesisOptions& options);

// Empty when the camera of the options can be rendered, otherwise the
// reason: an unknown model, a coefficient the model does not have set to a
// non-zero value, or a distortion that is not invertible over the image
// (undistorting pixels along rays from the principal point to the image
// border must round-trip through ImgFromCam to 1e-6 pixels and give
// strictly increasing radii; strong barrel distortion folds over beyond
// some radius and fails this). Used by SynthesisOptions::Check().
std::string SynthCameraProblem(const SynthesisOptions& options);

// The rig's LIDAR-to-camera transform: the LIDAR sits 10 cm above and 4 cm
// behind the camera, its x axis (forward) along the camera's z, its y
// (left) along the camera's -x and its z (up) along the camera's -y.
Rigid3d SynthCamFromLidar();

// Frame names: 000000, 000001, ...
std::string SynthFrameName(int frame_index);

// Writes the crease edges as text, one per line:
//   x1 y1 z1 x2 y2 z2 n1x n1y n1z n2x n2y n2z convex angle_deg
// (world frame, metres; n1, n2 the outward unit normals of the two faces;
// convex 1 for an outer corner, 0 for an inner one; angle between the
// normals). Lines starting with '#' are comments. Atomic.
void WriteCreaseEdges(const std::string& path,
                      const std::vector<CreaseEdge>& edges);
// Reads the format above; throws naming the path and line on error.
std::vector<CreaseEdge> ReadCreaseEdges(const std::string& path);

// Writes the borders of painted road marks (texture edges on flat ground,
// not creases) as text, one per line: x1 y1 z1 x2 y2 z2 (world frame,
// metres). Lines starting with '#' are comments. Atomic.
void WritePaintEdges(const std::string& path,
                     const std::vector<PaintEdge>& edges);
// Reads the format above; throws naming the path and line on error.
std::vector<PaintEdge> ReadPaintEdges(const std::string& path);

// Writes the mesh as binary PLY: vertex x y z (float) and material (uchar,
// the Material enum value), face vertex_indices. Atomic.
void WriteSceneMesh(const std::string& path, const SceneMesh& mesh);

// Generates the dataset. Throws colmap_lidar::Error when the options fail
// Check(), when output_path exists and is not empty while
// options.overwrite is false, or on any write failure (naming the file).
SynthesisSummary SynthesizeDataset(const SynthesisOptions& options,
                                   const std::string& output_path);

}  // namespace colmap_lidar
