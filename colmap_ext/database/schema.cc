#include "colmap_ext/database/schema.h"

#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/database/line_tracks_table.h"

namespace colmap_lidar {

// The spacing inside the parentheses reproduces COLMAP 3.8's string
// literals, which SQLite keeps verbatim in sqlite_master (minus
// "IF NOT EXISTS").
const std::vector<TableSchema>& StockTableSchemas() {
  static const std::vector<TableSchema> kSchemas = {
      {"cameras",
       "CREATE TABLE IF NOT EXISTS cameras   ("
       "camera_id            INTEGER  PRIMARY KEY AUTOINCREMENT  NOT NULL,"
       "    model                INTEGER                             NOT NULL,"
       "    width                INTEGER                             NOT NULL,"
       "    height               INTEGER                             NOT NULL,"
       "    params               BLOB,"
       "    prior_focal_length   INTEGER                             NOT NULL)",
       {"camera_id", "model", "width", "height", "params",
        "prior_focal_length"}},
      {"images",
       "CREATE TABLE IF NOT EXISTS images   ("
       "image_id   INTEGER  PRIMARY KEY AUTOINCREMENT  NOT NULL,"
       "    name       TEXT                                NOT NULL UNIQUE,"
       "    camera_id  INTEGER                             NOT NULL,"
       "    prior_qw   REAL,"
       "    prior_qx   REAL,"
       "    prior_qy   REAL,"
       "    prior_qz   REAL,"
       "    prior_tx   REAL,"
       "    prior_ty   REAL,"
       "    prior_tz   REAL,"
       "CONSTRAINT image_id_check CHECK(image_id >= 0 and image_id < "
       "2147483647),"
       "FOREIGN KEY(camera_id) REFERENCES cameras(camera_id));"
       "CREATE UNIQUE INDEX IF NOT EXISTS index_name ON images(name);",
       {"image_id", "name", "camera_id", "prior_qw", "prior_qx", "prior_qy",
        "prior_qz", "prior_tx", "prior_ty", "prior_tz"}},
      {"keypoints",
       "CREATE TABLE IF NOT EXISTS keypoints   ("
       "image_id  INTEGER  PRIMARY KEY  NOT NULL,"
       "    rows      INTEGER               NOT NULL,"
       "    cols      INTEGER               NOT NULL,"
       "    data      BLOB,"
       "FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE)",
       {"image_id", "rows", "cols", "data"}},
      {"descriptors",
       "CREATE TABLE IF NOT EXISTS descriptors   ("
       "image_id  INTEGER  PRIMARY KEY  NOT NULL,"
       "    rows      INTEGER               NOT NULL,"
       "    cols      INTEGER               NOT NULL,"
       "    data      BLOB,"
       "FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE)",
       {"image_id", "rows", "cols", "data"}},
      {"matches",
       "CREATE TABLE IF NOT EXISTS matches   ("
       "pair_id  INTEGER  PRIMARY KEY  NOT NULL,"
       "    rows     INTEGER               NOT NULL,"
       "    cols     INTEGER               NOT NULL,"
       "    data     BLOB)",
       {"pair_id", "rows", "cols", "data"}},
      {"two_view_geometries",
       "CREATE TABLE IF NOT EXISTS two_view_geometries   ("
       "pair_id  INTEGER  PRIMARY KEY  NOT NULL,"
       "    rows     INTEGER               NOT NULL,"
       "    cols     INTEGER               NOT NULL,"
       "    data     BLOB,"
       "    config   INTEGER               NOT NULL,"
       "    F        BLOB,"
       "    E        BLOB,"
       "    H        BLOB,"
       "    qvec     BLOB,"
       "    tvec     BLOB)",
       {"pair_id", "rows", "cols", "data", "config", "F", "E", "H", "qvec",
        "tvec"}},
  };
  return kSchemas;
}

const std::vector<std::string>& TwoViewGeometryLegacyColumns() {
  static const std::vector<std::string> kColumns = {"F", "E", "H", "qvec",
                                                    "tvec"};
  return kColumns;
}

// Foreign keys into COLMAP tables must cascade: COLMAP runs with
// foreign_keys=ON and aborts on a non-cascading reference when it deletes
// images (colmap-formats.md §1.7). A cascading one means
// `database_cleaner --type images` also empties the ext table, which is the
// wanted behaviour for per-image data.
const std::vector<TableSchema>& ExtTableSchemas() {
  static const std::vector<TableSchema> kSchemas = {
      {"ext_schema",
       "CREATE TABLE IF NOT EXISTS ext_schema ("
       "key   TEXT PRIMARY KEY NOT NULL,"
       " value TEXT NOT NULL)",
       {"key", "value"}},
      // One LIDAR scan per image. cam_from_lidar: 12 float64, row-major 3x4
      // [R|t] with p_cam = R * p_lidar + t.
      {"ext_lidar_scans",
       "CREATE TABLE IF NOT EXISTS ext_lidar_scans ("
       "image_id       INTEGER PRIMARY KEY NOT NULL"
       " REFERENCES images(image_id) ON DELETE CASCADE,"
       " path           TEXT    NOT NULL,"
       " num_points     INTEGER NOT NULL,"
       " cam_from_lidar BLOB    NOT NULL)",
       {"image_id", "path", "num_points", "cam_from_lidar"}},
      // Per image, the 3D line segments of src/lines
      // (line_segments_table.h).
      LineSegmentsTableSchema(),
      // Pairwise line matches and multi-view line tracks of src/matching
      // (line_tracks_table.h).
      LineMatchesTableSchema(),
      LineTracksTableSchema(),
      LineTrackElementsTableSchema(),
  };
  return kSchemas;
}

}  // namespace colmap_lidar
