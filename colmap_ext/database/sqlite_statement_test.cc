#include "colmap_ext/database/sqlite_statement.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

class SqliteStatementTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = JoinPaths(testing::CreateTestDir(), "statement.db");
    ASSERT_EQ(sqlite3_open(path_.c_str(), &handle_), SQLITE_OK);
    SqliteStatement(handle_, path_,
                    "CREATE TABLE t (id INTEGER PRIMARY KEY, x REAL, "
                    "s TEXT NOT NULL, b BLOB)")
        .Execute();
  }
  void TearDown() override { sqlite3_close_v2(handle_); }

  std::string path_;
  sqlite3* handle_ = nullptr;
};

TEST_F(SqliteStatementTest, BindsAndReadsEveryType) {
  const std::vector<int16_t> blob = {1, -2, 300};
  {
    SqliteStatement insert(handle_, path_,
                           "INSERT INTO t (id, x, s, b) VALUES (?, ?, ?, ?)");
    insert.BindInt64(1, int64_t(1) << 40);
    insert.BindDouble(2, 0.125);
    insert.BindText(3, std::string("a\0b", 3));
    insert.BindBlobArray(4, blob.data(), blob.size());
    insert.Execute();
    insert.Reset();
    insert.BindInt64(1, 2);
    insert.BindNull(2);
    insert.BindText(3, "");
    insert.BindBlob(4, nullptr, 0);
    insert.Execute();
  }
  SqliteStatement select(handle_, path_,
                         "SELECT id, x, s, b FROM t ORDER BY id DESC");
  ASSERT_TRUE(select.Step());
  EXPECT_EQ(select.ColumnInt64(0), int64_t(1) << 40);
  EXPECT_EQ(select.ColumnDouble(1), 0.125);
  EXPECT_EQ(select.ColumnText(2), std::string("a\0b", 3));
  EXPECT_EQ(select.ColumnBytes(3), 6u);
  std::vector<int16_t> read(3);
  select.ColumnBlobArray(3, 3, read.data(), "b");
  EXPECT_EQ(read, blob);
  // A wrong element count names the blob and the file.
  try {
    select.ColumnBlobArray(3, 2, read.data(), "blob b");
    ADD_FAILURE() << "No exception";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("blob b"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find(path_), std::string::npos);
  }
  ASSERT_TRUE(select.Step());
  EXPECT_TRUE(select.ColumnIsNull(1));
  EXPECT_FALSE(select.ColumnIsNull(3));  // Zero-length, not NULL.
  EXPECT_EQ(select.ColumnBytes(3), 0u);
  EXPECT_FALSE(select.Step());
}

TEST_F(SqliteStatementTest, ErrorsNamePathSqlAndMessage) {
  try {
    SqliteStatement(handle_, path_, "SELECT nope FROM t");
    ADD_FAILURE() << "No exception";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(path_), std::string::npos) << message;
    EXPECT_NE(message.find("SELECT nope FROM t"), std::string::npos) << message;
    EXPECT_NE(message.find("no such column"), std::string::npos) << message;
  }
  SqliteStatement insert(handle_, path_, "INSERT INTO t (id, s) VALUES (1, ?)");
  insert.BindNull(1);
  try {
    insert.Execute();
    ADD_FAILURE() << "No exception";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("NOT NULL"), std::string::npos)
        << error.what();
  }
  EXPECT_THROW(insert.BindText(5, "x"), Error);  // No such parameter.
}

TEST_F(SqliteStatementTest, MoveKeepsStatement) {
  SqliteStatement first(handle_, path_, "SELECT 42");
  SqliteStatement second = std::move(first);
  ASSERT_TRUE(second.Step());
  EXPECT_EQ(second.ColumnInt64(0), 42);
}

}  // namespace
}  // namespace colmap_lidar
