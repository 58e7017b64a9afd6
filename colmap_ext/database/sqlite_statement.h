// A thin RAII wrapper around one prepared SQLite statement. It is the only
// place outside Database (database.cc, database_*.cc) that touches the
// SQLite C API, so that modules adding their own ext_* tables (see
// ext_schema.h) write their row IO against this class through
// Database::Prepare() instead of raw sqlite3 calls.
//
// Every failure throws colmap_lidar::Error naming the database path, the SQL
// and SQLite's message.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "colmap_ext/util/logging.h"

struct sqlite3;
struct sqlite3_stmt;

namespace colmap_lidar {

// Throws colmap_lidar::Error "SQLite error in <db_path> (<context>): <msg>"
// when `result_code` is not SQLITE_OK, SQLITE_ROW or SQLITE_DONE.
void CheckSqliteResult(int result_code, sqlite3* handle,
                       const std::string& db_path, const std::string& context);

class SqliteStatement {
 public:
  // Prepares `sql` (one statement) on an open connection.
  SqliteStatement(sqlite3* handle, const std::string& db_path,
                  const std::string& sql);
  ~SqliteStatement();
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;
  SqliteStatement(SqliteStatement&& other) noexcept;
  SqliteStatement& operator=(SqliteStatement&& other) noexcept;

  // Parameters are numbered from 1, as in SQLite ("?" in order).
  void BindInt64(int index, int64_t value);
  void BindDouble(int index, double value);
  void BindText(int index, const std::string& value);
  void BindNull(int index);
  // Binds a copy of `num_bytes` bytes; binds a zero-length blob when
  // num_bytes == 0 (use BindNull for NULL).
  void BindBlob(int index, const void* data, size_t num_bytes);
  template <typename T>
  void BindBlobArray(int index, const T* data, size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    BindBlob(index, data, count * sizeof(T));
  }

  // Advances to the next result row: true when a row is available, false
  // when the statement has finished. Throws on any error (including a
  // constraint violation).
  bool Step();
  // Runs a statement that returns no rows (INSERT, UPDATE, DELETE, DDL).
  void Execute();
  // Makes the statement runnable again and clears all bindings.
  void Reset();

  // Columns of the current row are numbered from 0.
  bool ColumnIsNull(int column) const;
  int64_t ColumnInt64(int column) const;
  double ColumnDouble(int column) const;
  std::string ColumnText(int column) const;
  size_t ColumnBytes(int column) const;
  // Copies a blob column into `count` elements of T; throws naming `what`
  // when the blob does not hold exactly count * sizeof(T) bytes. A NULL or
  // zero-length blob is accepted only for count == 0.
  template <typename T>
  void ColumnBlobArray(int column, size_t count, T* data,
                       const std::string& what) const {
    static_assert(std::is_trivially_copyable_v<T>);
    const size_t num_bytes = ColumnBytes(column);
    THROW_CHECK(num_bytes == count * sizeof(T),
                "Blob of " << what << " in " << db_path_ << " has " << num_bytes
                           << " bytes, expected " << count * sizeof(T));
    if (num_bytes > 0) {
      std::memcpy(data, ColumnBlobData(column), num_bytes);
    }
  }

  const std::string& sql() const { return sql_; }

 private:
  const void* ColumnBlobData(int column) const;
  void CheckBind(int result_code, int index);

  sqlite3* handle_ = nullptr;
  sqlite3_stmt* statement_ = nullptr;
  std::string db_path_;
  std::string sql_;
};

}  // namespace colmap_lidar
