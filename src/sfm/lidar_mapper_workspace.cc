#include "src/sfm/lidar_mapper_workspace.h"

#include "colmap_ext/util/file.h"

namespace colmap_lidar {

LidarMapperWorkspace PrepareLidarMapperWorkspace(
    const LidarMapperPaths& paths, const std::string& dataset_path,
    const ImporterOptions& importer_options) {
  LidarMapperWorkspace workspace;
  workspace.paths = paths;
  const std::string database_path =
      paths.database_path.empty()
          ? JoinPaths(paths.workspace_path, "database.db")
          : paths.database_path;
  if (ExistsFile(database_path)) {
    return workspace;
  }
  if (dataset_path.empty()) {
    workspace.error = "No database " + database_path +
                      ": run lidar_importer or give --dataset_path";
    return workspace;
  }
  workspace.import = ImportDataset(dataset_path, paths.workspace_path,
                                   database_path, importer_options);
  workspace.imported = true;
  if (workspace.paths.image_path.empty()) {
    workspace.paths.image_path = workspace.import.image_path;
  }
  return workspace;
}

}  // namespace colmap_lidar
