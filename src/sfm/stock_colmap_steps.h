// The stock colmap runs of lidar_mapper (src/sfm/lidar_mapper.h): features
// and matches, the stock mapper's arguments and models, point triangulation
// with fixed poses, and the registration of pending images. Each step is a
// `colmap` subcommand run through ColmapRunner with lidar_mapper's options.
#pragma once

#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "colmap_ext/runner/colmap_runner.h"
#include "colmap_ext/scene/reconstruction.h"
#include "src/sfm/lidar_mapper.h"

namespace colmap_lidar {

// The value of colmap's *.num_threads options: -1 (all cores) for <= 0.
std::string ThreadsArg(int num_threads);

// Stock feature_extractor (CPU SIFT) with the SiftExtraction.* options on
// the images of the database (num_images of them, for the log).
void RunStockFeatureExtractor(const ColmapRunner& colmap,
                              const LidarMapperPaths& paths,
                              const LidarMapperOptions& options,
                              int num_images);

// Stock exhaustive_matcher up to exhaustive_max_num_images images, else
// sequential_matcher (stock matchers skip pairs already matched).
void RunStockMatcher(const ColmapRunner& colmap, const LidarMapperPaths& paths,
                     const LidarMapperOptions& options, int num_images);

// The Mapper.* options of stock `mapper` and `image_registrator`: the
// calibrated intrinsics stay fixed, lidar_mapper's PnP thresholds.
void AppendStockMapperArgs(
    const LidarMapperOptions& options,
    std::vector<std::pair<std::string, std::string>>* args);

// The models colmap mapper writes (numbered sub-folders).
std::vector<Reconstruction> ReadMapperModels(const std::string& mapper_path);

// The model with poses only (no points, no observations): what stock
// point_triangulator gets, so that it fills points2D from the database.
Reconstruction PosesOnly(const Reconstruction& model);

// Stock point_triangulator with the poses of `poses` (written to
// poses_path) and the intrinsics held fixed (--clear_points 1); returns the
// model it writes to triangulated_path.
Reconstruction TriangulatePoints(const ColmapRunner& colmap,
                                 const LidarMapperPaths& paths,
                                 const LidarMapperOptions& options,
                                 const Reconstruction& poses,
                                 const std::string& poses_path,
                                 const std::string& triangulated_path);

// Registers the images of `pending` (absent from the model at
// `model_path`) with stock image_registrator and takes each registered pose
// that lies inside the 99.9 % region of its prior; those images leave
// `pending`. Returns their count. A failed registrator run is a warning:
// the images keep waiting at their prior pose.
int RegisterPendingImages(const ColmapRunner& colmap,
                          const LidarMapperPaths& paths,
                          const LidarMapperOptions& options,
                          const std::string& model_path,
                          const std::string& output_path,
                          const std::unordered_map<image_t, Rigid3d>& priors,
                          std::unordered_map<image_t, bool>* pending,
                          Reconstruction* model);

}  // namespace colmap_lidar
