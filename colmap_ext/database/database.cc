#include "colmap_ext/database/database.h"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "colmap_ext/database/schema.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {
namespace {

using RowMajorMatrix3d = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
using RowMajorMatrix3x4d = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;

int64_t ToSqliteId(const uint64_t id) { return static_cast<int64_t>(id); }

// COLMAP stores swapped pairs in (smaller, larger) orientation and converts
// on read and write (base/database.cc); this is that conversion.
FeatureMatchesBlob SwapMatchColumns(const FeatureMatchesBlob& matches) {
  FeatureMatchesBlob swapped(matches.rows(), 2);
  swapped.col(0) = matches.col(1);
  swapped.col(1) = matches.col(0);
  return swapped;
}

TwoViewGeometry InvertTwoViewGeometry(const TwoViewGeometry& geometry) {
  TwoViewGeometry inverted;
  inverted.config = geometry.config;
  inverted.inlier_matches = SwapMatchColumns(geometry.inlier_matches);
  inverted.F = geometry.F.transpose();
  inverted.E = geometry.E.transpose();
  // An unset (zero) H stays zero instead of becoming inf.
  if (geometry.H.determinant() != 0.0) {
    inverted.H = geometry.H.inverse();
  }
  if (geometry.qvec.squaredNorm() > 0.0) {
    const Eigen::Quaterniond q2_from_1(geometry.qvec(0), geometry.qvec(1),
                                       geometry.qvec(2), geometry.qvec(3));
    const Rigid3d inverse =
        Rigid3d(q2_from_1.normalized(), geometry.tvec).Inverse();
    inverted.qvec << inverse.rotation.w(), inverse.rotation.x(),
        inverse.rotation.y(), inverse.rotation.z();
    inverted.tvec = inverse.translation;
  }
  return inverted;
}

void BindMatrix3d(SqliteStatement* statement, const int index,
                  const Eigen::Matrix3d& matrix) {
  const RowMajorMatrix3d row_major = matrix;
  statement->BindBlobArray(index, row_major.data(), 9);
}

// NULL and zero-length blobs read as zero, as COLMAP does.
template <int Rows, int Cols>
Eigen::Matrix<double, Rows, Cols> ReadFixedBlob(
    const SqliteStatement& statement, const int column,
    const std::string& what) {
  Eigen::Matrix<double, Rows, Cols, (Cols > 1 ? Eigen::RowMajor : 0)> matrix =
      decltype(matrix)::Zero();
  if (!statement.ColumnIsNull(column) && statement.ColumnBytes(column) > 0) {
    statement.ColumnBlobArray(column, Rows * Cols, matrix.data(), what);
  }
  return matrix;
}

FeatureMatchesBlob ReadMatchesBlob(const SqliteStatement& statement,
                                   const int rows_column,
                                   const std::string& what) {
  const int64_t rows = statement.ColumnInt64(rows_column);
  const int64_t cols = statement.ColumnInt64(rows_column + 1);
  THROW_CHECK(rows >= 0 && (cols == 2 || rows == 0),
              "Bad shape " << rows << " x " << cols << " of " << what);
  FeatureMatchesBlob matches(rows, 2);
  statement.ColumnBlobArray(rows_column + 2, static_cast<size_t>(rows) * 2,
                            matches.data(), what);
  return matches;
}

std::string PairName(const image_t image_id1, const image_t image_id2) {
  return "image pair (" + std::to_string(image_id1) + ", " +
         std::to_string(image_id2) + ")";
}

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

// Column order: image_id, name, camera_id, prior_qw..qz, prior_tx..tz.
DatabaseImage ReadImageRow(const SqliteStatement& statement) {
  DatabaseImage image;
  image.image_id = static_cast<image_t>(statement.ColumnInt64(0));
  image.name = statement.ColumnText(1);
  image.camera_id = static_cast<camera_t>(statement.ColumnInt64(2));
  bool has_q = true;
  for (int i = 3; i < 7; ++i) {
    has_q = has_q && !statement.ColumnIsNull(i);
  }
  if (has_q) {
    image.prior_q = Eigen::Quaterniond(
        statement.ColumnDouble(3), statement.ColumnDouble(4),
        statement.ColumnDouble(5), statement.ColumnDouble(6));
  }
  bool has_t = true;
  for (int i = 7; i < 10; ++i) {
    has_t = has_t && !statement.ColumnIsNull(i);
  }
  if (has_t) {
    image.prior_t =
        Eigen::Vector3d(statement.ColumnDouble(7), statement.ColumnDouble(8),
                        statement.ColumnDouble(9));
  }
  return image;
}

// Binds name, camera_id and the seven prior columns from `first_index` on.
void BindImageColumns(SqliteStatement* statement, const int first_index,
                      const DatabaseImage& image) {
  statement->BindText(first_index, image.name);
  statement->BindInt64(first_index + 1, image.camera_id);
  for (int i = 0; i < 4; ++i) {
    if (image.prior_q) {
      const Eigen::Quaterniond& q = *image.prior_q;
      const double values[4] = {q.w(), q.x(), q.y(), q.z()};
      statement->BindDouble(first_index + 2 + i, values[i]);
    } else {
      statement->BindNull(first_index + 2 + i);
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (image.prior_t) {
      statement->BindDouble(first_index + 6 + i, (*image.prior_t)(i));
    } else {
      statement->BindNull(first_index + 6 + i);
    }
  }
}

constexpr const char* kSelectImage =
    "SELECT image_id, name, camera_id, prior_qw, prior_qx, prior_qy, "
    "prior_qz, prior_tx, prior_ty, prior_tz FROM images";
constexpr const char* kSelectCamera =
    "SELECT camera_id, model, width, height, params, prior_focal_length "
    "FROM cameras";
constexpr const char* kSelectTwoViewGeometry =
    "SELECT pair_id, rows, cols, data, config, F, E, H, qvec, tvec "
    "FROM two_view_geometries";

TwoViewGeometry ReadTwoViewGeometryRow(const SqliteStatement& statement,
                                       const std::string& what) {
  TwoViewGeometry geometry;
  geometry.inlier_matches = ReadMatchesBlob(statement, 1, what);
  geometry.config =
      static_cast<TwoViewGeometryConfig>(statement.ColumnInt64(4));
  geometry.F = ReadFixedBlob<3, 3>(statement, 5, "F of " + what);
  geometry.E = ReadFixedBlob<3, 3>(statement, 6, "E of " + what);
  geometry.H = ReadFixedBlob<3, 3>(statement, 7, "H of " + what);
  geometry.qvec = ReadFixedBlob<4, 1>(statement, 8, "qvec of " + what);
  geometry.tvec = ReadFixedBlob<3, 1>(statement, 9, "tvec of " + what);
  return geometry;
}

}  // namespace

// ---------------------------------------------------------------------------
// Connection and schema.

Database::Database(const std::string& path) { Open(path); }

Database::~Database() { Close(); }

Database::Database(Database&& other) noexcept
    : handle_(std::exchange(other.handle_, nullptr)),
      path_(std::move(other.path_)),
      next_savepoint_id_(other.next_savepoint_id_) {}

Database& Database::operator=(Database&& other) noexcept {
  if (this != &other) {
    Close();
    handle_ = std::exchange(other.handle_, nullptr);
    path_ = std::move(other.path_);
    next_savepoint_id_ = other.next_savepoint_id_;
  }
  return *this;
}

void Database::Open(const std::string& path) {
  Close();
  sqlite3* handle = nullptr;
  const int result =
      sqlite3_open_v2(path.c_str(), &handle,
                      SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr);
  if (result != SQLITE_OK) {
    const std::string message =
        handle != nullptr ? sqlite3_errmsg(handle) : sqlite3_errstr(result);
    sqlite3_close(handle);
    THROW_ERROR("Cannot open database " << path << ": " << message);
  }
  handle_ = handle;
  path_ = path;
  try {
    // SQLite reads the header lazily: the first query is where a file that
    // is not a database fails ("file is not a database").
    bool is_new = false;
    {
      SqliteStatement statement = Prepare("SELECT count(*) FROM sqlite_master");
      THROW_CHECK(statement.Step(), "No result from sqlite_master of " << path);
      is_new = statement.ColumnInt64(0) == 0;
    }
    // COLMAP's connection settings (colmap-formats.md §1.1), except
    // synchronous=NORMAL instead of OFF: with WAL it still never corrupts
    // the file on an application crash and keeps it intact on power loss.
    Execute(
        "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL; "
        "PRAGMA temp_store=MEMORY; PRAGMA foreign_keys=ON;");
    sqlite3_busy_timeout(handle_, 10000);
    CreateAndCheckSchema(is_new);
  } catch (...) {
    Close();
    throw;
  }
}

void Database::Close() {
  if (handle_ == nullptr) {
    return;
  }
  // sqlite3_close_v2 defers the close until every statement is finalized;
  // statements are RAII-owned by callers, so this never leaks.
  sqlite3_close_v2(handle_);
  handle_ = nullptr;
}

void Database::CheckOpen() const {
  THROW_CHECK(handle_ != nullptr, "Database "
                                      << (path_.empty() ? "(none)" : path_)
                                      << " is not open");
}

SqliteStatement Database::Prepare(const std::string& sql) const {
  CheckOpen();
  return SqliteStatement(handle_, path_, sql);
}

void Database::Execute(const std::string& sql) const {
  CheckOpen();
  char* error = nullptr;
  const int result =
      sqlite3_exec(handle_, sql.c_str(), nullptr, nullptr, &error);
  if (result != SQLITE_OK) {
    const std::string message = error != nullptr ? error : "";
    sqlite3_free(error);
    THROW_ERROR("SQLite error in " << path_ << " (" << sql << "): " << message);
  }
}

int Database::UserVersion() const {
  SqliteStatement statement = Prepare("PRAGMA user_version");
  THROW_CHECK(statement.Step(), "No user_version in " << path_);
  return static_cast<int>(statement.ColumnInt64(0));
}

int Database::ExtSchemaVersion() const {
  SqliteStatement statement =
      Prepare("SELECT value FROM ext_schema WHERE key = ?");
  statement.BindText(1, kExtSchemaVersionKey);
  THROW_CHECK(statement.Step(),
              "No " << kExtSchemaVersionKey << " in ext_schema of " << path_);
  return static_cast<int>(
      ParseInt(statement.ColumnText(0),
               std::string(kExtSchemaVersionKey) + " in " + path_));
}

std::vector<std::string> Database::TableColumns(
    const std::string& table) const {
  SqliteStatement statement = Prepare("PRAGMA table_info(" + table + ")");
  std::vector<std::string> columns;
  while (statement.Step()) {
    columns.push_back(statement.ColumnText(1));
  }
  return columns;
}

void Database::CreateAndCheckSchema(const bool is_new) {
  DatabaseTransaction transaction(this);

  auto check_columns = [this](const TableSchema& schema) {
    const std::vector<std::string> columns = TableColumns(schema.name);
    for (const std::string& required : schema.required_columns) {
      THROW_CHECK(
          std::find(columns.begin(), columns.end(), required) != columns.end(),
          "Table " << schema.name << " in " << path_ << " lacks column "
                   << required << "; not a COLMAP 3.8 / colmap-lidar database");
    }
  };

  for (const TableSchema& schema : StockTableSchemas()) {
    Execute(schema.create_sql);
    if (schema.name == "two_view_geometries") {
      // COLMAP 3.8 upgrades older databases the same way on open.
      const std::vector<std::string> columns = TableColumns(schema.name);
      for (const std::string& column : TwoViewGeometryLegacyColumns()) {
        if (std::find(columns.begin(), columns.end(), column) ==
            columns.end()) {
          Execute("ALTER TABLE two_view_geometries ADD COLUMN " + column +
                  " BLOB");
        }
      }
    }
    check_columns(schema);
  }

  const std::vector<TableSchema>& ext_schemas = ExtTableSchemas();
  // ext_schema comes first so the version is checked before any other ext
  // table is created in a database written by newer code.
  Execute(ext_schemas.front().create_sql);
  check_columns(ext_schemas.front());
  {
    SqliteStatement statement =
        Prepare("SELECT value FROM ext_schema WHERE key = ?");
    statement.BindText(1, kExtSchemaVersionKey);
    if (statement.Step()) {
      const long long version =
          ParseInt(statement.ColumnText(0),
                   std::string(kExtSchemaVersionKey) + " in " + path_);
      THROW_CHECK(version <= kExtSchemaVersion,
                  "Database " << path_ << " has ext schema version " << version
                              << ", newer than the supported "
                              << kExtSchemaVersion << "; update colmap-lidar");
    }
  }
  for (const TableSchema& schema : ext_schemas) {
    Execute(schema.create_sql);
    check_columns(schema);
  }
  {
    SqliteStatement statement =
        Prepare("INSERT OR REPLACE INTO ext_schema (key, value) VALUES (?, ?)");
    statement.BindText(1, kExtSchemaVersionKey);
    statement.BindText(2, std::to_string(kExtSchemaVersion));
    statement.Execute();
  }
  // Never touch the user_version of a database someone else created.
  if (is_new) {
    Execute("PRAGMA user_version=" + std::to_string(kColmapUserVersion));
  }
  transaction.Commit();
}

// ---------------------------------------------------------------------------
// Pair ids.

image_pair_t Database::ImagePairToPairId(image_t image_id1, image_t image_id2) {
  THROW_CHECK(image_id1 < kMaxNumImages && image_id2 < kMaxNumImages,
              "Image ids " << image_id1 << ", " << image_id2
                           << " exceed COLMAP's limit " << kMaxNumImages);
  if (SwapImagePair(image_id1, image_id2)) {
    std::swap(image_id1, image_id2);
  }
  return static_cast<image_pair_t>(image_id1) * kMaxNumImages + image_id2;
}

std::pair<image_t, image_t> Database::PairIdToImagePair(
    const image_pair_t pair_id) {
  const image_t image_id2 = static_cast<image_t>(pair_id % kMaxNumImages);
  const image_t image_id1 =
      static_cast<image_t>((pair_id - image_id2) / kMaxNumImages);
  return {image_id1, image_id2};
}

// ---------------------------------------------------------------------------
// Existence and counts.

size_t Database::CountRows(const std::string& sql, const int64_t id) const {
  SqliteStatement statement = Prepare(sql);
  if (id >= 0) {
    statement.BindInt64(1, id);
  }
  THROW_CHECK(statement.Step(), "No result for " << sql << " in " << path_);
  return static_cast<size_t>(statement.ColumnInt64(0));
}

size_t Database::SumRows(const std::string& table) const {
  return CountRows("SELECT IFNULL(SUM(rows), 0) FROM " + table);
}

bool Database::ExistsCamera(const camera_t camera_id) const {
  return CountRows("SELECT count(*) FROM cameras WHERE camera_id = ?",
                   camera_id) > 0;
}

bool Database::ExistsImage(const image_t image_id) const {
  return CountRows("SELECT count(*) FROM images WHERE image_id = ?", image_id) >
         0;
}

bool Database::ExistsImageWithName(const std::string& name) const {
  SqliteStatement statement =
      Prepare("SELECT count(*) FROM images WHERE name = ?");
  statement.BindText(1, name);
  statement.Step();
  return statement.ColumnInt64(0) > 0;
}

bool Database::ExistsKeypoints(const image_t image_id) const {
  return CountRows("SELECT count(*) FROM keypoints WHERE image_id = ?",
                   image_id) > 0;
}

bool Database::ExistsDescriptors(const image_t image_id) const {
  return CountRows("SELECT count(*) FROM descriptors WHERE image_id = ?",
                   image_id) > 0;
}

bool Database::ExistsMatches(const image_t image_id1,
                             const image_t image_id2) const {
  return CountRows("SELECT count(*) FROM matches WHERE pair_id = ?",
                   ToSqliteId(ImagePairToPairId(image_id1, image_id2))) > 0;
}

bool Database::ExistsTwoViewGeometry(const image_t image_id1,
                                     const image_t image_id2) const {
  return CountRows("SELECT count(*) FROM two_view_geometries WHERE pair_id = ?",
                   ToSqliteId(ImagePairToPairId(image_id1, image_id2))) > 0;
}

bool Database::ExistsLidarScan(const image_t image_id) const {
  return CountRows("SELECT count(*) FROM ext_lidar_scans WHERE image_id = ?",
                   image_id) > 0;
}

size_t Database::NumCameras() const {
  return CountRows("SELECT count(*) FROM cameras");
}

size_t Database::NumImages() const {
  return CountRows("SELECT count(*) FROM images");
}

size_t Database::NumKeypoints() const { return SumRows("keypoints"); }

size_t Database::NumKeypointsForImage(const image_t image_id) const {
  return CountRows(
      "SELECT IFNULL(SUM(rows), 0) FROM keypoints WHERE image_id = ?",
      image_id);
}

size_t Database::NumDescriptors() const { return SumRows("descriptors"); }

size_t Database::NumDescriptorsForImage(const image_t image_id) const {
  return CountRows(
      "SELECT IFNULL(SUM(rows), 0) FROM descriptors WHERE image_id = ?",
      image_id);
}

size_t Database::NumMatches() const { return SumRows("matches"); }

size_t Database::NumInlierMatches() const {
  return SumRows("two_view_geometries");
}

size_t Database::NumMatchedImagePairs() const {
  return CountRows("SELECT count(*) FROM matches WHERE rows > 0");
}

size_t Database::NumVerifiedImagePairs() const {
  return CountRows("SELECT count(*) FROM two_view_geometries WHERE rows > 0");
}

size_t Database::NumLidarScans() const {
  return CountRows("SELECT count(*) FROM ext_lidar_scans");
}

// ---------------------------------------------------------------------------
// Cameras.

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

// ---------------------------------------------------------------------------
// Images.

image_t Database::WriteImage(const DatabaseImage& image) {
  THROW_CHECK(!image.name.empty(), "Image without a name for " << path_);
  SqliteStatement statement = Prepare(
      "INSERT INTO images (image_id, name, camera_id, prior_qw, prior_qx, "
      "prior_qy, prior_qz, prior_tx, prior_ty, prior_tz) "
      "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  if (image.image_id != kInvalidImageId) {
    statement.BindInt64(1, image.image_id);
  } else {
    statement.BindNull(1);
  }
  BindImageColumns(&statement, 2, image);
  statement.Execute();
  return static_cast<image_t>(sqlite3_last_insert_rowid(handle_));
}

void Database::UpdateImage(const DatabaseImage& image) {
  SqliteStatement statement = Prepare(
      "UPDATE images SET name = ?, camera_id = ?, prior_qw = ?, prior_qx = ?, "
      "prior_qy = ?, prior_qz = ?, prior_tx = ?, prior_ty = ?, prior_tz = ? "
      "WHERE image_id = ?");
  BindImageColumns(&statement, 1, image);
  statement.BindInt64(10, image.image_id);
  statement.Execute();
  THROW_CHECK(sqlite3_changes(handle_) == 1, "Cannot update image "
                                                 << image.image_id << " in "
                                                 << path_ << ": no such image");
}

std::optional<DatabaseImage> Database::ReadImage(const image_t image_id) const {
  SqliteStatement statement =
      Prepare(std::string(kSelectImage) + " WHERE image_id = ?");
  statement.BindInt64(1, image_id);
  if (!statement.Step()) {
    return std::nullopt;
  }
  return ReadImageRow(statement);
}

std::optional<DatabaseImage> Database::ReadImageWithName(
    const std::string& name) const {
  SqliteStatement statement =
      Prepare(std::string(kSelectImage) + " WHERE name = ?");
  statement.BindText(1, name);
  if (!statement.Step()) {
    return std::nullopt;
  }
  return ReadImageRow(statement);
}

std::vector<DatabaseImage> Database::ReadAllImages() const {
  SqliteStatement statement =
      Prepare(std::string(kSelectImage) + " ORDER BY image_id");
  std::vector<DatabaseImage> images;
  while (statement.Step()) {
    images.push_back(ReadImageRow(statement));
  }
  return images;
}

// ---------------------------------------------------------------------------
// Keypoints and descriptors.

void Database::WriteKeypoints(const image_t image_id,
                              const FeatureKeypointsBlob& keypoints) {
  THROW_CHECK(keypoints.cols() == 2 || keypoints.cols() == 4 ||
                  keypoints.cols() == 6 || keypoints.rows() == 0,
              "Keypoints of image " << image_id << " have " << keypoints.cols()
                                    << " columns; COLMAP reads 2, 4 or 6 ("
                                    << path_ << ")");
  SqliteStatement statement = Prepare(
      "INSERT OR REPLACE INTO keypoints (image_id, rows, cols, data) "
      "VALUES (?, ?, ?, ?)");
  statement.BindInt64(1, image_id);
  statement.BindInt64(2, keypoints.rows());
  statement.BindInt64(3, keypoints.rows() == 0 ? 6 : keypoints.cols());
  statement.BindBlobArray(4, keypoints.data(), keypoints.size());
  statement.Execute();
}

FeatureKeypointsBlob Database::ReadKeypoints(const image_t image_id) const {
  SqliteStatement statement =
      Prepare("SELECT rows, cols, data FROM keypoints WHERE image_id = ?");
  statement.BindInt64(1, image_id);
  if (!statement.Step()) {
    return FeatureKeypointsBlob(0, 6);
  }
  const int64_t rows = statement.ColumnInt64(0);
  const int64_t cols = statement.ColumnInt64(1);
  const std::string what = "keypoints of image " + std::to_string(image_id);
  THROW_CHECK(rows >= 0 && (cols == 2 || cols == 4 || cols == 6),
              "Bad shape " << rows << " x " << cols << " of " << what << " in "
                           << path_);
  FeatureKeypointsBlob keypoints(rows, cols);
  statement.ColumnBlobArray(2, keypoints.size(), keypoints.data(), what);
  return keypoints;
}

void Database::WriteDescriptors(const image_t image_id,
                                const FeatureDescriptorsBlob& descriptors) {
  SqliteStatement statement = Prepare(
      "INSERT OR REPLACE INTO descriptors (image_id, rows, cols, data) "
      "VALUES (?, ?, ?, ?)");
  statement.BindInt64(1, image_id);
  statement.BindInt64(2, descriptors.rows());
  statement.BindInt64(3, descriptors.rows() == 0 ? 128 : descriptors.cols());
  statement.BindBlobArray(4, descriptors.data(), descriptors.size());
  statement.Execute();
}

FeatureDescriptorsBlob Database::ReadDescriptors(const image_t image_id) const {
  SqliteStatement statement =
      Prepare("SELECT rows, cols, data FROM descriptors WHERE image_id = ?");
  statement.BindInt64(1, image_id);
  if (!statement.Step()) {
    return FeatureDescriptorsBlob(0, 128);
  }
  const int64_t rows = statement.ColumnInt64(0);
  const int64_t cols = statement.ColumnInt64(1);
  const std::string what = "descriptors of image " + std::to_string(image_id);
  THROW_CHECK(rows >= 0 && cols >= 0, "Bad shape " << rows << " x " << cols
                                                   << " of " << what << " in "
                                                   << path_);
  FeatureDescriptorsBlob descriptors(rows, cols);
  statement.ColumnBlobArray(2, descriptors.size(), descriptors.data(), what);
  return descriptors;
}

// ---------------------------------------------------------------------------
// Matches.

void Database::WriteMatches(const image_t image_id1, const image_t image_id2,
                            const FeatureMatchesBlob& matches) {
  const image_pair_t pair_id = ImagePairToPairId(image_id1, image_id2);
  SqliteStatement statement = Prepare(
      "INSERT INTO matches (pair_id, rows, cols, data) VALUES (?, ?, ?, ?)");
  statement.BindInt64(1, ToSqliteId(pair_id));
  statement.BindInt64(2, matches.rows());
  statement.BindInt64(3, 2);
  if (matches.rows() == 0) {
    statement.BindNull(4);
  } else if (SwapImagePair(image_id1, image_id2)) {
    const FeatureMatchesBlob swapped = SwapMatchColumns(matches);
    statement.BindBlobArray(4, swapped.data(), swapped.size());
  } else {
    statement.BindBlobArray(4, matches.data(), matches.size());
  }
  statement.Execute();
}

FeatureMatchesBlob Database::ReadMatches(const image_t image_id1,
                                         const image_t image_id2) const {
  SqliteStatement statement =
      Prepare("SELECT rows, cols, data FROM matches WHERE pair_id = ?");
  statement.BindInt64(1, ToSqliteId(ImagePairToPairId(image_id1, image_id2)));
  if (!statement.Step()) {
    return FeatureMatchesBlob(0, 2);
  }
  const FeatureMatchesBlob matches = ReadMatchesBlob(
      statement, 0,
      "matches of " + PairName(image_id1, image_id2) + " in " + path_);
  return SwapImagePair(image_id1, image_id2) ? SwapMatchColumns(matches)
                                             : matches;
}

std::vector<std::pair<image_pair_t, FeatureMatchesBlob>>
Database::ReadAllMatches() const {
  SqliteStatement statement =
      Prepare("SELECT pair_id, rows, cols, data FROM matches ORDER BY pair_id");
  std::vector<std::pair<image_pair_t, FeatureMatchesBlob>> all_matches;
  while (statement.Step()) {
    const image_pair_t pair_id =
        static_cast<image_pair_t>(statement.ColumnInt64(0));
    all_matches.emplace_back(
        pair_id, ReadMatchesBlob(statement, 1,
                                 "matches of pair_id " +
                                     std::to_string(pair_id) + " in " + path_));
  }
  return all_matches;
}

void Database::DeleteMatches(const image_t image_id1, const image_t image_id2) {
  SqliteStatement statement = Prepare("DELETE FROM matches WHERE pair_id = ?");
  statement.BindInt64(1, ToSqliteId(ImagePairToPairId(image_id1, image_id2)));
  statement.Execute();
}

void Database::ClearMatches() { Execute("DELETE FROM matches"); }

// ---------------------------------------------------------------------------
// Two-view geometries.

void Database::WriteTwoViewGeometry(const image_t image_id1,
                                    const image_t image_id2,
                                    const TwoViewGeometry& geometry) {
  const image_pair_t pair_id = ImagePairToPairId(image_id1, image_id2);
  const TwoViewGeometry stored = SwapImagePair(image_id1, image_id2)
                                     ? InvertTwoViewGeometry(geometry)
                                     : geometry;
  SqliteStatement statement = Prepare(
      "INSERT INTO two_view_geometries (pair_id, rows, cols, data, config, "
      "F, E, H, qvec, tvec) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  statement.BindInt64(1, ToSqliteId(pair_id));
  statement.BindInt64(2, stored.inlier_matches.rows());
  statement.BindInt64(3, 2);
  if (stored.inlier_matches.rows() == 0) {
    statement.BindNull(4);
  } else {
    statement.BindBlobArray(4, stored.inlier_matches.data(),
                            stored.inlier_matches.size());
  }
  statement.BindInt64(5, static_cast<int64_t>(stored.config));
  BindMatrix3d(&statement, 6, stored.F);
  BindMatrix3d(&statement, 7, stored.E);
  BindMatrix3d(&statement, 8, stored.H);
  statement.BindBlobArray(9, stored.qvec.data(), 4);
  statement.BindBlobArray(10, stored.tvec.data(), 3);
  statement.Execute();
}

std::optional<TwoViewGeometry> Database::ReadTwoViewGeometry(
    const image_t image_id1, const image_t image_id2) const {
  SqliteStatement statement =
      Prepare(std::string(kSelectTwoViewGeometry) + " WHERE pair_id = ?");
  statement.BindInt64(1, ToSqliteId(ImagePairToPairId(image_id1, image_id2)));
  if (!statement.Step()) {
    return std::nullopt;
  }
  const TwoViewGeometry geometry = ReadTwoViewGeometryRow(
      statement, "two-view geometry of " + PairName(image_id1, image_id2) +
                     " in " + path_);
  return SwapImagePair(image_id1, image_id2) ? InvertTwoViewGeometry(geometry)
                                             : geometry;
}

std::vector<std::pair<image_pair_t, TwoViewGeometry>>
Database::ReadAllTwoViewGeometries() const {
  SqliteStatement statement =
      Prepare(std::string(kSelectTwoViewGeometry) + " ORDER BY pair_id");
  std::vector<std::pair<image_pair_t, TwoViewGeometry>> geometries;
  while (statement.Step()) {
    const image_pair_t pair_id =
        static_cast<image_pair_t>(statement.ColumnInt64(0));
    geometries.emplace_back(
        pair_id, ReadTwoViewGeometryRow(
                     statement, "two-view geometry of pair_id " +
                                    std::to_string(pair_id) + " in " + path_));
  }
  return geometries;
}

void Database::DeleteTwoViewGeometry(const image_t image_id1,
                                     const image_t image_id2) {
  SqliteStatement statement =
      Prepare("DELETE FROM two_view_geometries WHERE pair_id = ?");
  statement.BindInt64(1, ToSqliteId(ImagePairToPairId(image_id1, image_id2)));
  statement.Execute();
}

void Database::ClearTwoViewGeometries() {
  Execute("DELETE FROM two_view_geometries");
}

// ---------------------------------------------------------------------------
// ext_lidar_scans.

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

// ---------------------------------------------------------------------------
// Transactions.

DatabaseTransaction::DatabaseTransaction(Database* database)
    : database_(database) {
  THROW_CHECK(database_ != nullptr, "DatabaseTransaction without a database");
  savepoint_ =
      "colmap_lidar_sp_" + std::to_string(database_->next_savepoint_id_++);
  database_->Execute("SAVEPOINT " + savepoint_);
}

DatabaseTransaction::~DatabaseTransaction() {
  if (finished_ || !database_->IsOpen()) {
    return;
  }
  try {
    // ROLLBACK TO undoes the changes but keeps the savepoint open; RELEASE
    // then ends it (and the transaction when it is the outermost).
    database_->Execute("ROLLBACK TO " + savepoint_ + "; RELEASE " + savepoint_);
  } catch (const Error& error) {
    LOG(ERROR) << "Rollback failed: " << error.what();
  }
}

void DatabaseTransaction::Commit() {
  THROW_CHECK(!finished_, "Transaction " << savepoint_ << " on "
                                         << database_->path()
                                         << " already committed");
  database_->Execute("RELEASE " + savepoint_);
  finished_ = true;
}

}  // namespace colmap_lidar
