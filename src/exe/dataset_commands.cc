// Subcommands about recordings: lidar_importer.
#include <cstdlib>
#include <iostream>
#include <string>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/dataset/importer.h"
#include "src/exe/commands.h"
#include "src/exe/option_manager.h"
#include "src/exe/option_sections.h"

namespace colmap_lidar {

// Section [LidarImport]; keep configs/lidar_importer.ini in step.
void AddImporterOptions(ImporterOptions* importer, OptionManager* options) {
  options->AddOption("LidarImport.input_format", &importer->input_format,
                     "Recording layout: auto | rig | kitti_raw (auto detects "
                     "it from the folder content).");
  options->AddOption("LidarImport.copy_images", &importer->copy_images,
                     "Copy the images into <workspace_path>/images; if false, "
                     "the dataset's image folder is used as image_path.");
  options->AddOption("LidarImport.copy_scans", &importer->copy_scans,
                     "Copy the LIDAR scans into <workspace_path>/lidar; if "
                     "false, the database stores their absolute paths.");
  options->AddOption("LidarImport.kitti_camera", &importer->kitti_camera,
                     "KITTI raw only: index N of the rectified camera "
                     "image_0N to import, 0..3.");
  options->AddOption("LidarImport.overwrite", &importer->overwrite,
                     "Replace the LIDAR rows, priors and copied files of "
                     "frames imported before; if false, importing a frame twice "
                     "is an error.");
  options->AddOption("LidarImport.calibrate_matched_images",
                     &importer->calibrate_matched_images,
                     "Existing images matched to frames take the "
                     "calibrated camera when theirs differs (same image "
                     "size); keypoints stay valid.");
  options->AddCheck([importer] { return importer->Check(); });
}

int RunLidarImporter(int argc, char** argv) {
  std::string dataset_path;
  std::string workspace_path;
  std::string database_path;
  ImporterOptions importer_options;

  OptionManager options;
  options.AddRequiredOption("dataset_path", &dataset_path,
                            "Folder of the recording to import (rig layout "
                            "or a KITTI raw drive, see "
                            "docs/dataset-format.md).");
  options.AddRequiredOption("workspace_path", &workspace_path,
                            "Output COLMAP workspace, created if missing; an "
                            "existing workspace is completed.");
  options.AddOption("database_path", &database_path,
                    "COLMAP database to create or complete; empty: "
                    "<workspace_path>/database.db.");
  AddImporterOptions(&importer_options, &options);
  if (!options.Parse(argc, argv)) {
    return options.ExitCode();
  }

  if (!ExistsDir(dataset_path)) {
    LOG(ERROR) << "--dataset_path " << dataset_path << " is not a folder";
    return EXIT_FAILURE;
  }

  const ImportSummary summary = ImportDataset(dataset_path, workspace_path,
                                              database_path, importer_options);
  // Like COLMAP's project.ini: the options of the run, reloadable with
  // --project_path.
  options.Write(JoinPaths(workspace_path, "lidar_importer.ini"));
  std::cout << FormatImportSummary(summary) << std::endl;
  return EXIT_SUCCESS;
}

}  // namespace colmap_lidar
