// Database (database.h): rows of the cameras table, with COLMAP's params
// blob and the parameter count checked against the camera model.
#include "colmap_ext/database/database.h"

#include <sqlite3.h>

#include "colmap_ext/database/database_internal.h"

namespace colmap_lidar {
namespace {

using database_internal::ToSqliteId;

void CheckCameraParams(const Camera& camera, const std::string& path) {
  const int expected = CameraModelNumParams(camera.model_id);
  THROW_CHECK(expected >= 0, "Camera " << camera.camera_id
                                       << " has unknown model id "
                                       << static_cast<int>(camera.model_id)
                                       << " (database " << path << ")");
  THROW_CHECK(camera.params.size() == static_cast<size_t>(expected),
              "Camera " << camera.camera_id << " of model "
                        << CameraModelIdToName(camera.model_id) << " has "
                        << camera.params.size() << " parameters, expected "
                        << expected << " (database " << path << ")");
}

// Column order: camera_id, model, width, height, params, prior_focal_length.
Camera ReadCameraRow(const SqliteStatement& statement,
                     const std::string& path) {
  Camera camera;
  camera.camera_id = static_cast<camera_t>(statement.ColumnInt64(0));
  const int64_t model = statement.ColumnInt64(1);
  THROW_CHECK(ExistsCameraModelWithId(static_cast<int>(model)),
              "Camera " << camera.camera_id << " in " << path
                        << " has unknown model id " << model);
  camera.model_id = static_cast<CameraModelId>(model);
  camera.width = static_cast<uint64_t>(statement.ColumnInt64(2));
  camera.height = static_cast<uint64_t>(statement.ColumnInt64(3));
  const size_t num_params =
      static_cast<size_t>(CameraModelNumParams(camera.model_id));
  camera.params.resize(num_params);
  statement.ColumnBlobArray(4, num_params, camera.params.data(),
                            "params of camera " +
                                std::to_string(camera.camera_id) + " (model " +
                                CameraModelIdToName(camera.model_id) + ")");
  camera.has_prior_focal_length = statement.ColumnInt64(5) != 0;
  return camera;
}

constexpr const char* kSelectCamera =
    "SELECT camera_id, model, width, height, params, prior_focal_length "
    "FROM cameras";

}  // namespace

camera_t Database::WriteCamera(const Camera& camera) {
  CheckCameraParams(camera, path_);
  const bool with_id = camera.camera_id != kInvalidCameraId;
  SqliteStatement statement = Prepare(
      "INSERT INTO cameras (camera_id, model, width, height, params, "
      "prior_focal_length) VALUES (?, ?, ?, ?, ?, ?)");
  if (with_id) {
    statement.BindInt64(1, camera.camera_id);
  } else {
    statement.BindNull(1);
  }
  statement.BindInt64(2, static_cast<int64_t>(camera.model_id));
  statement.BindInt64(3, ToSqliteId(camera.width));
  statement.BindInt64(4, ToSqliteId(camera.height));
  statement.BindBlobArray(5, camera.params.data(), camera.params.size());
  statement.BindInt64(6, camera.has_prior_focal_length ? 1 : 0);
  statement.Execute();
  return static_cast<camera_t>(sqlite3_last_insert_rowid(handle_));
}

void Database::UpdateCamera(const Camera& camera) {
  CheckCameraParams(camera, path_);
  SqliteStatement statement = Prepare(
      "UPDATE cameras SET model = ?, width = ?, height = ?, params = ?, "
      "prior_focal_length = ? WHERE camera_id = ?");
  statement.BindInt64(1, static_cast<int64_t>(camera.model_id));
  statement.BindInt64(2, ToSqliteId(camera.width));
  statement.BindInt64(3, ToSqliteId(camera.height));
  statement.BindBlobArray(4, camera.params.data(), camera.params.size());
  statement.BindInt64(5, camera.has_prior_focal_length ? 1 : 0);
  statement.BindInt64(6, camera.camera_id);
  statement.Execute();
  THROW_CHECK(sqlite3_changes(handle_) == 1,
              "Cannot update camera " << camera.camera_id << " in " << path_
                                      << ": no such camera");
}

std::optional<Camera> Database::ReadCamera(const camera_t camera_id) const {
  SqliteStatement statement =
      Prepare(std::string(kSelectCamera) + " WHERE camera_id = ?");
  statement.BindInt64(1, camera_id);
  if (!statement.Step()) {
    return std::nullopt;
  }
  return ReadCameraRow(statement, path_);
}

std::vector<Camera> Database::ReadAllCameras() const {
  SqliteStatement statement =
      Prepare(std::string(kSelectCamera) + " ORDER BY camera_id");
  std::vector<Camera> cameras;
  while (statement.Step()) {
    cameras.push_back(ReadCameraRow(statement, path_));
  }
  return cameras;
}

}  // namespace colmap_lidar
