#include "src/sfm/initial_poses.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <sstream>
#include <utility>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/sfm/lidar_pose_graph.h"
#include "src/sfm/model_alignment.h"
#include "src/sfm/stock_colmap_steps.h"

namespace colmap_lidar {
namespace {

// init_method "lidar_graph": the graph's poses for every image, and its
// accepted edges as RelativePoseEdges of the adjustment.
void InitializeFromLidarGraph(const LidarMapperPaths& paths,
                              const LidarMapperOptions& options,
                              const std::string& work_path,
                              const Database& database, InitialPoses* init,
                              LidarMapperSummary* summary) {
  LidarPoseGraphOptions graph_options = options.lidar_graph;
  graph_options.prior_position_sigma_m = options.prior_position_sigma_m;
  graph_options.prior_rotation_sigma_deg = options.prior_rotation_sigma_deg;
  graph_options.num_threads = options.num_threads;
  const LidarPoseGraphResult graph =
      LidarGraphPoses(database, graph_options, &init->model);
  LOG(INFO) << "lidar_mapper: " << graph.Format() << "\n"
            << graph.FormatEdges();
  WriteReconstruction(JoinPaths(work_path, "lidar_graph"),
                      PosesOnly(init->model), ModelFormat::kBinary);
  for (const LidarPoseGraphEdge& graph_edge : graph.edges) {
    if (!graph_edge.used) {
      continue;
    }
    RelativePoseEdge edge;
    edge.image_id1 = graph.image_ids.at(graph_edge.i);
    edge.image_id2 = graph.image_ids.at(graph_edge.j);
    edge.lidar1_from_lidar2 = graph_edge.registration.target_from_source;
    edge.cam1_from_lidar = graph.cam_from_lidar.at(graph_edge.i);
    edge.cam2_from_lidar = graph.cam_from_lidar.at(graph_edge.j);
    edge.sqrt_information = SqrtInformation(graph_edge.information);
    init->lidar_edges.push_back(edge);
  }
  summary->num_lidar_edges = static_cast<int>(init->lidar_edges.size());
  summary->init_alignment = graph.Format();
}

// The candidate models of init_method "mapper" (stock mapper runs, until
// one gives a model the prior alignment accepts) or "model" (the model at
// init_model_path), each aligned robustly to the priors on its own (stock
// mapper may write several, e.g. split where the walk turns on the spot).
// `num_registered`: the images of all candidates.
void AlignCandidateModels(const ColmapRunner& colmap,
                          const LidarMapperPaths& paths,
                          const LidarMapperOptions& options,
                          const std::string& work_path,
                          const std::unordered_map<image_t, Rigid3d>& priors,
                          std::vector<Reconstruction>* candidates,
                          std::vector<RobustPriorAlignmentSummary>* alignments,
                          int* num_registered) {
  RobustPriorAlignmentOptions alignment_options;
  alignment_options.position_sigma_m = options.prior_position_sigma_m;
  alignment_options.rotation_sigma_deg = options.prior_rotation_sigma_deg;
  alignment_options.min_num_inliers = options.init_min_num_inliers;
  alignment_options.min_inlier_ratio = options.init_min_inlier_ratio;
  // Stock mapper is randomised: a run that gives no acceptable model (on
  // small scenes one in a few builds a broken one, cameras turned by
  // 100 degrees) is repeated with another random seed.
  const int num_attempts =
      options.init_method == "model" ? 1 : options.mapper_num_attempts;
  for (int attempt = 0; attempt < num_attempts; ++attempt) {
    candidates->clear();
    alignments->clear();
    *num_registered = 0;
    if (options.init_method == "model") {
      THROW_CHECK(ExistsModel(options.init_model_path),
                  "lidar_mapper: init_model_path "
                      << options.init_model_path << " holds no sparse model");
      candidates->push_back(ReadReconstruction(options.init_model_path));
    } else {
      const std::string mapper_path = JoinPaths(work_path, "mapper");
      std::filesystem::remove_all(mapper_path);
      CreateDirIfNotExists(mapper_path);
      LOG(INFO) << "lidar_mapper: stock mapper for the initial poses"
                << " (random seed " << attempt << ")";
      try {
        std::vector<std::pair<std::string, std::string>> args = {
            {"database_path", paths.database_path},
            {"image_path", paths.image_path},
            {"output_path", mapper_path},
            {"random_seed", std::to_string(attempt)}};
        AppendStockMapperArgs(options, &args);
        colmap.Run("mapper", args);
        *candidates = ReadMapperModels(mapper_path);
      } catch (const Error& error) {
        LOG(WARNING) << "lidar_mapper: stock mapper failed (" << error.what()
                     << ")";
      }
    }
    bool any_accepted = false;
    for (Reconstruction& candidate : *candidates) {
      *num_registered += static_cast<int>(candidate.images.size());
      alignments->push_back(RobustAlignReconstructionToPriors(
          priors, alignment_options, &candidate));
      any_accepted = any_accepted || alignments->back().accepted;
      LOG(INFO) << "lidar_mapper: initial model of "
                << candidate.images.size()
                << " images: " << alignments->back().Format();
    }
    if (any_accepted) {
      break;
    }
    if (attempt + 1 < num_attempts) {
      LOG(WARNING) << "lidar_mapper: no stock mapper model agrees with the "
                      "priors; running stock mapper again";
    }
  }
}

// init_method "mapper" or "model": accepted models give their consensus
// images, the largest consensus first (an image is taken once); the images
// they registered outside a consensus are held out. Without an accepted
// model the run continues as "priors" (the fallback).
void InitializeFromModels(const ColmapRunner& colmap,
                          const LidarMapperPaths& paths,
                          const LidarMapperOptions& options,
                          const std::string& work_path,
                          const std::unordered_map<image_t, Rigid3d>& priors,
                          InitialPoses* init, LidarMapperSummary* summary) {
  Reconstruction& model = init->model;
  std::unordered_map<image_t, bool>& held_out = init->held_out;
  std::vector<Reconstruction> candidates;
  std::vector<RobustPriorAlignmentSummary> alignments;
  int num_registered = 0;
  AlignCandidateModels(colmap, paths, options, work_path, priors, &candidates,
                       &alignments, &num_registered);
  std::vector<size_t> order(candidates.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return alignments[a].inlier_image_ids.size() >
           alignments[b].inlier_image_ids.size();
  });
  std::unordered_map<image_t, bool> initialised;
  std::ostringstream alignment_text;
  double sum_squared_rms = 0.0;
  int num_accepted = 0;
  for (const size_t index : order) {
    const RobustPriorAlignmentSummary& alignment = alignments[index];
    alignment_text << (alignment_text.tellp() > 0 ? "; " : "")
                   << candidates[index].images.size()
                   << " images: " << alignment.Format();
    if (!alignment.accepted) {
      continue;
    }
    ++num_accepted;
    for (const image_t image_id : alignment.inlier_image_ids) {
      const Image* mapped_image = candidates[index].FindImage(image_id);
      Image* image = model.FindImage(image_id);
      if (mapped_image != nullptr && image != nullptr &&
          !initialised[image_id]) {
        image->cam_from_world = mapped_image->cam_from_world;
        initialised[image_id] = true;
        sum_squared_rms += alignment.rms_residual_m * alignment.rms_residual_m;
      }
    }
  }
  summary->init_alignment = alignment_text.str();
  int num_initialised = 0;
  for (const auto& [image_id, done] : initialised) {
    num_initialised += done ? 1 : 0;
  }
  if (num_accepted == 0) {
    // No trustworthy relative poses: continue as init_method "priors".
    LOG(WARNING) << "lidar_mapper: initial model rejected ("
                 << (candidates.empty() ? std::string("no model")
                                        : summary->init_alignment)
                 << "); starting from the prior poses instead";
    init->points_only_first = true;
    summary->init_used = "priors (fallback)";
    return;
  }
  summary->num_initial_images = num_initialised;
  summary->prior_alignment_rms_m = std::sqrt(sum_squared_rms / num_initialised);
  summary->num_init_outliers = num_registered - num_initialised;
  for (const Reconstruction& candidate : candidates) {
    for (const Image& image : candidate.images) {
      if (!initialised[image.image_id] &&
          model.FindImage(image.image_id) != nullptr) {
        held_out[image.image_id] = true;
      }
    }
  }
  // Images the mapper did not register at all join at their prior
  // pose: their observations triangulate with their neighbours' and the
  // adjustment moves them (on the default scene frames 12-18, 0.5-1.2 m
  // off, end within 2 cm after sim3); image_registrator could not place
  // them, as they see few points triangulated without them.
  summary->num_pending_images = static_cast<int>(held_out.size());
  LOG(INFO) << "lidar_mapper: " << num_initialised << " of "
            << model.images.size() << " images start at the pose of "
            << num_accepted << " accepted initial model(s), the others ("
            << summary->num_init_outliers
            << " registered outside a consensus) at their prior pose"
            << (options.register_pending_images && !held_out.empty()
                    ? "; those wait for image_registrator"
                    : std::string());
}

}  // namespace

InitialPoses InitializePoses(const ColmapRunner& colmap,
                             const LidarMapperPaths& paths,
                             const LidarMapperOptions& options,
                             const std::string& work_path,
                             const Database& database,
                             const Reconstruction& prior_model,
                             const std::unordered_map<image_t, Rigid3d>& priors,
                             LidarMapperSummary* summary) {
  InitialPoses init;
  init.model = prior_model;
  init.points_only_first = options.init_method == "priors";
  summary->init_used = options.init_method;
  summary->num_initial_images = static_cast<int>(init.model.images.size());
  if (options.init_method == "lidar_graph") {
    InitializeFromLidarGraph(paths, options, work_path, database, &init,
                             summary);
  } else if (options.init_method != "priors") {
    InitializeFromModels(colmap, paths, options, work_path, priors, &init,
                         summary);
  }
  return init;
}

}  // namespace colmap_lidar
