// The start of the lidar_mapper command: a workspace without a database is
// first filled from a recording by the importer (src/dataset/importer.h),
// so that one command runs import -> features -> lines -> association ->
// adjustment. RunLidarMapper (lidar_mapper.h) then runs on the result.
#pragma once

#include <string>

#include "src/dataset/importer.h"
#include "src/sfm/lidar_mapper.h"

namespace colmap_lidar {

struct LidarMapperWorkspace {
  // Empty on success; otherwise why the mapper cannot run (no database and
  // no recording to import), for the caller to report.
  std::string error;
  // The paths for RunLidarMapper: the input paths, with image_path set to
  // the imported images when it was empty and an import ran.
  LidarMapperPaths paths;
  // Whether the recording was imported, and the importer's summary.
  bool imported = false;
  ImportSummary import;
};

// The database is paths.database_path, default <workspace>/database.db.
// When it exists, nothing happens. Otherwise dataset_path (empty: none) is
// imported into paths.workspace_path with `importer_options`; without a
// dataset_path the result holds an error and nothing is written. Throws
// colmap_lidar::Error (from ImportDataset) when the import fails; the
// workspace is then unchanged.
LidarMapperWorkspace PrepareLidarMapperWorkspace(
    const LidarMapperPaths& paths, const std::string& dataset_path,
    const ImporterOptions& importer_options = ImporterOptions());

}  // namespace colmap_lidar
