#include "src/pipeline/automatic_reconstructor.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/mvs/stereo_config.h"
#include "colmap_ext/runner/colmap_runner.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/resource_usage.h"
#include "colmap_ext/util/stale_temporaries.h"
#include "colmap_ext/util/string.h"
#include "src/dataset/poses.h"
#include "src/eval/pose_evaluator.h"
#include "src/mvs/dense_cameras.h"
#include "src/mvs/lidar_patch_match_stereo.h"
#include "src/pipeline/pipeline_evaluation.h"
#include "src/pipeline/report.h"
#include "src/synth/synthesize.h"

namespace colmap_lidar {
namespace {

#define PIPELINE_CHECK(condition, stream_expr) \
  if (!(condition)) {                          \
    LOG(ERROR) << stream_expr;                 \
    return false;                              \
  }

constexpr int kMinImagesWithPriors = 3;

// What the stages share.
struct PipelineContext {
  const AutomaticReconstructorOptions* options = nullptr;
  PipelinePaths paths{""};
  std::string dataset_path;
  ColmapRunnerOptions colmap;
};

std::string ImagePathFile(const PipelinePaths& paths) {
  return JoinPaths(paths.pipeline, "image_path.txt");
}

// The image folder recorded by the import stage (the workspace's copy, or
// the recording's own folder when images are not copied). A folder inside
// the workspace is recorded relative to it, any other one as an absolute
// path, so that the workspace can be resumed from any working directory and
// moved or copied as a whole.
std::string ImportedImagePath(const PipelinePaths& paths) {
  const std::string file = ImagePathFile(paths);
  if (!ExistsFile(file)) {
    return paths.images;
  }
  const std::filesystem::path recorded(StringTrim(ReadTextFile(file)));
  if (recorded.is_absolute()) {
    return recorded.string();
  }
  const std::string in_workspace = JoinPaths(paths.workspace, recorded.string());
  // Workspaces of earlier versions recorded a path relative to the working
  // directory of their run.
  return (ExistsDir(in_workspace) || !ExistsDir(recorded.string()))
             ? in_workspace
             : recorded.string();
}

void WriteImportedImagePath(const PipelinePaths& paths,
                            const std::string& image_path) {
  const std::filesystem::path image_dir =
      std::filesystem::absolute(image_path).lexically_normal();
  const std::filesystem::path relative = image_dir.lexically_relative(
      std::filesystem::absolute(paths.workspace).lexically_normal());
  const bool inside = !relative.empty() && *relative.begin() != "..";
  const std::string recorded =
      inside ? relative.string() : image_dir.string();
  WriteFileAtomically(
      ImagePathFile(paths),
      [&recorded](std::ostream& stream) { stream << recorded << "\n"; },
      /*binary=*/false);
}

size_t NumImagesWithPriors(const std::string& database_path) {
  const Database database(database_path);
  size_t count = 0;
  for (const DatabaseImage& image : database.ReadAllImages()) {
    if (image.prior_q.has_value() && image.prior_t.has_value()) {
      ++count;
    }
  }
  return count;
}

bool HasGroundTruth(const std::string& dataset_path) {
  return ExistsFile(JoinPaths(dataset_path, "poses_gt.txt")) ||
         ExistsFile(JoinPaths(dataset_path, "reference.ply"));
}

// ---- The stages. Each returns its note (one line) and throws on failure.

std::string RunSynthesizeStage(const PipelineContext& context) {
  SynthesisOptions options = context.options->synthesis;
  options.num_threads = context.options->num_threads;
  // The folder has no finished recording (else the stage would be marked or
  // not applicable), so a partial one from an interrupted run is replaced.
  options.overwrite = true;
  const SynthesisSummary summary =
      SynthesizeDataset(options, context.dataset_path);
  std::ostringstream note;
  note << summary.num_frames << " frames, " << summary.num_lidar_points
       << " LIDAR points, " << summary.num_reference_points
       << " reference points (preset " << options.preset << ")";
  return note.str();
}

std::string RunImportStage(const PipelineContext& context) {
  CheckDirExists(context.dataset_path, "dataset_path");
  ImporterOptions options = context.options->import;
  // A re-run (after an interruption or with --overwrite) replaces the rows
  // of frames imported before instead of failing on them.
  options.overwrite = true;
  const PipelinePaths& paths = context.paths;
  const ImportSummary summary = ImportDataset(
      context.dataset_path, paths.workspace, paths.database, options);
  WriteImportedImagePath(paths, summary.image_path);
  std::ostringstream note;
  note << summary.num_frames << " frames (" << summary.dataset_format << "), "
       << summary.num_new_images << " new images, "
       << summary.num_matched_images << " matched ("
       << summary.num_recalibrated_images << " moved to the calibrated camera), "
       << summary.num_frames_with_prior << " with priors";
  return note.str();
}

std::string RunOdometryStage(const PipelineContext& context) {
  const PipelinePaths& paths = context.paths;
  const LidarPriorPosesSummary summary =
      RunLidarOdometryPriors(paths.database, paths.prior_model,
                             context.options->odometry,
                             context.options->odometry_priors);
  std::ostringstream note;
  note << summary.poses.size() << " frames registered, "
       << summary.trajectory_length_m << " m, "
       << summary.num_failed_registrations << " failed registrations";
  return note.str();
}

std::string RunSfmStage(const PipelineContext& context) {
  const PipelinePaths& paths = context.paths;
  LidarMapperOptions options = context.options->mapper;
  options.colmap_binary = context.options->colmap_binary;
  options.num_threads = context.options->num_threads;
  options.adjustment.num_threads = context.options->num_threads;
  LidarMapperPaths mapper_paths;
  mapper_paths.workspace_path = paths.workspace;
  mapper_paths.database_path = paths.database;
  mapper_paths.image_path = ImportedImagePath(paths);
  mapper_paths.output_path = paths.refined_model;
  return RunLidarMapper(mapper_paths, options).Outcome();
}

// Keeps every step-th reference of patch-match.cfg (sources unchanged) and
// the same images in fusion.cfg.
void ThinDenseReferences(const std::string& dense_path, const int step) {
  const std::string patch_match_cfg =
      JoinPaths(dense_path, "stereo/patch-match.cfg");
  const std::string fusion_cfg = JoinPaths(dense_path, "stereo/fusion.cfg");
  const std::vector<PatchMatchEntry> entries =
      ReadPatchMatchConfig(patch_match_cfg);
  std::vector<PatchMatchEntry> kept;
  std::vector<std::string> names;
  for (size_t i = 0; i < entries.size(); i += step) {
    kept.push_back(entries[i]);
    names.push_back(entries[i].ref_image_name);
  }
  WritePatchMatchConfig(patch_match_cfg, kept);
  WriteFusionConfig(fusion_cfg, names);
}

std::string RunDenseStage(const PipelineContext& context) {
  const PipelinePaths& paths = context.paths;
  const AutomaticReconstructorOptions& options = *context.options;
  CheckDirExists(paths.refined_model, "the refined model (stage sfm)");
  StagedDirectory staged(paths.dense);
  const ColmapRunner colmap(context.colmap);
  colmap.Run("image_undistorter",
             {{"image_path", ImportedImagePath(paths)},
              {"input_path", paths.refined_model},
              {"output_path", staged.path()},
              {"output_type", "COLMAP"},
              {"max_image_size", std::to_string(options.dense_max_image_size)}});
  if (options.dense_max_image_size > 0) {
    ScaleDenseCamerasToImages(staged.path());
  }
  if (options.dense_image_step > 1) {
    ThinDenseReferences(staged.path(), options.dense_image_step);
  }
  const LidarFuserSummary fused =
      RunLidarFuser(paths.database, paths.refined_model, staged.path(),
                    options.lidar_fusion);
  staged.Commit();
  const size_t num_references =
      ReadFusionConfig(JoinPaths(paths.dense, "stereo/fusion.cfg")).size();
  std::ostringstream note;
  note << num_references << " reference images, " << fused.num_frames
       << " scans fused into " << fused.num_voxels << " voxels";
  return note.str();
}

std::string RunPatchMatchStage(const PipelineContext& context) {
  const PipelinePaths& paths = context.paths;
  CheckFileExists(JoinPaths(paths.dense, "stereo/patch-match.cfg"),
                  "the dense workspace (stage dense)");
  LidarPatchMatchOptions options = context.options->patch_match;
  options.num_threads = context.options->num_threads;
  const LidarPatchMatchSummary summary =
      RunLidarPatchMatchStereo(paths.dense, options);
  std::ostringstream note;
  note << summary.num_references << " references, "
       << summary.num_photometric_computed << " photometric and "
       << summary.num_geometric_computed << " geometric maps computed, "
       << summary.num_photometric_skipped << " skipped as done, "
       << summary.num_without_sources << " without source views";
  if (summary.support.Total() > 0) {
    note << "; geometric " << summary.support.Format() << "; "
         << summary.num_not_fused << " kept out of fusion; "
         << summary.num_filled << " textureless pixels filled";
  }
  return note.str();
}

size_t CountPlyVertices(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  THROW_CHECK(stream.good(), "Cannot read " << path);
  std::string line;
  while (std::getline(stream, line) && StringTrim(line) != "end_header") {
    const std::vector<std::string> words = StringSplit(StringTrim(line), " ");
    if (words.size() == 3 && words[0] == "element" && words[1] == "vertex") {
      return std::stoull(words[2]);
    }
  }
  THROW_ERROR("No vertex element in the PLY header of " << path);
}

std::string RunFusionStage(const PipelineContext& context) {
  const PipelinePaths& paths = context.paths;
  const AutomaticReconstructorOptions& options = *context.options;
  CheckFileExists(JoinPaths(paths.dense, "stereo/fusion.cfg"),
                  "the dense workspace (stage dense)");
  const std::string temp_path = JoinPaths(paths.dense, "fused.tmp-run.ply");
  const ColmapRunner colmap(context.colmap);
  std::vector<std::pair<std::string, std::string>> fusion_options = {
      {"workspace_path", paths.dense},
      {"workspace_format", "COLMAP"},
      {"input_type", options.fusion_input_type},
      {"output_path", temp_path},
      {"StereoFusion.num_threads",
       std::to_string(options.fusion_num_threads > 0
                          ? options.fusion_num_threads
                          : options.num_threads)},
      {"StereoFusion.min_num_pixels",
       std::to_string(options.fusion_min_num_pixels)}};
  // The geometric pixels that only the LIDAR's vote or the parallax
  // tolerance kept stay out of the cloud (lidar_patch_match_stereo.h).
  const std::string mask_dir = FusionMaskDir(paths.dense);
  if (options.fusion_input_type == "geometric" && ExistsDir(mask_dir)) {
    fusion_options.emplace_back("StereoFusion.mask_path", mask_dir);
  }
  colmap.Run("stereo_fusion", fusion_options);
  const size_t num_points = CountPlyVertices(temp_path);
  THROW_CHECK(num_points > 0,
              "stereo_fusion fused no point from the depth maps of "
                  << paths.dense << " (see " << context.colmap.log_path
                  << "); try --AutomaticReconstruction.fusion_input_type "
                     "photometric or a smaller fusion_min_num_pixels");
  std::filesystem::rename(temp_path + ".vis", paths.fused + ".vis");
  std::filesystem::rename(temp_path, paths.fused);
  return std::to_string(num_points) + " fused points";
}

std::string RunMeshStage(const PipelineContext& context) {
  const PipelinePaths& paths = context.paths;
  const AutomaticReconstructorOptions& options = *context.options;
  CheckFileExists(paths.fused, "the fused cloud (stage fusion)");
  DelaunayMeshingOptions meshing = options.meshing;
  meshing.num_threads = options.num_threads;
  std::string lines_path;
  if (options.mesh_with_lines) {
    // A model without line tracks (e.g. a scene without LIDAR-supported
    // creases) is meshed without lines rather than failing.
    if (ReadReconstruction(paths.refined_model).lines3D.empty()) {
      LOG(WARNING) << "mesh: " << paths.refined_model
                   << " has no 3D lines; meshing without line samples";
    } else {
      lines_path = paths.refined_model;
    }
  }
  const DelaunayMeshingSummary summary = MeshDenseWorkspace(
      meshing, options.meshing_input, paths.dense, lines_path, paths.mesh,
      lines_path.empty() ? "" : paths.database);
  std::ostringstream note;
  note << summary.num_input_points << " input points, "
       << summary.num_mesh_vertices << " vertices, " << summary.num_faces
       << " faces";
  return note.str();
}

std::string RunEvaluateStage(const PipelineContext& context) {
  PipelineEvaluationInput input;
  input.dataset_path = context.dataset_path;
  input.prior_model_path = context.paths.prior_model;
  input.refined_model_path = context.paths.refined_model;
  input.mapper_model_path = context.paths.mapper_model;
  input.mesh_path = context.paths.mesh;
  input.lidar_cloud_path = LidarFusedPlyPath(context.paths.dense);
  input.database_path = context.paths.database;
  input.output_path = context.paths.eval;
  PipelineEvaluationOptions options;
  options.mesh = context.options->mesh_evaluation;
  options.mesh_alignment = context.options->mesh_alignment;
  options.mesh_icp = context.options->mesh_icp;
  options.lidar_baseline = context.options->evaluate_lidar_baseline;
  options.poisson_depth = context.options->lidar_baseline_poisson_depth;
  options.poisson_trim = context.options->lidar_baseline_poisson_trim;
  options.num_threads = context.options->num_threads;
  options.colmap = context.colmap;
  return EvaluatePipeline(input, options);
}

// <pipeline>/stages.json from all stage marks, in pipeline order.
void WriteStagesJson(const PipelinePaths& paths) {
  std::vector<StageRecord> records;
  for (const PipelineStage stage : AllPipelineStages()) {
    StageRecord record;
    if (ReadStageRecord(paths.StageMark(stage), &record)) {
      records.push_back(record);
    }
  }
  WriteStageRecordsJson(JoinPaths(paths.pipeline, "stages.json"), records);
}

std::string RunReportStage(const PipelineContext& context) {
  // The report shows the stages finished so far (all but itself).
  WriteStagesJson(context.paths);
  ReportOptions options;
  options.python_binary = context.options->python_binary;
  options.log_path = JoinPaths(context.paths.pipeline, "report.log");
  const ReportSummary summary =
      WriteReport(context.paths.workspace, context.dataset_path,
                  context.paths.report, options);
  return std::to_string(summary.num_figures) + " figures in " +
         summary.html_path;
}

std::string RunStage(const PipelineStage stage,
                     const PipelineContext& context) {
  switch (stage) {
    case PipelineStage::kSynthesize:
      return RunSynthesizeStage(context);
    case PipelineStage::kImport:
      return RunImportStage(context);
    case PipelineStage::kOdometry:
      return RunOdometryStage(context);
    case PipelineStage::kSfm:
      return RunSfmStage(context);
    case PipelineStage::kDense:
      return RunDenseStage(context);
    case PipelineStage::kPatchMatch:
      return RunPatchMatchStage(context);
    case PipelineStage::kFusion:
      return RunFusionStage(context);
    case PipelineStage::kMesh:
      return RunMeshStage(context);
    case PipelineStage::kEvaluate:
      return RunEvaluateStage(context);
    case PipelineStage::kReport:
      return RunReportStage(context);
  }
  THROW_ERROR("Unknown pipeline stage");
}

// Empty when the stage applies; else why it does not.
std::string WhyNotApplicable(const PipelineStage stage,
                             const PipelineContext& context) {
  const PipelinePaths& paths = context.paths;
  switch (stage) {
    case PipelineStage::kSynthesize:
      if (!context.options->dataset_path.empty()) {
        return "a recording was given (--dataset_path)";
      }
      if (!ExistsFile(paths.StageMark(stage)) &&
          ExistsFile(JoinPaths(paths.default_dataset, "calibration.yaml"))) {
        return "the workspace holds a recording in " + paths.default_dataset;
      }
      return "";
    case PipelineStage::kOdometry:
      if (ExistsFile(paths.StageMark(stage))) {
        return "";
      }
      THROW_CHECK(ExistsFile(paths.database),
                  "No database " << paths.database
                                 << ": run the import stage first");
      if (NumImagesWithPriors(paths.database) >= kMinImagesWithPriors) {
        return "the images have prior poses";
      }
      return "";
    case PipelineStage::kEvaluate:
      // Without ground truth: the real-data figures of the refined model.
      if (!HasGroundTruth(context.dataset_path) &&
          !ExistsModel(paths.refined_model)) {
        return "the recording has no poses_gt.txt or reference.ply and "
               "there is no refined model";
      }
      return "";
    default:
      return "";
  }
}

}  // namespace

LidarPatchMatchOptions PipelinePatchMatchOptions() {
  LidarPatchMatchOptions options;
  options.num_iterations = 2;
  options.num_geom_iterations = 1;
  return options;
}

bool AutomaticReconstructorOptions::Check() const {
  std::vector<PipelineStage> selected;
  PIPELINE_CHECK(ParsePipelineStages(stages, &selected),
                 "AutomaticReconstruction.stages: '"
                     << stages
                     << "' is not 'all', a stage or 'first:last' of "
                        "synthesize, import, odometry, sfm, dense, "
                        "patch_match, fusion, mesh, evaluate, report");
  PIPELINE_CHECK(dense_image_step >= 1,
                 "AutomaticReconstruction.dense_image_step must be >= 1, got "
                     << dense_image_step);
  PIPELINE_CHECK(dense_max_image_size == -1 || dense_max_image_size > 0,
                 "AutomaticReconstruction.dense_max_image_size must be -1 or "
                 "> 0, got "
                     << dense_max_image_size);
  PIPELINE_CHECK(fusion_min_num_pixels >= 1,
                 "AutomaticReconstruction.fusion_min_num_pixels must be >= 1, "
                 "got "
                     << fusion_min_num_pixels);
  PIPELINE_CHECK(
      fusion_input_type == "geometric" || fusion_input_type == "photometric",
      "AutomaticReconstruction.fusion_input_type must be geometric or "
      "photometric, got '"
          << fusion_input_type << "'");
  PIPELINE_CHECK(fusion_input_type == "photometric" ||
                     patch_match.geom_consistency,
                 "AutomaticReconstruction.fusion_input_type geometric needs "
                 "the PatchMatch geometric pass (geom_consistency)");
  PIPELINE_CHECK(mesh_alignment == "none" || mesh_alignment == "se3" ||
                     mesh_alignment == "sim3" ||
                     mesh_alignment == "se3_axes" ||
                     mesh_alignment == "sim3_axes",
                 "AutomaticReconstruction.mesh_alignment must be none, se3, "
                 "sim3, se3_axes or sim3_axes, got '"
                     << mesh_alignment << "'");
  PIPELINE_CHECK(lidar_baseline_poisson_depth >= 1 &&
                     lidar_baseline_poisson_depth <= 16,
                 "AutomaticReconstruction.lidar_baseline_poisson_depth must "
                 "be in [1, 16], got "
                     << lidar_baseline_poisson_depth);
  PIPELINE_CHECK(lidar_baseline_poisson_trim >= 0.0,
                 "AutomaticReconstruction.lidar_baseline_poisson_trim must "
                 "be >= 0, got "
                     << lidar_baseline_poisson_trim);
  PIPELINE_CHECK(!python_binary.empty(),
                 "AutomaticReconstruction.python_binary is empty");
  // Every stage option set is checked so that all problems are reported.
  bool ok = synthesis.Check();
  ok = import.Check() && ok;
  ok = odometry.Check() && ok;
  ok = odometry_priors.Check() && ok;
  ok = mapper.Check() && ok;
  ok = lidar_fusion.Check() && ok;
  ok = patch_match.Check() && ok;
  ok = meshing.Check() && ok;
  ok = meshing_input.Check() && ok;
  ok = mesh_evaluation.Check() && ok;
  return ok;
}

PipelinePaths::PipelinePaths(const std::string& workspace_path)
    : workspace(workspace_path),
      database(JoinPaths(workspace_path, "database.db")),
      images(JoinPaths(workspace_path, "images")),
      prior_model(JoinPaths(workspace_path, "sparse/prior")),
      refined_model(JoinPaths(workspace_path, "sparse/refined")),
      mapper_model(JoinPaths(workspace_path, "sparse/lidar_mapper/mapper/0")),
      dense(JoinPaths(workspace_path, "dense")),
      fused(JoinPaths(workspace_path, "dense/fused.ply")),
      mesh(JoinPaths(workspace_path, "dense/meshed-delaunay.ply")),
      eval(JoinPaths(workspace_path, "eval")),
      report(JoinPaths(workspace_path, "report")),
      pipeline(JoinPaths(workspace_path, "pipeline")),
      default_dataset(JoinPaths(workspace_path, "dataset")) {}

std::string PipelinePaths::StageMark(const PipelineStage stage) const {
  return JoinPaths(pipeline, std::string(PipelineStageName(stage)) + ".done");
}

AutomaticReconstructorSummary RunAutomaticReconstructor(
    const std::string& workspace_path,
    const AutomaticReconstructorOptions& options) {
  THROW_CHECK(options.Check(), "Invalid automatic_reconstructor options");
  std::vector<PipelineStage> selected;
  ParsePipelineStages(options.stages, &selected);

  CreateDirIfNotExists(workspace_path);
  PipelineContext context;
  context.options = &options;
  context.paths = PipelinePaths(workspace_path);
  const PipelinePaths& paths = context.paths;
  CreateDirIfNotExists(paths.pipeline);
  // What a run killed before left under temporary names (never read as
  // output, but a killed dense stage leaves a copy of every undistorted
  // image).
  RemoveStaleTemporaries(workspace_path, /*recursive=*/true);
  context.dataset_path = options.dataset_path.empty() ? paths.default_dataset
                                                      : options.dataset_path;
  context.colmap.colmap_binary = options.colmap_binary;
  context.colmap.log_path = JoinPaths(paths.pipeline, "colmap.log");
  // Fails early, before any work, when colmap is missing.
  ColmapRunner::FindColmapBinary(options.colmap_binary);

  AutomaticReconstructorSummary summary;
  for (const PipelineStage stage : selected) {
    const std::string name = PipelineStageName(stage);
    const std::string why_not = WhyNotApplicable(stage, context);
    if (!why_not.empty()) {
      LOG(INFO) << "automatic_reconstructor: stage " << name
                << " does not apply: " << why_not;
      summary.not_applicable.push_back(name);
      continue;
    }
    const std::string mark = paths.StageMark(stage);
    StageRecord record;
    if (!options.overwrite && ReadStageRecord(mark, &record)) {
      LOG(INFO) << "automatic_reconstructor: stage " << name
                << " was done at " << record.finished_at << " (" << record.note
                << "); skipped";
      summary.skipped.push_back(record);
      continue;
    }
    // The later stages consume this stage's output: their marks go.
    for (int later = static_cast<int>(stage); later < kNumPipelineStages;
         ++later) {
      std::filesystem::remove(
          paths.StageMark(static_cast<PipelineStage>(later)));
    }
    LOG(INFO) << "automatic_reconstructor: stage " << name << " ...";
    const ResourceTimer timer;
    try {
      record.note = RunStage(stage, context);
    } catch (const Error& error) {
      THROW_ERROR("Stage " << name << " failed: " << error.what());
    }
    record.stage = name;
    record.wall_seconds = timer.WallSeconds();
    record.cpu_seconds = timer.CpuSeconds();
    record.peak_memory_bytes = timer.PeakMemoryBytes();
    record.finished_at = UtcTimestamp();
    WriteStageRecord(mark, record);
    LOG(INFO) << "automatic_reconstructor: stage " << name << " done in "
              << record.wall_seconds << " s (CPU " << record.cpu_seconds
              << " s, peak " << record.peak_memory_bytes / (1024 * 1024)
              << " MiB): " << record.note;
    summary.ran.push_back(record);
  }

  WriteStagesJson(paths);
  summary.mesh_path = ExistsFile(paths.mesh) ? paths.mesh : "";
  const std::string html = JoinPaths(paths.report, "index.html");
  summary.report_path = ExistsFile(html) ? html : "";
  return summary;
}

}  // namespace colmap_lidar
