#include "colmap_ext/database/line_tracks_table.h"

#include <string>

namespace colmap_lidar {

const TableSchema& LineMatchesTableSchema() {
  static const TableSchema kSchema = {
      "ext_line_matches",
      "CREATE TABLE IF NOT EXISTS ext_line_matches ("
      "pair_id INTEGER PRIMARY KEY NOT NULL,"
      " rows    INTEGER NOT NULL,"
      " cols    INTEGER NOT NULL,"
      " data    BLOB)",
      {"pair_id", "rows", "cols", "data"}};
  return kSchema;
}

const TableSchema& LineTracksTableSchema() {
  static const TableSchema kSchema = {
      "ext_line_tracks",
      "CREATE TABLE IF NOT EXISTS ext_line_tracks ("
      "line3D_id INTEGER PRIMARY KEY NOT NULL,"
      " plucker   BLOB NOT NULL,"
      " segment3D BLOB NOT NULL)",
      {"line3D_id", "plucker", "segment3D"}};
  return kSchema;
}

const TableSchema& LineTrackElementsTableSchema() {
  static const TableSchema kSchema = {
      "ext_line_track_elements",
      "CREATE TABLE IF NOT EXISTS ext_line_track_elements ("
      "line3D_id INTEGER NOT NULL"
      " REFERENCES ext_line_tracks(line3D_id) ON DELETE CASCADE,"
      " image_id  INTEGER NOT NULL"
      " REFERENCES images(image_id) ON DELETE CASCADE,"
      " idx       INTEGER NOT NULL,"
      " PRIMARY KEY (line3D_id, image_id),"
      " UNIQUE (image_id, idx))",
      {"line3D_id", "image_id", "idx"}};
  return kSchema;
}

namespace {

// Database::Open creates the tables (they are listed in ExtTableSchemas());
// writers also create them, harmlessly, so that a database opened by an
// older build can still take matches and tracks.
void EnsureTables(const Database& database) {
  database.Execute(LineMatchesTableSchema().create_sql);
  database.Execute(LineTracksTableSchema().create_sql);
  database.Execute(LineTrackElementsTableSchema().create_sql);
}

LineMatchesBlob SwapColumns(const LineMatchesBlob& matches) {
  LineMatchesBlob swapped(matches.rows(), 2);
  // A column block of an empty matrix offsets a null pointer (undefined).
  if (matches.rows() == 0) {
    return swapped;
  }
  swapped.col(0) = matches.col(1);
  swapped.col(1) = matches.col(0);
  return swapped;
}

LineMatchesBlob ReadMatchesRow(const SqliteStatement& select,
                               const std::string& db_path,
                               image_pair_t pair_id) {
  const int64_t rows = select.ColumnInt64(1);
  const int64_t cols = select.ColumnInt64(2);
  const std::string what =
      "ext_line_matches of pair " + std::to_string(pair_id);
  THROW_CHECK(rows >= 0 && (cols == 2 || rows == 0),
              what << " in " << db_path << " has shape " << rows << " x "
                   << cols << ", expected N x 2");
  // Compare with the blob before allocating: a corrupt row count must not
  // size the matrix (ColumnBlobArray below repeats the exact check).
  constexpr size_t kRowBytes = 2 * sizeof(uint32_t);
  THROW_CHECK(static_cast<uint64_t>(rows) <= select.ColumnBytes(3) / kRowBytes,
              what << " in " << db_path << " claims " << rows
                   << " rows, its blob has " << select.ColumnBytes(3)
                   << " bytes");
  LineMatchesBlob matches(rows, 2);
  select.ColumnBlobArray(3, static_cast<size_t>(rows) * 2, matches.data(),
                         what);
  return matches;
}

}  // namespace

void WriteLineMatches(Database* database, const image_t image_id1,
                      const image_t image_id2, const LineMatchesBlob& matches) {
  THROW_CHECK(image_id1 != image_id2,
              "Line matches of image " << image_id1 << " with itself");
  EnsureTables(*database);
  const image_pair_t pair_id =
      Database::ImagePairToPairId(image_id1, image_id2);
  const LineMatchesBlob stored = Database::SwapImagePair(image_id1, image_id2)
                                     ? SwapColumns(matches)
                                     : matches;
  SqliteStatement insert = database->Prepare(
      "INSERT OR REPLACE INTO ext_line_matches (pair_id, rows, cols, data) "
      "VALUES (?, ?, ?, ?)");
  insert.BindInt64(1, static_cast<int64_t>(pair_id));
  insert.BindInt64(2, stored.rows());
  insert.BindInt64(3, 2);
  insert.BindBlobArray(4, stored.data(), static_cast<size_t>(stored.size()));
  insert.Execute();
}

LineMatchesBlob ReadLineMatches(const Database& database,
                                const image_t image_id1,
                                const image_t image_id2) {
  const image_pair_t pair_id =
      Database::ImagePairToPairId(image_id1, image_id2);
  SqliteStatement select = database.Prepare(
      "SELECT pair_id, rows, cols, data FROM ext_line_matches WHERE pair_id "
      "= ?");
  select.BindInt64(1, static_cast<int64_t>(pair_id));
  if (!select.Step()) {
    return LineMatchesBlob(0, 2);
  }
  const LineMatchesBlob stored =
      ReadMatchesRow(select, database.path(), pair_id);
  return Database::SwapImagePair(image_id1, image_id2) ? SwapColumns(stored)
                                                       : stored;
}

std::vector<std::pair<image_pair_t, LineMatchesBlob>> ReadAllLineMatches(
    const Database& database) {
  SqliteStatement select = database.Prepare(
      "SELECT pair_id, rows, cols, data FROM ext_line_matches ORDER BY "
      "pair_id");
  std::vector<std::pair<image_pair_t, LineMatchesBlob>> all_matches;
  while (select.Step()) {
    const auto pair_id = static_cast<image_pair_t>(select.ColumnInt64(0));
    all_matches.emplace_back(pair_id,
                             ReadMatchesRow(select, database.path(), pair_id));
  }
  return all_matches;
}

void ClearLineMatches(Database* database) {
  EnsureTables(*database);
  database->Execute("DELETE FROM ext_line_matches");
}

size_t NumLineMatches(const Database& database) {
  SqliteStatement count =
      database.Prepare("SELECT IFNULL(SUM(rows), 0) FROM ext_line_matches");
  count.Step();
  return static_cast<size_t>(count.ColumnInt64(0));
}

void WriteLineTracks(Database* database,
                     const std::vector<LineTrackRecord>& tracks) {
  EnsureTables(*database);
  DatabaseTransaction transaction(database);
  // Elements go with their tracks (ON DELETE CASCADE); delete them first
  // anyway so that the result does not depend on foreign_keys being on.
  database->Execute("DELETE FROM ext_line_track_elements");
  database->Execute("DELETE FROM ext_line_tracks");
  SqliteStatement insert_track = database->Prepare(
      "INSERT INTO ext_line_tracks (line3D_id, plucker, segment3D) VALUES "
      "(?, ?, ?)");
  SqliteStatement insert_element = database->Prepare(
      "INSERT INTO ext_line_track_elements (line3D_id, image_id, idx) VALUES "
      "(?, ?, ?)");
  for (const LineTrackRecord& track : tracks) {
    THROW_CHECK(track.line3D_id != kInvalidLine3DId &&
                    track.line3D_id <=
                        static_cast<line3D_t>(INT64_MAX),
                "Invalid line3D_id " << track.line3D_id << " written to "
                                     << database->path());
    const double segment3D[6] = {
        track.start_in_world.x(), track.start_in_world.y(),
        track.start_in_world.z(), track.end_in_world.x(),
        track.end_in_world.y(),   track.end_in_world.z()};
    insert_track.BindInt64(1, static_cast<int64_t>(track.line3D_id));
    insert_track.BindBlobArray(2, track.plucker.data(), 6);
    insert_track.BindBlobArray(3, segment3D, 6);
    insert_track.Execute();
    insert_track.Reset();
    for (const LineTrackElement& element : track.elements) {
      insert_element.BindInt64(1, static_cast<int64_t>(track.line3D_id));
      insert_element.BindInt64(2, element.image_id);
      insert_element.BindInt64(3, element.line2D_idx);
      try {
        insert_element.Execute();
      } catch (const Error& error) {
        THROW_ERROR("Line track " << track.line3D_id << ", element (image "
                                  << element.image_id << ", segment "
                                  << element.line2D_idx
                                  << "): " << error.what());
      }
      insert_element.Reset();
    }
  }
  transaction.Commit();
}

std::vector<LineTrackRecord> ReadLineTracks(const Database& database) {
  std::vector<LineTrackRecord> tracks;
  {
    SqliteStatement select = database.Prepare(
        "SELECT line3D_id, plucker, segment3D FROM ext_line_tracks ORDER BY "
        "line3D_id");
    while (select.Step()) {
      LineTrackRecord track;
      track.line3D_id = static_cast<line3D_t>(select.ColumnInt64(0));
      const std::string what =
          "ext_line_tracks row " + std::to_string(track.line3D_id);
      double segment3D[6];
      select.ColumnBlobArray(1, 6, track.plucker.data(), "plucker of " + what);
      select.ColumnBlobArray(2, 6, segment3D, "segment3D of " + what);
      track.start_in_world =
          Eigen::Vector3d(segment3D[0], segment3D[1], segment3D[2]);
      track.end_in_world =
          Eigen::Vector3d(segment3D[3], segment3D[4], segment3D[5]);
      tracks.push_back(std::move(track));
    }
  }
  SqliteStatement select = database.Prepare(
      "SELECT line3D_id, image_id, idx FROM ext_line_track_elements ORDER BY "
      "line3D_id, image_id");
  size_t track_pos = 0;
  while (select.Step()) {
    const auto line3D_id = static_cast<line3D_t>(select.ColumnInt64(0));
    // Both queries are ordered by line3D_id: advance in step.
    while (track_pos < tracks.size() &&
           tracks[track_pos].line3D_id < line3D_id) {
      ++track_pos;
    }
    THROW_CHECK(track_pos < tracks.size() &&
                    tracks[track_pos].line3D_id == line3D_id,
                "ext_line_track_elements in " << database.path()
                                              << " refers to missing track "
                                              << line3D_id);
    LineTrackElement element;
    element.image_id = static_cast<image_t>(select.ColumnInt64(1));
    element.line2D_idx = static_cast<uint32_t>(select.ColumnInt64(2));
    tracks[track_pos].elements.push_back(element);
  }
  return tracks;
}

void ClearLineTracks(Database* database) {
  EnsureTables(*database);
  DatabaseTransaction transaction(database);
  database->Execute("DELETE FROM ext_line_track_elements");
  database->Execute("DELETE FROM ext_line_tracks");
  transaction.Commit();
}

size_t NumLineTracks(const Database& database) {
  SqliteStatement count =
      database.Prepare("SELECT count(*) FROM ext_line_tracks");
  count.Step();
  return static_cast<size_t>(count.ColumnInt64(0));
}

}  // namespace colmap_lidar
