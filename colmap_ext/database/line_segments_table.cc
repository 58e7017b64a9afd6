#include "colmap_ext/database/line_segments_table.h"

namespace colmap_lidar {

const TableSchema& LineSegmentsTableSchema() {
  static const TableSchema kSchema = {
      "ext_line_segments",
      "CREATE TABLE IF NOT EXISTS ext_line_segments ("
      "image_id    INTEGER NOT NULL"
      " REFERENCES images(image_id) ON DELETE CASCADE,"
      " idx         INTEGER NOT NULL,"
      " segment2D   BLOB    NOT NULL,"
      " segment3D   BLOB    NOT NULL,"
      " num_inliers INTEGER NOT NULL,"
      " descriptor  BLOB    NOT NULL,"
      " PRIMARY KEY (image_id, idx))",
      {"image_id", "idx", "segment2D", "segment3D", "num_inliers",
       "descriptor"}};
  return kSchema;
}

namespace {

// Database::Open creates the table (it is listed in ExtTableSchemas());
// writers also create it, harmlessly, so that a database opened before the
// table existed in its file can still take segments.
void EnsureTable(const Database& database) {
  database.Execute(LineSegmentsTableSchema().create_sql);
}

}  // namespace

void WriteLineSegments(Database* database, const image_t image_id,
                       const std::vector<LineSegmentRecord>& segments) {
  EnsureTable(*database);
  DatabaseTransaction transaction(database);
  {
    SqliteStatement remove =
        database->Prepare("DELETE FROM ext_line_segments WHERE image_id = ?");
    remove.BindInt64(1, image_id);
    remove.Execute();
  }
  SqliteStatement insert = database->Prepare(
      "INSERT INTO ext_line_segments (image_id, idx, segment2D, segment3D, "
      "num_inliers, descriptor) VALUES (?, ?, ?, ?, ?, ?)");
  for (size_t idx = 0; idx < segments.size(); ++idx) {
    const LineSegmentRecord& segment = segments[idx];
    const double segment2D[4] = {segment.start2D.x(), segment.start2D.y(),
                                 segment.end2D.x(), segment.end2D.y()};
    const double segment3D[6] = {
        segment.start3D_in_cam.x(), segment.start3D_in_cam.y(),
        segment.start3D_in_cam.z(), segment.end3D_in_cam.x(),
        segment.end3D_in_cam.y(),   segment.end3D_in_cam.z()};
    insert.BindInt64(1, image_id);
    insert.BindInt64(2, static_cast<int64_t>(idx));
    insert.BindBlobArray(3, segment2D, 4);
    insert.BindBlobArray(4, segment3D, 6);
    insert.BindInt64(5, segment.num_inliers);
    insert.BindBlobArray(6, segment.descriptor.data(), 32);
    insert.Execute();
    insert.Reset();
  }
  transaction.Commit();
}

std::vector<LineSegmentRecord> ReadLineSegments(const Database& database,
                                                const image_t image_id) {
  SqliteStatement select = database.Prepare(
      "SELECT idx, segment2D, segment3D, num_inliers, descriptor FROM "
      "ext_line_segments WHERE image_id = ? ORDER BY idx");
  select.BindInt64(1, image_id);
  std::vector<LineSegmentRecord> segments;
  const std::string what =
      "ext_line_segments of image " + std::to_string(image_id);
  while (select.Step()) {
    THROW_CHECK(select.ColumnInt64(0) == static_cast<int64_t>(segments.size()),
                what << " in " << database.path() << ": idx "
                     << select.ColumnInt64(0) << " out of sequence");
    LineSegmentRecord segment;
    double segment2D[4];
    double segment3D[6];
    select.ColumnBlobArray(1, 4, segment2D, "segment2D of " + what);
    select.ColumnBlobArray(2, 6, segment3D, "segment3D of " + what);
    segment.start2D = Eigen::Vector2d(segment2D[0], segment2D[1]);
    segment.end2D = Eigen::Vector2d(segment2D[2], segment2D[3]);
    segment.start3D_in_cam =
        Eigen::Vector3d(segment3D[0], segment3D[1], segment3D[2]);
    segment.end3D_in_cam =
        Eigen::Vector3d(segment3D[3], segment3D[4], segment3D[5]);
    segment.num_inliers = static_cast<uint32_t>(select.ColumnInt64(3));
    select.ColumnBlobArray(4, 32, segment.descriptor.data(),
                           "descriptor of " + what);
    segments.push_back(segment);
  }
  return segments;
}

void DeleteLineSegments(Database* database, const image_t image_id) {
  EnsureTable(*database);
  SqliteStatement remove =
      database->Prepare("DELETE FROM ext_line_segments WHERE image_id = ?");
  remove.BindInt64(1, image_id);
  remove.Execute();
}

size_t NumLineSegments(const Database& database) {
  SqliteStatement count =
      database.Prepare("SELECT count(*) FROM ext_line_segments");
  count.Step();
  return static_cast<size_t>(count.ColumnInt64(0));
}

size_t NumLineSegmentsForImage(const Database& database,
                               const image_t image_id) {
  SqliteStatement count = database.Prepare(
      "SELECT count(*) FROM ext_line_segments WHERE image_id = ?");
  count.BindInt64(1, image_id);
  count.Step();
  return static_cast<size_t>(count.ColumnInt64(0));
}

std::vector<image_t> ReadImageIdsWithLineSegments(const Database& database) {
  SqliteStatement select = database.Prepare(
      "SELECT DISTINCT image_id FROM ext_line_segments ORDER BY image_id");
  std::vector<image_t> image_ids;
  while (select.Step()) {
    image_ids.push_back(static_cast<image_t>(select.ColumnInt64(0)));
  }
  return image_ids;
}

const LineSegmentRecord& LineSegmentCache::Segment(image_t image_id,
                                                   uint32_t idx,
                                                   line3D_t line3D_id) {
  auto it = segments_.find(image_id);
  if (it == segments_.end()) {
    it = segments_.emplace(image_id, ReadLineSegments(database_, image_id))
             .first;
  }
  THROW_CHECK(idx < it->second.size(),
              database_.path()
                  << ": line track " << line3D_id << " references segment "
                  << idx << " of image " << image_id << ", which has only "
                  << it->second.size() << " rows in ext_line_segments");
  return it->second[idx];
}

}  // namespace colmap_lidar
