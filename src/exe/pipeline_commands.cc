// Subcommands of the whole pipeline: automatic_reconstructor and report
// (src/pipeline).
#include <cstdlib>
#include <iostream>
#include <string>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/exe/commands.h"
#include "src/exe/option_manager.h"
#include "src/exe/option_sections.h"
#include "src/pipeline/automatic_reconstructor.h"
#include "src/pipeline/report.h"

namespace colmap_lidar {
namespace {

// Section [AutomaticReconstruction]; keep
// configs/automatic_reconstructor.ini in step.
void AddAutomaticReconstructionOptions(AutomaticReconstructorOptions* o,
                                       OptionManager* options) {
  const std::string s = "AutomaticReconstruction.";
  options->AddOption(s + "stages", &o->stages,
                     "Stages to run: all | a stage | first:last, of "
                     "synthesize, import, odometry, sfm, dense, patch_match, "
                     "fusion, mesh, evaluate, report.");
  options->AddOption(s + "overwrite", &o->overwrite,
                     "Re-run stages marked done in <workspace>/pipeline.");
  options->AddOption(s + "num_threads", &o->num_threads,
                     "Threads of every stage; <= 0 uses all cores.");
  options->AddOption(s + "colmap_binary", &o->colmap_binary,
                     "Stock colmap; empty: $COLMAP_BINARY or colmap on "
                     "PATH.");
  options->AddOption(s + "python_binary", &o->python_binary,
                     "Python 3 with numpy and matplotlib, for the report.");
  options->AddOption(s + "dense_image_step", &o->dense_image_step,
                     "Every n-th image is a PatchMatch reference and is "
                     "fused (all stay source views), >= 1.");
  options->AddOption(s + "dense_max_image_size", &o->dense_max_image_size,
                     "image_undistorter --max_image_size, pixels; -1 keeps "
                     "the full size.");
  options->AddOption(s + "fusion_min_num_pixels", &o->fusion_min_num_pixels,
                     "stereo_fusion --StereoFusion.min_num_pixels, >= 1.");
  options->AddOption(s + "fusion_num_threads", &o->fusion_num_threads,
                     "stereo_fusion --StereoFusion.num_threads; <= 0: "
                     "num_threads. More than one makes the fused cloud and "
                     "the mesh differ from run to run.");
  options->AddOption(s + "fusion_input_type", &o->fusion_input_type,
                     "stereo_fusion --input_type: geometric | photometric.");
  options->AddOption(s + "mesh_with_lines", &o->mesh_with_lines,
                     "Sample the refined 3D line segments into the Delaunay "
                     "triangulation.");
  options->AddOption(s + "mesh_alignment", &o->mesh_alignment,
                     "Meshes aligned to the ground truth before their "
                     "evaluation by the refined trajectory's fit: none | "
                     "se3 | sim3 (camera centres) | se3_axes | sim3_axes "
                     "(centres and orientations, as Tanks and Temples).");
  options->AddOption(s + "mesh_icp", &o->mesh_icp,
                     "Evaluate the meshes also after an ICP refinement of "
                     "that alignment against reference.ply "
                     "(eval/mesh_*_icp.json).");
  options->AddOption(s + "evaluate_lidar_baseline",
                     &o->evaluate_lidar_baseline,
                     "Evaluate also a Poisson mesh of the registered LIDAR "
                     "cloud (the LIDAR-only baseline).");
  options->AddOption(s + "lidar_baseline_poisson_depth",
                     &o->lidar_baseline_poisson_depth,
                     "Its --PoissonMeshing.depth, 1..16.");
  options->AddOption(s + "lidar_baseline_poisson_trim",
                     &o->lidar_baseline_poisson_trim,
                     "Its --PoissonMeshing.trim, >= 0.");
  options->AddCheck([o] { return o->Check(); });
}

}  // namespace

int RunAutomaticReconstructorCommand(int argc, char** argv) {
  std::string workspace_path;
  AutomaticReconstructorOptions pipeline_options;

  OptionManager options;
  options.AddRequiredOption("workspace_path", &workspace_path,
                            "Workspace to create or complete (a new folder, "
                            "one of an earlier run, or a stock COLMAP "
                            "workspace with database.db).");
  options.AddOption("dataset_path", &pipeline_options.dataset_path,
                    "Recording (rig format or KITTI raw); empty: the "
                    "default synthetic scene in <workspace>/dataset.");
  AddAutomaticReconstructionOptions(&pipeline_options, &options);
  AddSynthesisOptions(&pipeline_options.synthesis, &options);
  AddImporterOptions(&pipeline_options.import, &options);
  // The stages' own sections; their thread counts and colmap binaries are
  // replaced by AutomaticReconstruction.num_threads / colmap_binary.
  AddLidarMapperOptions(&pipeline_options.mapper, &options);
  LineBundleAdjustmentNames adjustment_names;
  AddLineBundleAdjustmentOptions(&pipeline_options.mapper.adjustment,
                                 &adjustment_names,
                                 /*with_gauge_and_priors=*/false, &options);
  AddLidarFusionOptions(&pipeline_options.lidar_fusion, &options);
  AddLidarPatchMatchOptions(&pipeline_options.patch_match, &options);
  AddDelaunayMeshingOptions(&pipeline_options.meshing,
                            &pipeline_options.meshing_input, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (ExistsFile(workspace_path) && !ExistsDir(workspace_path)) {
    LOG(ERROR) << "--workspace_path " << workspace_path << " is a file";
    return EXIT_FAILURE;
  }
  if (!pipeline_options.dataset_path.empty() &&
      !ExistsDir(pipeline_options.dataset_path)) {
    LOG(ERROR) << "--dataset_path " << pipeline_options.dataset_path
               << " is not a folder";
    return EXIT_FAILURE;
  }
  const AutomaticReconstructorSummary summary =
      RunAutomaticReconstructor(workspace_path, pipeline_options);
  double seconds = 0.0;
  for (const StageRecord& record : summary.ran) {
    seconds += record.wall_seconds;
  }
  std::cout << "automatic_reconstructor: " << summary.ran.size()
            << " stages run in " << seconds << " s, "
            << summary.skipped.size() << " done before, "
            << summary.not_applicable.size() << " not applicable";
  if (!summary.mesh_path.empty()) {
    std::cout << "\n  mesh:   " << summary.mesh_path;
  }
  if (!summary.report_path.empty()) {
    std::cout << "\n  report: " << summary.report_path;
  }
  std::cout << std::endl;
  return EXIT_SUCCESS;
}

int RunReportCommand(int argc, char** argv) {
  std::string workspace_path;
  std::string dataset_path;
  std::string output_path;
  ReportOptions report_options;

  OptionManager options;
  options.AddRequiredOption("workspace_path", &workspace_path,
                            "Workspace of automatic_reconstructor (or one "
                            "laid out the same way).");
  options.AddOption("dataset_path", &dataset_path,
                    "Recording, for the page's header; default "
                    "<workspace>/dataset.");
  options.AddOption("output_path", &output_path,
                    "Report folder; default <workspace>/report.");
  options.AddOption("Report.python_binary", &report_options.python_binary,
                    "Python 3 with numpy and matplotlib.");
  options.AddCheck([&report_options] { return report_options.Check(); });
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }
  if (!ExistsDir(workspace_path)) {
    LOG(ERROR) << "--workspace_path " << workspace_path << " is not a folder";
    return EXIT_FAILURE;
  }
  if (dataset_path.empty()) {
    dataset_path = JoinPaths(workspace_path, "dataset");
  }
  if (output_path.empty()) {
    output_path = JoinPaths(workspace_path, "report");
  }
  const ReportSummary summary =
      WriteReport(workspace_path, dataset_path, output_path, report_options);
  std::cout << "report: " << summary.num_figures << " figures, "
            << summary.html_path << std::endl;
  return EXIT_SUCCESS;
}

}  // namespace colmap_lidar
