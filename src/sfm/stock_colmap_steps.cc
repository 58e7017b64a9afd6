#include "src/sfm/stock_colmap_steps.h"

#include <filesystem>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/sfm/pose_prior_checks.h"

namespace colmap_lidar {

std::string ThreadsArg(int num_threads) {
  return std::to_string(num_threads <= 0 ? -1 : num_threads);
}

void RunStockFeatureExtractor(const ColmapRunner& colmap,
                              const LidarMapperPaths& paths,
                              const LidarMapperOptions& options,
                              int num_images) {
  LOG(INFO) << "lidar_mapper: feature_extractor (CPU SIFT) on " << num_images
            << " images";
  colmap.Run("feature_extractor",
             {{"database_path", paths.database_path},
              {"image_path", paths.image_path},
              {"SiftExtraction.use_gpu", "0"},
              {"SiftExtraction.num_threads", ThreadsArg(options.num_threads)},
              {"SiftExtraction.max_image_size",
               std::to_string(options.sift_max_image_size)},
              {"SiftExtraction.max_num_features",
               std::to_string(options.sift_max_num_features)}});
}

void RunStockMatcher(const ColmapRunner& colmap, const LidarMapperPaths& paths,
                     const LidarMapperOptions& options, int num_images) {
  const std::string threads = ThreadsArg(options.num_threads);
  if (num_images <= options.exhaustive_max_num_images) {
    LOG(INFO) << "lidar_mapper: exhaustive_matcher";
    colmap.Run("exhaustive_matcher", {{"database_path", paths.database_path},
                                      {"SiftMatching.use_gpu", "0"},
                                      {"SiftMatching.num_threads", threads}});
  } else {
    LOG(INFO) << "lidar_mapper: sequential_matcher, overlap "
              << options.sequential_overlap;
    colmap.Run("sequential_matcher",
               {{"database_path", paths.database_path},
                {"SiftMatching.use_gpu", "0"},
                {"SiftMatching.num_threads", threads},
                {"SequentialMatching.overlap",
                 std::to_string(options.sequential_overlap)},
                {"SequentialMatching.quadratic_overlap",
                 options.sequential_quadratic_overlap ? "1" : "0"}});
  }
}

void AppendStockMapperArgs(
    const LidarMapperOptions& options,
    std::vector<std::pair<std::string, std::string>>* args) {
  args->insert(
      args->end(),
      {{"Mapper.ba_refine_focal_length", "0"},
       {"Mapper.ba_refine_principal_point", "0"},
       {"Mapper.ba_refine_extra_params", "0"},
       {"Mapper.abs_pose_min_num_inliers",
        std::to_string(options.mapper_abs_pose_min_num_inliers)},
       {"Mapper.abs_pose_min_inlier_ratio",
        std::to_string(options.mapper_abs_pose_min_inlier_ratio)},
       {"Mapper.num_threads", ThreadsArg(options.num_threads)}});
}

std::vector<Reconstruction> ReadMapperModels(const std::string& mapper_path) {
  std::vector<Reconstruction> models;
  for (const auto& entry : std::filesystem::directory_iterator(mapper_path)) {
    if (entry.is_directory() && ExistsModel(entry.path().string())) {
      models.push_back(ReadReconstruction(entry.path().string()));
    }
  }
  return models;
}

Reconstruction PosesOnly(const Reconstruction& model) {
  Reconstruction poses;
  poses.cameras = model.cameras;
  for (const Image& image : model.images) {
    Image copy;
    copy.image_id = image.image_id;
    copy.name = image.name;
    copy.camera_id = image.camera_id;
    copy.cam_from_world = image.cam_from_world;
    poses.images.push_back(std::move(copy));
  }
  return poses;
}

Reconstruction TriangulatePoints(const ColmapRunner& colmap,
                                 const LidarMapperPaths& paths,
                                 const LidarMapperOptions& options,
                                 const Reconstruction& poses,
                                 const std::string& poses_path,
                                 const std::string& triangulated_path) {
  WriteReconstruction(poses_path, poses, ModelFormat::kBinary);
  CreateDirIfNotExists(triangulated_path);
  colmap.Run("point_triangulator",
             {{"database_path", paths.database_path},
              {"image_path", paths.image_path},
              {"input_path", poses_path},
              {"output_path", triangulated_path},
              {"clear_points", "1"},
              {"Mapper.ba_refine_focal_length", "0"},
              {"Mapper.ba_refine_principal_point", "0"},
              {"Mapper.ba_refine_extra_params", "0"},
              {"Mapper.filter_max_reproj_error",
               std::to_string(options.triangulation_max_error_px)},
              {"Mapper.num_threads", ThreadsArg(options.num_threads)}});
  return ReadReconstruction(triangulated_path);
}

int RegisterPendingImages(const ColmapRunner& colmap,
                          const LidarMapperPaths& paths,
                          const LidarMapperOptions& options,
                          const std::string& model_path,
                          const std::string& output_path,
                          const std::unordered_map<image_t, Rigid3d>& priors,
                          std::unordered_map<image_t, bool>* pending,
                          Reconstruction* model) {
  std::filesystem::remove_all(output_path);
  CreateDirIfNotExists(output_path);
  Reconstruction registered;
  try {
    std::vector<std::pair<std::string, std::string>> args = {
        {"database_path", paths.database_path},
        {"input_path", model_path},
        {"output_path", output_path}};
    AppendStockMapperArgs(options, &args);
    colmap.Run("image_registrator", args);
    registered = ReadReconstruction(output_path);
  } catch (const Error& error) {
    LOG(WARNING) << "lidar_mapper: image_registrator failed (" << error.what()
                 << "); " << pending->size()
                 << " images keep their prior pose";
    return 0;
  }
  int num_taken = 0;
  int num_far = 0;
  for (auto it = pending->begin(); it != pending->end();) {
    const Image* image = registered.FindImage(it->first);
    Image* target = model->FindImage(it->first);
    if (image == nullptr || target == nullptr) {
      ++it;
      continue;
    }
    if (PriorOutlierLevel(image->cam_from_world, priors.at(it->first),
                          options.prior_position_sigma_m,
                          options.prior_rotation_sigma_deg) > 0) {
      ++num_far;
      ++it;
      continue;
    }
    target->cam_from_world = image->cam_from_world;
    ++num_taken;
    it = pending->erase(it);
  }
  LOG(INFO) << "lidar_mapper: image_registrator placed " << num_taken
            << " pending images (" << num_far
            << " registered outside their prior's region, not taken); "
            << pending->size() << " still pending";
  return num_taken;
}

}  // namespace colmap_lidar
