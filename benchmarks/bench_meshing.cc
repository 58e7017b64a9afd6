// Time and peak memory of the Delaunay mesher (src/mesh) on the synthetic
// box-on-ground scene, sampled to a requested number of visual points, plus
// the accuracy of the mesh. One run per process, because the peak resident
// set (VmHWM) only grows:
//
//   build/benchmarks/bench_meshing [num_points=1000000] [max_proj_dist_px=2]
//                                  [num_threads=2]
//
// Prints one table row: points, Delaunay vertices, cells, rays, stage
// seconds, peak memory and bytes per input point, face-to-surface distance
// percentiles and coverage of the observed true surface at 1 cm.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "src/mesh/delaunay_mesher.h"
#include "src/mesh/synthetic_box_scene.h"

using namespace colmap_lidar;

int main(int argc, char** argv) {
  const double num_points = argc > 1 ? std::atof(argv[1]) : 1e6;
  DelaunayMeshingOptions options;
  options.max_proj_dist_px = argc > 2 ? std::atof(argv[2]) : 2.0;
  options.num_threads = argc > 3 ? std::atoi(argv[3]) : 2;

  // About 29 m^2 of observed surface (box 4.2 m^2, ground 25 m^2).
  SyntheticBoxSceneOptions scene_options;
  scene_options.noise_m = 0.001;
  scene_options.box_spacing_m = std::sqrt(29.0 / num_points);
  scene_options.ground_spacing_m = scene_options.box_spacing_m;
  const SyntheticBoxScene scene(scene_options);
  const SyntheticPoints points = scene.SampleVisualPoints();
  const MeshingInput input = MakeVisualMeshingInput(scene, points);
  const size_t memory_before = PeakResidentMemoryBytes();

  DelaunayMeshingSummary summary;
  const TriangleMesh mesh = DelaunayMeshing(options, input, &summary);

  std::vector<double> distances;
  for (size_t i = 0; i < mesh.faces.size(); ++i) {
    const auto& face = mesh.faces[i];
    distances.push_back(scene.DistanceToSurface(
        (mesh.vertices[face[0]] + mesh.vertices[face[1]] +
         mesh.vertices[face[2]]) / 3));
  }
  std::sort(distances.begin(), distances.end());
  auto percentile = [&](double p) {
    return distances.empty()
               ? 0.0
               : distances[std::min(distances.size() - 1,
                                    static_cast<size_t>(p * distances.size()))];
  };
  const SyntheticPoints truth = scene.SampleTrueSurface(0.05, 2);
  const MeshDistance mesh_distance(mesh);
  size_t num_covered = 0;
  for (const Eigen::Vector3d& point : truth.positions) {
    num_covered += mesh_distance.Distance(point) <= 0.01 ? 1 : 0;
  }

  std::printf(
      "%10s %9s %9s %9s %7s %7s %7s %7s %9s %9s %9s %9s %8s %8s\n", "points",
      "vertices", "cells", "rays", "tri_s", "vis_s", "cut_s", "total_s",
      "peak_MiB", "input_MiB", "B/point", "faces", "p50_mm", "p95_mm");
  std::printf(
      "%10zu %9zu %9zu %9zu %7.1f %7.1f %7.1f %7.1f %9.0f %9.0f %9.0f %9zu "
      "%8.2f %8.2f\n",
      summary.num_input_points, summary.num_vertices, summary.num_cells,
      summary.num_rays, summary.triangulation_seconds,
      summary.visibility_seconds, summary.graph_cut_seconds,
      summary.total_seconds, summary.peak_memory_bytes / 1048576.0,
      memory_before / 1048576.0,
      static_cast<double>(summary.peak_memory_bytes) /
          summary.num_input_points,
      summary.num_faces, 1e3 * percentile(0.5), 1e3 * percentile(0.95));
  std::printf("coverage at 1 cm: %.4f of %zu observed true-surface samples\n",
              static_cast<double>(num_covered) / truth.positions.size(),
              truth.positions.size());
  return EXIT_SUCCESS;
}
