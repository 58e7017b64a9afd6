// Compares our schema with what the stock colmap 3.8 binary creates, and
// checks that opening a colmap-created database only adds our ext_* tables.
#include "colmap_ext/database/schema.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <map>
#include <regex>
#include <tuple>

#include "colmap_ext/database/database.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

// Everything about a table that colmap could depend on.
struct TableInfo {
  std::string sql;
  // (cid, name, type, notnull, default, pk) from PRAGMA table_info.
  std::vector<std::tuple<int64_t, std::string, std::string, int64_t,
                         std::string, int64_t>>
      columns;
  bool operator==(const TableInfo& other) const {
    return sql == other.sql && columns == other.columns;
  }
};

// sqlite_master objects by name -> info (only tables get columns).
std::map<std::string, TableInfo> ReadSchema(const std::string& path) {
  sqlite3* handle = nullptr;
  EXPECT_EQ(
      sqlite3_open_v2(path.c_str(), &handle, SQLITE_OPEN_READONLY, nullptr),
      SQLITE_OK);
  std::map<std::string, TableInfo> schema;
  {
    SqliteStatement master(handle, path,
                           "SELECT type, name, IFNULL(sql, '') FROM "
                           "sqlite_master");
    while (master.Step()) {
      schema[master.ColumnText(1)].sql = master.ColumnText(2);
    }
  }
  for (auto& [name, info] : schema) {
    SqliteStatement columns(handle, path, "PRAGMA table_info(" + name + ")");
    while (columns.Step()) {
      info.columns.emplace_back(columns.ColumnInt64(0), columns.ColumnText(1),
                                columns.ColumnText(2), columns.ColumnInt64(3),
                                columns.ColumnText(4), columns.ColumnInt64(5));
    }
  }
  sqlite3_close_v2(handle);
  return schema;
}

int ReadUserVersion(const std::string& path) {
  sqlite3* handle = nullptr;
  EXPECT_EQ(sqlite3_open(path.c_str(), &handle), SQLITE_OK);
  int version = -1;
  {
    SqliteStatement statement(handle, path, "PRAGMA user_version");
    EXPECT_TRUE(statement.Step());
    version = static_cast<int>(statement.ColumnInt64(0));
  }
  sqlite3_close_v2(handle);
  return version;
}

// Collapses runs of white space and drops it next to punctuation, so that
// statements with the same tokens compare equal.
std::string NormaliseSql(const std::string& sql) {
  std::string collapsed = std::regex_replace(sql, std::regex("\\s+"), " ");
  collapsed = std::regex_replace(collapsed, std::regex(" ?([(),;]) ?"), "$1");
  return collapsed;
}

std::string CreateWithColmap(const std::string& dir) {
  const std::string path = JoinPaths(dir, "colmap.db");
  const int code = testing::RunCommand(
      "colmap database_creator --database_path '" + path + "'",
      JoinPaths(dir, "database_creator.log"));
  EXPECT_EQ(code, 0) << ReadTextFile(JoinPaths(dir, "database_creator.log"));
  return path;
}

const std::vector<std::string> kStockObjects = {
    "cameras",     "images",  "index_name",          "keypoints",
    "descriptors", "matches", "two_view_geometries", "sqlite_sequence"};

