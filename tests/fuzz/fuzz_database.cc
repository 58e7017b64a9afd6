// Rows of database.db as stock COLMAP or another tool may have left them:
// the blobs and shapes of the stock tables and of our ext_* tables (see
// fuzz_db_input.h for the encoding). A template database (one camera,
// images 1 and 2) is made once; each input inserts its rows inside a
// transaction, runs every reader and rolls back.
#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/database/line_tracks_table.h"
#include "colmap_ext/scene/camera.h"
#include "tests/fuzz/fuzz_db_input.h"
#include "tests/fuzz/fuzz_util.h"

using namespace colmap_lidar;
using fuzz::DbInputReader;

namespace {

Database* g_database = nullptr;

void BindBytes(SqliteStatement* statement, int index, DbInputReader* input) {
  std::string bytes;
  if (input->Bytes(&bytes)) {
    statement->BindBlob(index, bytes.data(), bytes.size());
  } else {
    statement->BindNull(index);
  }
}

void BindText(SqliteStatement* statement, int index, DbInputReader* input) {
  std::string text;
  if (input->Bytes(&text)) {
    statement->BindText(index, text);
  } else {
    statement->BindNull(index);
  }
}

void BindReal(SqliteStatement* statement, int index, DbInputReader* input,
              bool is_null) {
  const double value = input->Real();
  if (is_null) {
    statement->BindNull(index);
  } else {
    statement->BindDouble(index, value);
  }
}

// Inserts one row; a constraint violation throws colmap_lidar::Error, which
// ends the row (the rest of the input still goes to later rows).
void InsertRow(Database* db, DbInputReader* input) {
  const uint8_t table = input->Byte() % fuzz::kDbNumTables;
  switch (table) {
    case fuzz::kDbCameras: {
      SqliteStatement s = db->Prepare(
          "INSERT OR REPLACE INTO cameras VALUES (?, ?, ?, ?, ?, ?)");
      for (int i = 1; i <= 4; ++i) s.BindInt64(i, input->Int());
      BindBytes(&s, 5, input);
      s.BindInt64(6, input->Int());
      s.Execute();
      break;
    }
    case fuzz::kDbImages: {
      SqliteStatement s = db->Prepare(
          "INSERT OR REPLACE INTO images VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, "
          "?)");
      s.BindInt64(1, input->Int());
      BindText(&s, 2, input);
      s.BindInt64(3, input->Int());
      const uint8_t null_mask = input->Byte();
      for (int i = 0; i < 7; ++i) {
        BindReal(&s, 4 + i, input, (null_mask >> i) & 1);
      }
      s.Execute();
      break;
    }
    case fuzz::kDbKeypoints:
    case fuzz::kDbDescriptors:
    case fuzz::kDbMatches:
    case fuzz::kDbLineMatches: {
      const char* name = table == fuzz::kDbKeypoints     ? "keypoints"
                         : table == fuzz::kDbDescriptors ? "descriptors"
                         : table == fuzz::kDbMatches     ? "matches"
                                                         : "ext_line_matches";
      SqliteStatement s = db->Prepare(std::string("INSERT OR REPLACE INTO ") +
                                      name + " VALUES (?, ?, ?, ?)");
      for (int i = 1; i <= 3; ++i) s.BindInt64(i, input->Int());
      BindBytes(&s, 4, input);
      s.Execute();
      break;
    }
    case fuzz::kDbTwoViewGeometries: {
      SqliteStatement s = db->Prepare(
          "INSERT OR REPLACE INTO two_view_geometries VALUES (?, ?, ?, ?, ?, "
          "?, ?, ?, ?, ?)");
      for (int i = 1; i <= 3; ++i) s.BindInt64(i, input->Int());
      BindBytes(&s, 4, input);
      s.BindInt64(5, input->Int());
      for (int i = 6; i <= 10; ++i) BindBytes(&s, i, input);
      s.Execute();
      break;
    }
    case fuzz::kDbLidarScans: {
      SqliteStatement s = db->Prepare(
          "INSERT OR REPLACE INTO ext_lidar_scans VALUES (?, ?, ?, ?)");
      s.BindInt64(1, input->Int());
      BindText(&s, 2, input);
      s.BindInt64(3, input->Int());
      BindBytes(&s, 4, input);
      s.Execute();
      break;
    }
    case fuzz::kDbLineSegments: {
      SqliteStatement s = db->Prepare(
          "INSERT OR REPLACE INTO ext_line_segments VALUES (?, ?, ?, ?, ?, ?)");
      s.BindInt64(1, input->Int());
      s.BindInt64(2, input->Int());
      BindBytes(&s, 3, input);
      BindBytes(&s, 4, input);
      s.BindInt64(5, input->Int());
      BindBytes(&s, 6, input);
      s.Execute();
      break;
    }
    case fuzz::kDbLineTracks: {
      SqliteStatement track = db->Prepare(
          "INSERT OR REPLACE INTO ext_line_tracks VALUES (?, ?, ?)");
      const int64_t line3D_id = input->Int();
      track.BindInt64(1, line3D_id);
      BindBytes(&track, 2, input);
      BindBytes(&track, 3, input);
      track.Execute();
      SqliteStatement element = db->Prepare(
          "INSERT OR REPLACE INTO ext_line_track_elements VALUES (?, ?, ?)");
      element.BindInt64(1, line3D_id);
      element.BindInt64(2, input->Int());
      element.BindInt64(3, input->Int());
      element.Execute();
      break;
    }
  }
}

void ReadEverything(const Database& db) {
  fuzz::ExpectNoCrash([&] { db.ReadAllCameras(); });
  fuzz::ExpectNoCrash([&] { db.ReadAllImages(); });
  fuzz::ExpectNoCrash([&] { db.ReadImageWithName("a"); });
  fuzz::ExpectNoCrash([&] { db.NumKeypoints(); });
  fuzz::ExpectNoCrash([&] { db.NumMatches(); });
  fuzz::ExpectNoCrash([&] { db.NumInlierMatches(); });
  for (const image_t image_id : {1u, 2u}) {
    fuzz::ExpectNoCrash([&] { db.ReadImage(image_id); });
    fuzz::ExpectNoCrash([&] { db.ReadKeypoints(image_id); });
    fuzz::ExpectNoCrash([&] { db.ReadDescriptors(image_id); });
    fuzz::ExpectNoCrash([&] { db.ReadLidarScan(image_id); });
    fuzz::ExpectNoCrash([&] { ReadLineSegments(db, image_id); });
  }
  fuzz::ExpectNoCrash([&] { db.ReadMatches(1, 2); });
  fuzz::ExpectNoCrash([&] { db.ReadMatches(2, 1); });
  fuzz::ExpectNoCrash([&] { db.ReadAllMatches(); });
  fuzz::ExpectNoCrash([&] { db.ReadTwoViewGeometry(1, 2); });
  fuzz::ExpectNoCrash([&] { db.ReadTwoViewGeometry(2, 1); });
  fuzz::ExpectNoCrash([&] { db.ReadAllTwoViewGeometries(); });
  fuzz::ExpectNoCrash([&] { db.ReadAllLidarScans(); });
  fuzz::ExpectNoCrash([&] { ReadImageIdsWithLineSegments(db); });
  fuzz::ExpectNoCrash([&] { ReadLineMatches(db, 1, 2); });
  fuzz::ExpectNoCrash([&] { ReadLineMatches(db, 2, 1); });
  fuzz::ExpectNoCrash([&] { ReadAllLineMatches(db); });
  fuzz::ExpectNoCrash([&] { ReadLineTracks(db); });
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::InitFuzzTarget();
  g_database = new Database(fuzz::TempDir() + "/database.db");
  Camera camera = Camera::FromModelName("PINHOLE", 64, 48, {50, 50, 32, 24});
  camera.camera_id = 1;
  g_database->WriteCamera(camera);
  for (const image_t image_id : {1u, 2u}) {
    DatabaseImage image;
    image.image_id = image_id;
    image.name = image_id == 1 ? "a" : "b";
    image.camera_id = 1;
    g_database->WriteImage(image);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  DbInputReader input(data, size);
  DatabaseTransaction transaction(g_database);
  // A few rows at most, so that one input stays fast.
  for (int row = 0; row < 8 && !input.AtEnd(); ++row) {
    fuzz::ExpectNoCrash([&] { InsertRow(g_database, &input); });
  }
  ReadEverything(*g_database);
  // The transaction rolls back: the next input sees the template again.
  return 0;
}
