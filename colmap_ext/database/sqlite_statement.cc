#include "colmap_ext/database/sqlite_statement.h"

#include <sqlite3.h>

#include <utility>

namespace colmap_lidar {

void CheckSqliteResult(const int result_code, sqlite3* handle,
                       const std::string& db_path, const std::string& context) {
  if (result_code == SQLITE_OK || result_code == SQLITE_ROW ||
      result_code == SQLITE_DONE) {
    return;
  }
  // sqlite3_errmsg describes the most recent failure on the connection,
  // which is more specific (e.g. the failed constraint) than errstr.
  const char* message =
      handle != nullptr ? sqlite3_errmsg(handle) : sqlite3_errstr(result_code);
  THROW_ERROR("SQLite error in " << db_path << " (" << context
                                 << "): " << message);
}

SqliteStatement::SqliteStatement(sqlite3* handle, const std::string& db_path,
                                 const std::string& sql)
    : handle_(handle), db_path_(db_path), sql_(sql) {
  THROW_CHECK(handle_ != nullptr,
              "Database " << db_path_ << " is not open (" << sql_ << ")");
  const int result =
      sqlite3_prepare_v2(handle_, sql_.c_str(), -1, &statement_, nullptr);
  if (result != SQLITE_OK) {
    sqlite3_finalize(statement_);
    statement_ = nullptr;
    CheckSqliteResult(result, handle_, db_path_, "preparing " + sql_);
  }
}

SqliteStatement::~SqliteStatement() {
  // Finalizing never fails in a way we could act on; errors were reported
  // by the step that caused them.
  sqlite3_finalize(statement_);
}

SqliteStatement::SqliteStatement(SqliteStatement&& other) noexcept
    : handle_(std::exchange(other.handle_, nullptr)),
      statement_(std::exchange(other.statement_, nullptr)),
      db_path_(std::move(other.db_path_)),
      sql_(std::move(other.sql_)) {}

SqliteStatement& SqliteStatement::operator=(SqliteStatement&& other) noexcept {
  if (this != &other) {
    sqlite3_finalize(statement_);
    handle_ = std::exchange(other.handle_, nullptr);
    statement_ = std::exchange(other.statement_, nullptr);
    db_path_ = std::move(other.db_path_);
    sql_ = std::move(other.sql_);
  }
  return *this;
}

void SqliteStatement::CheckBind(const int result_code, const int index) {
  if (result_code != SQLITE_OK) {
    CheckSqliteResult(
        result_code, handle_, db_path_,
        "binding parameter " + std::to_string(index) + " of " + sql_);
  }
}

void SqliteStatement::BindInt64(const int index, const int64_t value) {
  CheckBind(sqlite3_bind_int64(statement_, index, value), index);
}

void SqliteStatement::BindDouble(const int index, const double value) {
  CheckBind(sqlite3_bind_double(statement_, index, value), index);
}

void SqliteStatement::BindText(const int index, const std::string& value) {
  CheckBind(sqlite3_bind_text(statement_, index, value.c_str(),
                              static_cast<int>(value.size()), SQLITE_TRANSIENT),
            index);
}

void SqliteStatement::BindNull(const int index) {
  CheckBind(sqlite3_bind_null(statement_, index), index);
}

void SqliteStatement::BindBlob(const int index, const void* data,
                               const size_t num_bytes) {
  if (num_bytes == 0) {
    CheckBind(sqlite3_bind_zeroblob(statement_, index, 0), index);
    return;
  }
  CheckBind(sqlite3_bind_blob64(statement_, index, data,
                                static_cast<sqlite3_uint64>(num_bytes),
                                SQLITE_TRANSIENT),
            index);
}

bool SqliteStatement::Step() {
  const int result = sqlite3_step(statement_);
  CheckSqliteResult(result, handle_, db_path_, sql_);
  return result == SQLITE_ROW;
}

void SqliteStatement::Execute() {
  while (Step()) {
  }
}

void SqliteStatement::Reset() {
  // sqlite3_reset repeats the error of the last step, which Step() already
  // reported, so its result is ignored here.
  sqlite3_reset(statement_);
  sqlite3_clear_bindings(statement_);
}

bool SqliteStatement::ColumnIsNull(const int column) const {
  return sqlite3_column_type(statement_, column) == SQLITE_NULL;
}

int64_t SqliteStatement::ColumnInt64(const int column) const {
  return sqlite3_column_int64(statement_, column);
}

double SqliteStatement::ColumnDouble(const int column) const {
  return sqlite3_column_double(statement_, column);
}

std::string SqliteStatement::ColumnText(const int column) const {
  const unsigned char* text = sqlite3_column_text(statement_, column);
  const int num_bytes = sqlite3_column_bytes(statement_, column);
  if (text == nullptr) {
    return std::string();
  }
  return std::string(reinterpret_cast<const char*>(text),
                     static_cast<size_t>(num_bytes));
}

size_t SqliteStatement::ColumnBytes(const int column) const {
  // sqlite3_column_blob must come before sqlite3_column_bytes so that the
  // size refers to the blob representation.
  sqlite3_column_blob(statement_, column);
  return static_cast<size_t>(sqlite3_column_bytes(statement_, column));
}

const void* SqliteStatement::ColumnBlobData(const int column) const {
  return sqlite3_column_blob(statement_, column);
}

}  // namespace colmap_lidar