TEST(Schema, FreshDatabaseEqualsColmapDatabaseCreator) {
  const std::string dir = testing::CreateTestDir();
  const std::string colmap_path = CreateWithColmap(dir);
  const std::string our_path = JoinPaths(dir, "ours.db");
  { Database database(our_path); }

  const auto colmap_schema = ReadSchema(colmap_path);
  const auto our_schema = ReadSchema(our_path);
  for (const std::string& name : kStockObjects) {
    ASSERT_EQ(colmap_schema.count(name), 1u) << name;
    ASSERT_EQ(our_schema.count(name), 1u) << name;
    const TableInfo& theirs = colmap_schema.at(name);
    const TableInfo& ours = our_schema.at(name);
    EXPECT_EQ(ours.columns, theirs.columns) << name;
    EXPECT_EQ(NormaliseSql(ours.sql), NormaliseSql(theirs.sql)) << name;
    // Our statements even keep colmap's spacing.
    EXPECT_EQ(ours.sql, theirs.sql) << name;
  }
  // Nothing else of colmap's is missing, and we only add ext_* tables (plus
  // their automatic indices).
  for (const auto& [name, info] : colmap_schema) {
    EXPECT_EQ(our_schema.count(name), 1u) << name;
  }
  for (const auto& [name, info] : our_schema) {
    if (colmap_schema.count(name) == 0) {
      EXPECT_TRUE(name.rfind("ext_", 0) == 0 ||
                  name.rfind("sqlite_autoindex_ext_", 0) == 0)
          << name;
    }
  }
  for (const TableSchema& schema : ExtTableSchemas()) {
    EXPECT_EQ(our_schema.count(schema.name), 1u) << schema.name;
  }
  EXPECT_EQ(ReadUserVersion(colmap_path), 3800);
  EXPECT_EQ(ReadUserVersion(our_path), 3800);
}

TEST(Schema, NormaliseSqlDetectsTokenChanges) {
  // The comparison above must be able to fail.
  EXPECT_EQ(NormaliseSql("CREATE TABLE a   (x  INTEGER ,\n y BLOB)"),
            NormaliseSql("CREATE TABLE a (x INTEGER, y BLOB)"));
  EXPECT_NE(NormaliseSql("CREATE TABLE a (x INTEGER NOT NULL)"),
            NormaliseSql("CREATE TABLE a (x INTEGER)"));
}

TEST(Schema, OpeningColmapDatabaseOnlyAddsExtTables) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = CreateWithColmap(dir);
  // A user_version that is not ours shows that we never rewrite it.
  {
    sqlite3* handle = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &handle), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(handle, "PRAGMA user_version=1234", nullptr, nullptr,
                           nullptr),
              SQLITE_OK);
    sqlite3_close(handle);
  }
  const auto before = ReadSchema(path);
  {
    Database database(path);
    EXPECT_EQ(database.UserVersion(), 1234);
    EXPECT_EQ(database.ExtSchemaVersion(), kExtSchemaVersion);
    EXPECT_EQ(database.NumCameras(), 0u);
  }
  const auto after = ReadSchema(path);
  for (const auto& [name, info] : before) {
    ASSERT_EQ(after.count(name), 1u) << name;
    EXPECT_TRUE(after.at(name) == info) << name;
  }
  for (const TableSchema& schema : ExtTableSchemas()) {
    ASSERT_EQ(after.count(schema.name), 1u) << schema.name;
    EXPECT_EQ(before.count(schema.name), 0u) << schema.name;
    for (const std::string& column : schema.required_columns) {
      bool found = false;
      for (const auto& entry : after.at(schema.name).columns) {
        found = found || std::get<1>(entry) == column;
      }
      EXPECT_TRUE(found) << schema.name << "." << column;
    }
  }
  EXPECT_EQ(ReadUserVersion(path), 1234);
  // Opening again changes nothing.
  { Database database(path); }
  EXPECT_EQ(ReadSchema(path).size(), after.size());
  EXPECT_EQ(ReadUserVersion(path), 1234);
}

TEST(Schema, LegacyTwoViewGeometriesGetColmapsColumns) {
  const std::string path = JoinPaths(testing::CreateTestDir(), "legacy.db");
  {
    sqlite3* handle = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &handle), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(handle,
                           "CREATE TABLE two_view_geometries (pair_id INTEGER "
                           "PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols "
                           "INTEGER NOT NULL, data BLOB, config INTEGER NOT "
                           "NULL)",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(handle);
  }
  { Database database(path); }
  const auto schema = ReadSchema(path);
  std::vector<std::string> names;
  for (const auto& entry : schema.at("two_view_geometries").columns) {
    names.push_back(std::get<1>(entry));
  }
  EXPECT_EQ(names, (std::vector<std::string>{"pair_id", "rows", "cols", "data",
                                             "config", "F", "E", "H", "qvec",
                                             "tvec"}));
  // The file existed with a table: not ours to version.
  EXPECT_EQ(ReadUserVersion(path), 0);
}

}  // namespace
}  // namespace colmap_lidar
