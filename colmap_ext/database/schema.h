// The schema of a COLMAP 3.8 database.db plus our own ext_* tables.
//
// Stock tables: the CREATE statements have exactly the tokens and spacing
// COLMAP 3.8 issues (base/database.cc), so sqlite_master of a database we
// create is identical to one `colmap database_creator` creates
// (docs: colmap-formats.md §1.2).
//
// Our tables: every ext_* table is one entry of ExtTableSchemas() in
// schema.cc. To add a table (e.g. ext_line_segments), append an entry there
// with `CREATE TABLE IF NOT EXISTS` text and its required columns; Database
// creates missing tables on open and refuses a file that lacks a required
// column. Row IO for the new table goes in the adding module, written
// against Database::Prepare(). Bump kExtSchemaVersion only for a change that
// older code cannot read (a new column meaning, not a new table): databases
// with a newer version than ours are refused.
#pragma once

#include <string>
#include <vector>

namespace colmap_lidar {

// COLMAP 3.8's PRAGMA user_version, set only when we create a database.
constexpr int kColmapUserVersion = 3800;

// Version of our ext_* schema, stored as ext_schema("ext_schema_version").
constexpr int kExtSchemaVersion = 1;
constexpr const char* kExtSchemaVersionKey = "ext_schema_version";

struct TableSchema {
  std::string name;
  // CREATE TABLE IF NOT EXISTS ... ; may contain several statements (e.g. a
  // table and its index) separated by ';'.
  std::string create_sql;
  // Columns that must be present in an existing table of that name.
  std::vector<std::string> required_columns;
};

// COLMAP's six tables in COLMAP's creation order (cameras, images + its
// index_name, keypoints, descriptors, matches, two_view_geometries).
const std::vector<TableSchema>& StockTableSchemas();

// Columns that COLMAP adds to an old two_view_geometries table on open
// (each `name BLOB`); a database missing them is upgraded the same way.
const std::vector<std::string>& TwoViewGeometryLegacyColumns();

// ext_schema first, then every other ext_* table.
const std::vector<TableSchema>& ExtTableSchemas();

}  // namespace colmap_lidar
