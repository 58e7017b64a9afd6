#include "src/mvs/lidar_patch_match_stereo.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <unordered_map>

#include <glog/logging.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "colmap_ext/mvs/stereo_config.h"
#include "colmap_ext/mvs/workspace.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/process_group.h"
#include "src/mvs/interpolation.h"
#include "src/mvs/map_filter.h"
#include "src/mvs/ncc_cost.h"
#include "src/mvs/own_scan.h"
#include "src/mvs/patch_match.h"
#include "src/mvs/source_views.h"
#include "src/mvs/textureless_fill.h"

namespace colmap_lidar {
namespace {

float Percentile(std::vector<float> values, double fraction) {
  const size_t k = std::min(values.size() - 1,
                            static_cast<size_t>(fraction * values.size()));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

void CreateParentDir(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return;
  const std::string dir = path.substr(0, slash);
  // Creates nested folders one level at a time.
  size_t pos = 0;
  while ((pos = dir.find('/', pos + 1)) != std::string::npos) {
    CreateDirIfNotExists(dir.substr(0, pos));
  }
  CreateDirIfNotExists(dir);
}

bool MapsExist(const DenseWorkspace& workspace, const std::string& name,
               DenseMapType type) {
  return ExistsFile(workspace.DepthMapPath(name, type)) &&
         ExistsFile(workspace.NormalMapPath(name, type));
}

// True, logged, when the maps of this type exist and are kept (a resumed
// run, unless options.overwrite); reference `j` of `num_jobs`.
bool KeepDoneMaps(const DenseWorkspace& workspace,
                  const LidarPatchMatchOptions& options,
                  const std::string& name, DenseMapType type, size_t j,
                  size_t num_jobs) {
  if (options.overwrite || !MapsExist(workspace, name, type)) return false;
  LOG(INFO) << "[" << j + 1 << "/" << num_jobs << "] " << name << ": "
            << (type == DenseMapType::kPhotometric ? "photometric"
                                                   : "geometric")
            << " maps exist, skipped";
  return true;
}

void WriteMaps(const DenseWorkspace& workspace, const std::string& name,
               DenseMapType type, const PlaneMap& map) {
  const std::string depth_path = workspace.DepthMapPath(name, type);
  const std::string normal_path = workspace.NormalMapPath(name, type);
  CreateParentDir(depth_path);
  CreateParentDir(normal_path);
  // Normal first: a depth map never exists without its normal map, which
  // would abort stock fusion (colmap-formats.md 4.2).
  ToNormalMap(map).Write(normal_path);
  ToDepthMap(map).Write(depth_path);
}

std::string FusionMaskPath(const DenseWorkspace& workspace,
                           const std::string& name) {
  return JoinPaths(FusionMaskDir(workspace.Path()), name + ".png");
}

// 8-bit PNG, 0 where `not_fused` is 1, else 255 (stereo_fusion skips the
// pixels of a mask that are 0).
void WriteFusionMask(const std::string& path,
                     const std::vector<uint8_t>& not_fused, int width,
                     int height) {
  THROW_CHECK(not_fused.size() == static_cast<size_t>(width) * height,
              "fusion mask of " << not_fused.size() << " pixels for "
                                << width << "x" << height << ": " << path);
  const cv::Mat flags(height, width, CV_8UC1,
                      const_cast<uint8_t*>(not_fused.data()));
  const cv::Mat mask = flags == 0;  // 255 where true.
  std::vector<uchar> png;
  THROW_CHECK(cv::imencode(".png", mask, png), "Cannot encode " << path);
  CreateParentDir(path);
  WriteFileAtomically(path, [&png](std::ostream& stream) {
    stream.write(reinterpret_cast<const char*>(png.data()),
                 static_cast<std::streamsize>(png.size()));
  });
}

// Views and maps loaded on demand, keeping only what the current reference
// needs (bounded memory for long sequences).
class WorkspaceCache {
 public:
  WorkspaceCache(const DenseWorkspace& workspace, const Reconstruction& model,
                 int max_image_size)
      : workspace_(workspace), model_(model), max_image_size_(max_image_size) {}

  void Retain(const std::vector<int>& indices) {
    for (auto it = views_.begin(); it != views_.end();) {
      it = std::find(indices.begin(), indices.end(), it->first) == indices.end()
               ? views_.erase(it)
               : std::next(it);
    }
    for (auto it = maps_.begin(); it != maps_.end();) {
      it = std::find(indices.begin(), indices.end(), it->first) == indices.end()
               ? maps_.erase(it)
               : std::next(it);
    }
  }

  const MvsView& View(int idx) {
    auto& view = views_[idx];
    if (!view) {
      const Image& image = model_.images[idx];
      view = std::make_unique<MvsView>(LoadMvsView(
          workspace_.ImagePath(image.name), model_.cameras.at(image.camera_id),
          image, max_image_size_));
    }
    return *view;
  }

  // The photometric maps of image idx; nullptr when missing or of another
  // size than the view.
  const PlaneMap* PhotometricMap(int idx) {
    auto it = maps_.find(idx);
    if (it == maps_.end()) {
      const std::string& name = model_.images[idx].name;
      std::unique_ptr<PlaneMap> map;
      if (MapsExist(workspace_, name, DenseMapType::kPhotometric)) {
        map = std::make_unique<PlaneMap>(FromDenseMaps(
            DepthMap::Read(workspace_.DepthMapPath(name, DenseMapType::kPhotometric)),
            NormalMap::Read(
                workspace_.NormalMapPath(name, DenseMapType::kPhotometric))));
        const MvsView& view = View(idx);
        if (map->width != view.width || map->height != view.height) {
          LOG(WARNING) << "Photometric map of " << name << " is "
                       << map->width << "x" << map->height
                       << ", not the view's size; not used";
          map.reset();
        }
      }
      it = maps_.emplace(idx, std::move(map)).first;
    }
    return it->second.get();
  }

 private:
  const DenseWorkspace& workspace_;
  const Reconstruction& model_;
  const int max_image_size_;
  std::map<int, std::unique_ptr<MvsView>> views_;
  std::map<int, std::unique_ptr<PlaneMap>> maps_;
};

// The cost filter; with a soft LIDAR prior, pixels that agree with it are
// kept whatever their photometric cost.
size_t FilterMaps(float max_cost, const std::vector<float>& prior_depth,
                  const LidarPatchMatchOptions& options, PlaneMap* map) {
  if (prior_depth.empty() || !(options.lidar_prior_weight > 0)) {
    return FilterByCost(max_cost, map);
  }
  return FilterByCostOrPrior(max_cost, prior_depth,
                             static_cast<float>(options.lidar_prior_tolerance),
                             map);
}

// World points of the sparse features the image observes.
std::vector<Eigen::Vector3f> FeaturesOf(const Reconstruction& model,
                                        const Image& image) {
  std::vector<Eigen::Vector3f> features;
  for (const Point2D& point2D : image.points2D) {
    if (point2D.point3D_id == kInvalidPoint3DId) continue;
    const auto it = model.points3D.find(point2D.point3D_id);
    if (it != model.points3D.end()) {
      features.push_back(it->second.xyz.cast<float>());
    }
  }
  return features;
}

// Runs one pass of this rank's images; every rank then meets the others
// (ProcessGroup::CheckAllOk) before the next pass reads their maps, and a
// rank's error ends the job on every rank.
template <typename Pass>
void RunPassOnAllRanks(const ProcessGroup& group, const std::string& what,
                       Pass&& pass) {
  std::exception_ptr error;
  try {
    pass();
  } catch (...) {
    error = std::current_exception();
  }
  group.CheckAllOk(error, what);
}

// The counts of every rank's summary, summed on every rank.
void SumOverRanks(const ProcessGroup& group, LidarPatchMatchSummary* summary) {
  if (!group.Distributed()) return;
  std::vector<size_t*> counts = {
      &summary->num_not_fused,           &summary->num_filled,
      &summary->support.images_only,     &summary->support.images_and_lidar,
      &summary->support.lidar_and_views, &summary->support.lidar_only};
  std::vector<int*> ints = {
      &summary->num_photometric_computed, &summary->num_photometric_skipped,
      &summary->num_geometric_computed, &summary->num_geometric_skipped};
  std::vector<double> values;
  for (size_t* count : counts) values.push_back(static_cast<double>(*count));
  for (int* count : ints) values.push_back(*count);
  values = group.Sum(values);
  for (size_t i = 0; i < counts.size(); ++i) {
    *counts[i] = static_cast<size_t>(values[i]);
  }
  for (size_t i = 0; i < ints.size(); ++i) {
    *ints[i] = static_cast<int>(values[counts.size() + i]);
  }
}

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

std::vector<float> DensePriorDepth(const PlaneMap& interpolated) {
  std::vector<float> prior = interpolated.depth;
  for (float& depth : prior) {
    if (!(depth > 0)) depth = 0.0f;
  }
  return prior;
}

ReferenceInit InitializeReference(
    const MvsView& ref, const std::vector<Eigen::Vector3f>& features_in_world,
    const FusedLidarCloud* lidar, int ref_image_idx,
    const LidarPatchMatchOptions& options) {
  ReferenceInit init;
  std::vector<DepthSample> lidar_samples;
  if (lidar != nullptr) {
    lidar_samples = ProjectLidarSamples(ref, lidar->points, lidar->normals,
                                        options, &init.stats);
  }
  const std::vector<DepthSample> samples = MergeFeatureSamples(
      ref, features_in_world, lidar_samples, options, &init.stats);
  std::vector<float> depths;
  for (const DepthSample& sample : samples) {
    if (sample.from_feature || !options.RandomInit() ||
        init.stats.num_features == 0) {
      depths.push_back(sample.depth);
    }
  }
  THROW_CHECK(!depths.empty(),
              "view " << ref.name
                      << " sees no sparse point and no LIDAR point: no depth "
                         "range for PatchMatch");
  init.depth_min = std::max(static_cast<float>(options.min_depth),
                            Percentile(depths, 0.01) / 1.5f);
  init.depth_max = std::max(init.depth_min * 1.01f, Percentile(depths, 0.99) * 1.5f);
  if (options.RandomInit()) {
    init.state = PlaneMap(ref.width, ref.height);
  } else {
    std::vector<uint8_t> across_depth_edge;
    init.state = InterpolateSamples(ref, samples, options, &across_depth_edge);
    if (lidar != nullptr && options.lidar_own_scan_min_incidence_deg < 90 &&
        ref_image_idx >= 0) {
      init.stats.num_own_scan_pixels = PreferOwnScan(
          ref,
          OwnScanSamples(ref, *lidar, static_cast<uint32_t>(ref_image_idx),
                         features_in_world, options),
          options, &init.state, &across_depth_edge);
    }
    init.prior_depth = DensePriorDepth(init.state);
    if (!options.lidar_prior_across_depth_edges) {
      for (size_t i = 0; i < across_depth_edge.size(); ++i) {
        if (across_depth_edge[i]) init.prior_depth[i] = 0.0f;
      }
    }
  }
  return init;
}

std::string FusionMaskDir(const std::string& workspace_path) {
  return JoinPaths(workspace_path, "stereo/fusion_masks");
}

LidarPatchMatchSummary RunLidarPatchMatchStereo(
    const std::string& workspace_path, const LidarPatchMatchOptions& options) {
  THROW_CHECK(options.Check(), "invalid LidarPatchMatch options");
  const auto start = std::chrono::steady_clock::now();
  const DenseWorkspace workspace(workspace_path);
  const Reconstruction model = workspace.ReadModel();
  const std::vector<PatchMatchEntry> entries =
      ReadPatchMatchConfig(workspace.PatchMatchConfigPath());
  const std::string lidar_path = JoinPaths(workspace_path, "lidar_fused.ply");
  FusedLidarCloud lidar;
  const bool have_lidar = ExistsFile(lidar_path);
  if (have_lidar) {
    lidar = ReadFusedLidarCloud(lidar_path);
  }
  THROW_CHECK(have_lidar || options.RandomInit(),
              "LidarPatchMatch.init lidar needs " << lidar_path
                                                  << " (run lidar_fuser)");
  LOG(INFO) << "PatchMatch on " << entries.size() << " reference images of "
            << workspace_path << " (init " << options.init << ", "
            << lidar.size() << " LIDAR voxels)";
  const SourceViewSelector selector(model, lidar.visibility, lidar.points,
                                    options);
  std::unordered_map<std::string, int> name_to_idx;
  for (size_t i = 0; i < model.images.size(); ++i) {
    name_to_idx[model.images[i].name] = static_cast<int>(i);
  }

  struct Job {
    int ref_idx;
    std::vector<int> srcs;
  };
  std::vector<Job> jobs;
  LidarPatchMatchSummary summary;
  for (const PatchMatchEntry& entry : entries) {
    const auto it = name_to_idx.find(entry.ref_image_name);
    THROW_CHECK(it != name_to_idx.end(),
                "reference image " << entry.ref_image_name << " of "
                                   << workspace.PatchMatchConfigPath()
                                   << " is not in the workspace model");
    Job job{it->second, selector.Select(it->second, entry)};
    if (job.srcs.empty()) {
      LOG(WARNING) << "Image " << entry.ref_image_name
                   << " has no source view; skipped";
      ++summary.num_without_sources;
      continue;
    }
    jobs.push_back(std::move(job));
  }
  summary.num_references = static_cast<int>(jobs.size());

  // Under mpirun each rank takes every Size()-th reference of each pass
  // (maps are per image and written atomically into the shared workspace;
  // the seeds are per image, so the maps are those of one process).
  const ProcessGroup& group = ProcessGroup::World();
  if (group.Distributed()) {
    LOG(INFO) << "Rank " << group.Rank() << " of " << group.Size() << ": "
              << (jobs.size() + group.Size() - 1 - group.Rank()) / group.Size()
              << " of the " << jobs.size() << " references";
  }
  WorkspaceCache cache(workspace, model, options.max_image_size);
  // This rank's references of a pass whose maps are still to compute, with
  // the cache holding the reference and its sources for `compute`.
  auto for_each_reference = [&](DenseMapType type, int* num_skipped,
                                const auto& compute) {
    for (size_t j = 0; j < jobs.size(); ++j) {
      if (!group.Owns(j)) continue;
      const Job& job = jobs[j];
      const Image& image = model.images[job.ref_idx];
      if (KeepDoneMaps(workspace, options, image.name, type, j, jobs.size())) {
        ++*num_skipped;
        continue;
      }
      // The image's time counts its views' loading.
      const auto image_start = std::chrono::steady_clock::now();
      std::vector<int> needed = job.srcs;
      needed.push_back(job.ref_idx);
      cache.Retain(needed);
      compute(j, job, image, cache.View(job.ref_idx), image_start);
    }
  };
  // Photometric pass.
  RunPassOnAllRanks(group, "PatchMatch, photometric pass", [&] {
    for_each_reference(
        DenseMapType::kPhotometric, &summary.num_photometric_skipped,
        [&](size_t j, const Job& job, const Image& image, const MvsView& ref,
            std::chrono::steady_clock::time_point image_start) {
          std::vector<const MvsView*> srcs;
          for (int s : job.srcs) srcs.push_back(&cache.View(s));
          ReferenceInit init = InitializeReference(
              ref, FeaturesOf(model, image), have_lidar ? &lidar : nullptr,
              job.ref_idx, options);
          size_t num_extrapolated = 0;
          if (!init.prior_depth.empty() && options.init_extrapolate_planes) {
            // After the prior is taken: the extrapolated planes carry none.
            num_extrapolated = ExtrapolateToEmptyPixels(ref, &init.state);
          }
          const PatchCostComputer cost(ref, srcs, options);
          PatchMatchProblem problem;
          problem.cost = &cost;
          problem.depth_min = init.depth_min;
          problem.depth_max = init.depth_max;
          problem.prior_depth =
              init.prior_depth.empty() ? nullptr : &init.prior_depth;
          RunPatchMatch(
              problem, options, options.num_iterations,
              static_cast<uint64_t>(options.seed) * 7919 + job.ref_idx,
              &init.state);
          const size_t kept =
              FilterMaps(static_cast<float>(options.filter_max_cost),
                         init.prior_depth, options, &init.state);
          WriteMaps(workspace, image.name, DenseMapType::kPhotometric,
                    init.state);
          ++summary.num_photometric_computed;
          LOG(INFO) << "[" << j + 1 << "/" << jobs.size() << "] " << image.name
                    << ": photometric, " << srcs.size() << " sources, "
                    << init.stats.num_lidar_zbuffer -
                           init.stats.num_lidar_occluded
                    << " LIDAR samples (" << init.stats.num_lidar_occluded
                    << " occluded), " << init.stats.num_own_scan_pixels
                    << " pixels from its own scan, " << init.stats.num_features
                    << " features, " << num_extrapolated
                    << " pixels started on an extrapolated plane, " << kept
                    << " valid pixels, " << Seconds(image_start) << " s";
        });
  });
  // Geometric pass.
  if (options.geom_consistency) {
    RunPassOnAllRanks(group, "PatchMatch, geometric pass", [&] {
      for_each_reference(
          DenseMapType::kGeometric, &summary.num_geometric_skipped,
          [&](size_t j, const Job& job, const Image& image, const MvsView& ref,
              std::chrono::steady_clock::time_point image_start) {
            // Only sources with photometric maps can confirm a depth (e.g. when
            // the references are a subset of the images and a source is none).
            std::vector<const MvsView*> srcs;
            std::vector<const PlaneMap*> src_maps;
            for (int s : job.srcs) {
              const PlaneMap* src_map = cache.PhotometricMap(s);
              if (src_map != nullptr) {
                srcs.push_back(&cache.View(s));
                src_maps.push_back(src_map);
              }
            }
            if (!options.visible_sources_only &&
                static_cast<int>(srcs.size()) <
                    options.filter_min_num_consistent) {
              LOG(WARNING) << image.name << ": " << srcs.size() << " of "
                           << job.srcs.size()
                           << " source views have photometric maps, fewer than "
                              "filter_min_num_consistent ("
                           << options.filter_min_num_consistent
                           << "): its geometric map is empty";
            }
            if (srcs.empty()) {
              WriteMaps(workspace, image.name, DenseMapType::kGeometric,
                        PlaneMap(ref.width, ref.height));
              ++summary.num_geometric_computed;
              return;
            }
            const PlaneMap* ref_map = cache.PhotometricMap(job.ref_idx);
            THROW_CHECK(ref_map != nullptr,
                        "no usable photometric maps of " << image.name);
            PlaneMap state = *ref_map;
            PatchCostComputer cost(ref, srcs, options);
            cost.SetSourceMaps(src_maps);
            std::vector<float> depths;
            for (float d : state.depth) {
              if (d > 0) depths.push_back(d);
            }
            THROW_CHECK(!depths.empty(), "photometric depth map of "
                                             << image.name << " is empty");
            PatchMatchProblem problem;
            problem.cost = &cost;
            problem.depth_min = std::max(static_cast<float>(options.min_depth),
                                         Percentile(depths, 0.0) / 1.2f);
            problem.depth_max = Percentile(depths, 1.0) * 1.2f;
            // The geometric pass keeps the soft LIDAR prior of the photometric
            // one. The consistency filter may count it as a view.
            std::vector<float> prior_depth;
            std::vector<Eigen::Vector3f> prior_normal;
            if (!options.RandomInit() && (options.lidar_prior_weight > 0 ||
                                          options.filter_lidar_as_view ||
                                          options.keep_lidar_where_unseen)) {
              ReferenceInit prior = InitializeReference(
                  ref, FeaturesOf(model, image), &lidar, job.ref_idx, options);
              prior_depth = std::move(prior.prior_depth);
              prior_normal = std::move(prior.state.normal);
            }
            if (options.lidar_prior_weight > 0) {
              problem.prior_depth =
                  prior_depth.empty() ? nullptr : &prior_depth;
            }
            RunPatchMatch(problem, options, options.num_geom_iterations,
                          static_cast<uint64_t>(options.seed) * 7919 +
                              job.ref_idx + 1000000,
                          &state);
            // Only here, not in the photometric pass: the photometric maps are
            // the other views' source maps, and pixels reset there moved
            // KITTI's fused cloud and mesh (in-view LIDAR within 0.1 m 81.1
            // -> 80.5 %), although none of them is fused.
            size_t num_unseen = 0;
            if (!prior_depth.empty() && options.keep_lidar_where_unseen) {
              num_unseen =
                  KeepLidarWhereUnseen(cost, prior_depth, prior_normal, &state);
            }
            FilterMaps(static_cast<float>(options.filter_max_cost +
                                          options.geom_consistency_regularizer *
                                              options.filter_max_reproj_error),
                       prior_depth, options, &state);
            std::vector<uint8_t> not_fused;
            DepthSupportCounts support;
            const size_t kept = FilterByConsistency(
                cost, options, prior_depth, &state, &not_fused, &support);
            summary.support += support;
            size_t num_filled = 0;
            if (options.fill_textureless_regions) {
              std::vector<uint8_t> textureless(state.depth.size(), 0);
              for (int row = 0; row < state.height; ++row) {
                for (int col = 0; col < state.width; ++col) {
                  textureless[state.Index(row, col)] =
                      cost.Textureless(row, col);
                }
              }
              TexturelessFillOptions fill_options;
              fill_options.max_relative_depth_error =
                  options.filter_max_relative_depth_error;
              // Interpolated, not measured: kept out of fusion like the pixels
              // that the LIDAR alone confirms (the mesher closes unmeasured
              // surfaces itself; fused, these moved KITTI's mesh away from the
              // LIDAR: docs/benchmarks/matrix.md).
              std::vector<uint8_t> filled;
              num_filled = FillTexturelessRegions(
                  ref.K, textureless, fill_options, kMaxCost, &state, &filled);
              for (size_t i = 0; i < filled.size(); ++i)
                not_fused[i] |= filled[i];
              summary.num_filled += num_filled;
            }
            // The mask before the maps: maps that exist (done, on a resume)
            // always have theirs.
            const std::string mask_path = FusionMaskPath(workspace, image.name);
            size_t num_not_fused = 0;
            if ((options.filter_lidar_as_view && !prior_depth.empty()) ||
                options.filter_reproj_parallax || num_filled > 0) {
              for (const uint8_t flag : not_fused) num_not_fused += flag;
              WriteFusionMask(mask_path, not_fused, state.width, state.height);
            } else {
              std::filesystem::remove(mask_path);
            }
            summary.num_not_fused += num_not_fused;
            WriteMaps(workspace, image.name, DenseMapType::kGeometric, state);
            ++summary.num_geometric_computed;
            LOG(INFO) << "[" << j + 1 << "/" << jobs.size() << "] "
                      << image.name << ": geometric, " << kept
                      << " valid pixels ("
                      << support.lidar_and_views + support.lidar_only
                      << " need the LIDAR, " << support.lidar_only
                      << " of them by the LIDAR alone; " << num_not_fused
                      << " kept out of fusion; " << num_unseen
                      << " on the LIDAR where no source sees it; " << num_filled
                      << " textureless filled), " << Seconds(image_start)
                      << " s";
          });
    });
  }
  SumOverRanks(group, &summary);
  summary.seconds = Seconds(start);
  return summary;
}

}  // namespace colmap_lidar
