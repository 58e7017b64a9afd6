// Step 5 of lidar_mapper (src/sfm/lidar_mapper.h), as COLMAP's mapper
// alternates adjustment and triangulation: stock point_triangulator with the
// current poses -> registration of pending images -> line association ->
// LineBundleAdjuster -> outlier filtering -> convergence test and the guard
// of the poses against their priors.
#pragma once

#include <string>
#include <unordered_map>

#include "colmap_ext/database/database.h"
#include "colmap_ext/runner/colmap_runner.h"
#include "src/sfm/initial_poses.h"
#include "src/sfm/lidar_mapper.h"

namespace colmap_lidar {

// Points of `model` triangulated anew by stock point_triangulator at its
// current poses (held fixed, as are the intrinsics), images in held_out
// left out; the observations replace the images' points2D. Returns the
// model of the images it ran on (poses only). Throws like
// TriangulatePoints.
Reconstruction TriangulateAtPoses(
    const ColmapRunner& colmap, const LidarMapperPaths& paths,
    const LidarMapperOptions& options, const std::string& work_path,
    const std::unordered_map<image_t, bool>& held_out, Reconstruction* model);

// When lidar_mapper keeps poses other than those of its last adjustment
// (CheckLidarEdges restored the LIDAR graph's), the points and lines that
// adjustment moved with its poses no longer fit them (up to the poses'
// change: 0.44 m on the KITTI sample) and would seed the depth maps and
// the mesh's line samples off the surface. They are rebuilt at the kept
// poses: points by TriangulateAtPoses, lines from the database's last
// association, each placed from its LIDAR endpoints (else its views) and
// kept when its reprojection error is at most options.max_line_error_px.
void RebuildStructureAtPoses(const ColmapRunner& colmap,
                             const LidarMapperPaths& paths,
                             const LidarMapperOptions& options,
                             const std::string& work_path,
                             const std::unordered_map<image_t, bool>& held_out,
                             const Database& database, Reconstruction* model);

// Runs up to options.max_num_iterations iterations on init->model (leaving
// the points, line tracks and poses of the last kept iteration in it) and
// init->held_out (pending images leave it when registered). The
// association replaces the database's line matches and tracks. Appends
// each iteration to summary->iterations and fills num_registered_pending,
// adjustment_seconds, num_rejected_iterations, num_reset_images and
// converged.
void RunMapperIterations(const ColmapRunner& colmap,
                         const LidarMapperPaths& paths,
                         const LidarMapperOptions& options,
                         const std::string& work_path,
                         const std::unordered_map<image_t, Rigid3d>& priors,
                         Database* database, InitialPoses* init,
                         LidarMapperSummary* summary);

}  // namespace colmap_lidar
