// Database (database.h): the connection, the schema check on open, pair ids,
// existence tests and row counts, and transactions. The row IO of each table
// is in database_cameras.cc, database_images.cc, database_features.cc
// (keypoints, descriptors), database_matches.cc (matches, two-view
// geometries) and database_lidar_scans.cc (ext_lidar_scans).
#include "colmap_ext/database/database.h"

#include <sqlite3.h>

#include <algorithm>
#include <utility>

#include "colmap_ext/database/database_internal.h"
#include "colmap_ext/database/schema.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {
namespace {

using database_internal::ToSqliteId;

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
  // -1: no version row yet.
  long long stored_version = -1;
  {
    SqliteStatement statement =
        Prepare("SELECT value FROM ext_schema WHERE key = ?");
    statement.BindText(1, kExtSchemaVersionKey);
    if (statement.Step()) {
      const long long version =
          ParseInt(statement.ColumnText(0),
                   std::string(kExtSchemaVersionKey) + " in " + path_);
      stored_version = version;
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
  // Written only when it changes: rewriting the same row on every open
  // would change the file of a workspace that a failed command must leave
  // as it was.
  if (stored_version != kExtSchemaVersion) {
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
