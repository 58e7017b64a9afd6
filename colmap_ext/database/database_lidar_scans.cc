// Database (database.h): rows of our ext_lidar_scans table (the scan taken
// with an image: path, point count, cam_from_lidar as a row-major 3x4 blob).
#include <filesystem>
#include <limits>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/database_internal.h"

namespace colmap_lidar {
namespace {

using database_internal::ToSqliteId;
using RowMajorMatrix3x4d = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;

}  // namespace

std::string LidarScanFilePath(const std::string& database_path,
                              const std::string& scan_path) {
  const std::filesystem::path path(scan_path);
  if (path.is_absolute()) {
    return path.lexically_normal().string();
  }
  return (std::filesystem::path(database_path).parent_path() / path)
      .lexically_normal()
      .string();
}

void Database::WriteLidarScan(const LidarScanRecord& scan) {
  THROW_CHECK(
      scan.num_points <=
          static_cast<uint64_t>(std::numeric_limits<int64_t>::max()),
      "LIDAR scan of image " << scan.image_id << " has too many points");
  const RowMajorMatrix3x4d cam_from_lidar = scan.cam_from_lidar.ToMatrix();
  SqliteStatement statement = Prepare(
      "INSERT OR REPLACE INTO ext_lidar_scans (image_id, path, num_points, "
      "cam_from_lidar) VALUES (?, ?, ?, ?)");
  statement.BindInt64(1, scan.image_id);
  statement.BindText(2, scan.path);
  statement.BindInt64(3, ToSqliteId(scan.num_points));
  statement.BindBlobArray(4, cam_from_lidar.data(), 12);
  statement.Execute();
}

namespace {

// Column order: image_id, path, num_points, cam_from_lidar.
LidarScanRecord ReadLidarScanRow(const SqliteStatement& statement,
                                 const std::string& path) {
  LidarScanRecord scan;
  scan.image_id = static_cast<image_t>(statement.ColumnInt64(0));
  scan.path = statement.ColumnText(1);
  scan.num_points = static_cast<uint64_t>(statement.ColumnInt64(2));
  RowMajorMatrix3x4d cam_from_lidar;
  statement.ColumnBlobArray(3, 12, cam_from_lidar.data(),
                            "cam_from_lidar of image " +
                                std::to_string(scan.image_id) + " in " + path);
  scan.cam_from_lidar = Rigid3d::FromMatrix(cam_from_lidar);
  return scan;
}

constexpr const char* kSelectLidarScan =
    "SELECT image_id, path, num_points, cam_from_lidar FROM ext_lidar_scans";

}  // namespace

std::optional<LidarScanRecord> Database::ReadLidarScan(
    const image_t image_id) const {
  SqliteStatement statement =
      Prepare(std::string(kSelectLidarScan) + " WHERE image_id = ?");
  statement.BindInt64(1, image_id);
  if (!statement.Step()) {
    return std::nullopt;
  }
  return ReadLidarScanRow(statement, path_);
}

std::vector<LidarScanRecord> Database::ReadAllLidarScans() const {
  SqliteStatement statement =
      Prepare(std::string(kSelectLidarScan) + " ORDER BY image_id");
  std::vector<LidarScanRecord> scans;
  while (statement.Step()) {
    scans.push_back(ReadLidarScanRow(statement, path_));
  }
  return scans;
}

void Database::DeleteLidarScan(const image_t image_id) {
  SqliteStatement statement =
      Prepare("DELETE FROM ext_lidar_scans WHERE image_id = ?");
  statement.BindInt64(1, image_id);
  statement.Execute();
}

}  // namespace colmap_lidar
