#include "colmap_ext/database/database.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cstring>
#include <fstream>
#include <random>

#include "colmap_ext/database/schema.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

// An independent connection without foreign keys, to check what is really
// stored (bytes, NULLs) and to tamper with files.
class RawDb {
 public:
  explicit RawDb(const std::string& path) : path_(path) {
    EXPECT_EQ(
        sqlite3_open_v2(path.c_str(), &handle_, SQLITE_OPEN_READWRITE, nullptr),
        SQLITE_OK);
  }
  ~RawDb() { sqlite3_close_v2(handle_); }
  SqliteStatement Prepare(const std::string& sql) {
    return SqliteStatement(handle_, path_, sql);
  }
  // Raw bytes of a blob column of the first row of `sql`; "NULL" marker via
  // is_null.
  std::string Blob(const std::string& sql, bool* is_null = nullptr) {
    SqliteStatement statement = Prepare(sql);
    EXPECT_TRUE(statement.Step()) << sql;
    if (is_null != nullptr) {
      *is_null = statement.ColumnIsNull(0);
    }
    std::string bytes(statement.ColumnBytes(0), '\0');
    statement.ColumnBlobArray(0, bytes.size(), bytes.data(), sql);
    return bytes;
  }
  int64_t Int(const std::string& sql) {
    SqliteStatement statement = Prepare(sql);
    EXPECT_TRUE(statement.Step()) << sql;
    return statement.ColumnInt64(0);
  }
  void Exec(const std::string& sql) {
    ASSERT_EQ(sqlite3_exec(handle_, sql.c_str(), nullptr, nullptr, nullptr),
              SQLITE_OK)
        << sql << ": " << sqlite3_errmsg(handle_);
  }

 private:
  std::string path_;
  sqlite3* handle_ = nullptr;
};

template <typename T>
std::string Bytes(const T* data, size_t count) {
  return std::string(reinterpret_cast<const char*>(data), count * sizeof(T));
}

Camera MakePinhole(camera_t camera_id) {
  Camera camera;
  camera.camera_id = camera_id;
  camera.model_id = CameraModelId::kPinhole;
  camera.width = 1242;
  camera.height = 375;
  camera.params = {721.5377, 722.25, 609.5593, 172.854};
  camera.has_prior_focal_length = true;
  return camera;
}

std::string NewDbPath() {
  return JoinPaths(testing::CreateTestDir(), "database.db");
}

// Expects a colmap_lidar::Error whose message contains `needle`.
template <typename Fn>
void ExpectErrorContaining(Fn&& fn, const std::string& needle) {
  try {
    fn();
    ADD_FAILURE() << "No exception, expected one naming " << needle;
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(needle), std::string::npos)
        << error.what();
  }
}

TEST(Database, PairIdMatchesColmapFormula) {
  EXPECT_EQ(Database::ImagePairToPairId(1, 2), 2147483647ull + 2);
  EXPECT_EQ(Database::ImagePairToPairId(2, 1), 2147483647ull + 2);
  EXPECT_EQ(Database::ImagePairToPairId(7, 124), 7ull * 2147483647ull + 124);
  EXPECT_EQ(Database::ImagePairToPairId(0, 0), 0u);
  const image_t big = 2147483646;
  const image_pair_t largest = Database::ImagePairToPairId(big, big - 1);
  EXPECT_EQ(largest, uint64_t(big - 1) * 2147483647ull + big);
  EXPECT_LE(largest, uint64_t(std::numeric_limits<int64_t>::max()));
  for (const auto& [a, b] : std::vector<std::pair<image_t, image_t>>{
           {1, 2}, {20, 7}, {0, 5}, {big - 1, big}, {3, 3}}) {
    const auto decoded =
        Database::PairIdToImagePair(Database::ImagePairToPairId(a, b));
    EXPECT_EQ(decoded.first, std::min(a, b));
    EXPECT_EQ(decoded.second, std::max(a, b));
  }
  EXPECT_THROW(Database::ImagePairToPairId(2147483647u, 1), Error);
}

TEST(Database, CamerasRoundTripWithBytes) {
  const std::string path = NewDbPath();
  Camera opencv;
  opencv.model_id = CameraModelId::kOpenCV;
  opencv.width = 640;
  opencv.height = 480;
  opencv.params = {500, 501, 320, 240, 0.1, -0.02, 0.001, 0.002};
  {
    Database database(path);
    EXPECT_EQ(database.WriteCamera(MakePinhole(5)), 5u);
    EXPECT_EQ(database.WriteCamera(opencv), 6u);  // AUTOINCREMENT after 5.
    EXPECT_EQ(database.NumCameras(), 2u);
    EXPECT_TRUE(database.ExistsCamera(6));
    EXPECT_FALSE(database.ExistsCamera(7));

    const std::optional<Camera> read = database.ReadCamera(6);
    ASSERT_TRUE(read.has_value());
    EXPECT_EQ(read->model_id, CameraModelId::kOpenCV);
    EXPECT_EQ(read->width, 640u);
    EXPECT_EQ(read->height, 480u);
    EXPECT_EQ(read->params, opencv.params);
    EXPECT_FALSE(read->has_prior_focal_length);
    EXPECT_FALSE(database.ReadCamera(99).has_value());

    const std::vector<Camera> all = database.ReadAllCameras();
    ASSERT_EQ(all.size(), 2u);
    EXPECT_EQ(all[0].camera_id, 5u);
    EXPECT_EQ(all[0].params, MakePinhole(5).params);
    EXPECT_TRUE(all[0].has_prior_focal_length);

    Camera updated = *read;
    updated.params[4] = 0.5;
    database.UpdateCamera(updated);
    EXPECT_EQ(database.ReadCamera(6)->params[4], 0.5);

    // A wrong parameter count names the camera.
    Camera bad = MakePinhole(9);
    bad.params.pop_back();
    ExpectErrorContaining([&] { database.WriteCamera(bad); }, "Camera 9");
    EXPECT_FALSE(database.ExistsCamera(9));
    ExpectErrorContaining([&] { database.WriteCamera(MakePinhole(5)); },
                          path);  // Duplicate id: SQLite's constraint error.
  }
  RawDb raw(path);
  const std::vector<double> params = MakePinhole(5).params;
  EXPECT_EQ(raw.Blob("SELECT params FROM cameras WHERE camera_id = 5"),
            Bytes(params.data(), params.size()));
  EXPECT_EQ(raw.Int("SELECT model FROM cameras WHERE camera_id = 5"), 1);
  EXPECT_EQ(
      raw.Int("SELECT prior_focal_length FROM cameras WHERE camera_id = 5"), 1);
  EXPECT_EQ(raw.Int("SELECT width FROM cameras WHERE camera_id = 5"), 1242);

  // A blob of the wrong length is refused on read, naming the camera.
  raw.Exec("UPDATE cameras SET params = zeroblob(24) WHERE camera_id = 5");
  Database database(path);
  ExpectErrorContaining([&] { database.ReadCamera(5); }, "camera 5");
}

TEST(Database, ImagesRoundTripWithPriors) {
  const std::string path = NewDbPath();
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized();
  const Eigen::Vector3d t(1.5, -2.25, 30.0);
  {
    Database database(path);
    database.WriteCamera(MakePinhole(1));
    DatabaseImage with_priors;
    with_priors.image_id = 1000;
    with_priors.name = "sub/0000000000.png";
    with_priors.camera_id = 1;
    with_priors.prior_q = q;
    with_priors.prior_t = t;
    EXPECT_EQ(database.WriteImage(with_priors), 1000u);
    DatabaseImage plain;
    plain.name = "0000000001.png";
    plain.camera_id = 1;
    EXPECT_EQ(database.WriteImage(plain), 1001u);
    EXPECT_EQ(database.NumImages(), 2u);

    // Foreign keys are on: an image of a missing camera is refused.
    DatabaseImage orphan = plain;
    orphan.name = "orphan.png";
    orphan.camera_id = 77;
    ExpectErrorContaining([&] { database.WriteImage(orphan); }, "FOREIGN KEY");
    // Names are unique.
    ExpectErrorContaining([&] { database.WriteImage(plain); }, path);

    EXPECT_TRUE(database.ExistsImageWithName("sub/0000000000.png"));
    EXPECT_FALSE(database.ExistsImageWithName("0000000000.png"));
    const std::optional<DatabaseImage> read =
        database.ReadImageWithName("sub/0000000000.png");
    ASSERT_TRUE(read.has_value());
    EXPECT_EQ(read->image_id, 1000u);
    EXPECT_EQ(read->camera_id, 1u);
    ASSERT_TRUE(read->prior_q.has_value());
    EXPECT_EQ(read->prior_q->coeffs(), q.coeffs());
    ASSERT_TRUE(read->prior_t.has_value());
    EXPECT_EQ(*read->prior_t, t);

    const std::optional<DatabaseImage> read_plain = database.ReadImage(1001);
    ASSERT_TRUE(read_plain.has_value());
    EXPECT_EQ(read_plain->name, "0000000001.png");
    EXPECT_FALSE(read_plain->prior_q.has_value());
    EXPECT_FALSE(read_plain->prior_t.has_value());
    EXPECT_FALSE(database.ReadImage(5).has_value());

    DatabaseImage updated = *read_plain;
    updated.prior_t = Eigen::Vector3d(4, 5, 6);
    database.UpdateImage(updated);
    const std::vector<DatabaseImage> all = database.ReadAllImages();
    ASSERT_EQ(all.size(), 2u);
    EXPECT_EQ(all[0].image_id, 1000u);
    EXPECT_EQ(all[1].image_id, 1001u);
    EXPECT_FALSE(all[1].prior_q.has_value());
    EXPECT_EQ(*all[1].prior_t, Eigen::Vector3d(4, 5, 6));
    DatabaseImage missing = updated;
    missing.image_id = 4;
    ExpectErrorContaining([&] { database.UpdateImage(missing); }, "image 4");
  }
  RawDb raw(path);
  EXPECT_EQ(raw.Int("SELECT count(*) FROM images WHERE image_id = 1001 AND "
                    "prior_qw IS NULL AND prior_qz IS NULL AND prior_tx = 4"),
            1);
  SqliteStatement statement = raw.Prepare(
      "SELECT prior_qw, prior_qx, prior_qy, prior_qz, prior_tx, prior_ty, "
      "prior_tz FROM images WHERE image_id = 1000");
  ASSERT_TRUE(statement.Step());
  EXPECT_EQ(statement.ColumnDouble(0), q.w());
  EXPECT_EQ(statement.ColumnDouble(1), q.x());
  EXPECT_EQ(statement.ColumnDouble(3), q.z());
  EXPECT_EQ(statement.ColumnDouble(4), 1.5);
  EXPECT_EQ(statement.ColumnDouble(6), 30.0);
}

TEST(Database, FeaturesRoundTripWithBytes) {
  const std::string path = NewDbPath();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coord(0.f, 1000.f);
  FeatureKeypointsBlob keypoints(50, 6);
  for (int i = 0; i < keypoints.size(); ++i) {
    keypoints.data()[i] = coord(rng);
  }
  FeatureKeypointsBlob keypoints2(3, 2);
  keypoints2 << 1.5f, 2.5f, 3.5f, 4.5f, 5.5f, 6.5f;
  FeatureDescriptorsBlob descriptors(50, 128);
  for (int i = 0; i < descriptors.size(); ++i) {
    descriptors.data()[i] = static_cast<uint8_t>(rng() % 256);
  }
  {
    Database database(path);
    database.WriteCamera(MakePinhole(1));
    for (image_t id : {3u, 8u}) {
      DatabaseImage image;
      image.image_id = id;
      image.name = "img" + std::to_string(id) + ".png";
      image.camera_id = 1;
      database.WriteImage(image);
    }
    database.WriteKeypoints(3, keypoints);
    database.WriteKeypoints(8, keypoints2);
    database.WriteDescriptors(3, descriptors);
    FeatureKeypointsBlob bad(2, 3);
    bad.setZero();
    ExpectErrorContaining([&] { database.WriteKeypoints(3, bad); }, "image 3");

    EXPECT_EQ(database.ReadKeypoints(3), keypoints);
    EXPECT_EQ(database.ReadKeypoints(8), keypoints2);
    EXPECT_EQ(database.ReadKeypoints(8).cols(), 2);
    EXPECT_EQ(database.ReadKeypoints(9).rows(), 0);
    EXPECT_EQ(database.ReadDescriptors(3), descriptors);
    EXPECT_EQ(database.NumKeypointsForImage(3), 50u);
    EXPECT_EQ(database.NumKeypointsForImage(9), 0u);
    EXPECT_EQ(database.NumKeypoints(), 53u);
    EXPECT_EQ(database.NumDescriptors(), 50u);
    EXPECT_EQ(database.NumDescriptorsForImage(3), 50u);
    EXPECT_TRUE(database.ExistsKeypoints(8));
    EXPECT_FALSE(database.ExistsDescriptors(8));
  }
  RawDb raw(path);
  EXPECT_EQ(raw.Blob("SELECT data FROM keypoints WHERE image_id = 3"),
            Bytes(keypoints.data(), keypoints.size()));
  EXPECT_EQ(raw.Blob("SELECT data FROM keypoints WHERE image_id = 3").size(),
            50u * 6 * 4);
  // Row-major: the second float is y of keypoint 0.
  const std::string kp2 =
      raw.Blob("SELECT data FROM keypoints WHERE image_id = 8");
  float second = 0;
  std::memcpy(&second, kp2.data() + 4, 4);
  EXPECT_EQ(second, 2.5f);
  EXPECT_EQ(raw.Int("SELECT cols FROM keypoints WHERE image_id = 8"), 2);
  EXPECT_EQ(raw.Blob("SELECT data FROM descriptors WHERE image_id = 3"),
            Bytes(descriptors.data(), descriptors.size()));
  EXPECT_EQ(raw.Int("SELECT cols FROM descriptors WHERE image_id = 3"), 128);
}

TEST(Database, MatchesAndGeometriesKeepColmapOrientation) {
  const std::string path = NewDbPath();
  FeatureMatchesBlob matches(3, 2);
  matches << 10, 20, 11, 21, 12, 22;  // Column 0 indexes image 9.
  TwoViewGeometry geometry;
  geometry.config = TwoViewGeometryConfig::kCalibrated;
  geometry.inlier_matches = matches.topRows(2);
  geometry.F << 1, 2, 3, 4, 5, 6, 7, 8, 9;
  geometry.E << 0, -1, 2, 1, 0, -3, -2, 3, 0;
  geometry.H << 2, 0.1, 3, 0, 1.5, -1, 0.001, 0, 1;
  const Eigen::Quaterniond q = Eigen::Quaterniond(
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  geometry.qvec << q.w(), q.x(), q.y(), q.z();
  geometry.tvec << 0.6, 0, 0.8;
  {
    Database database(path);
    // Called with (9, 4): stored as pair (4, 9) with swapped columns.
    database.WriteMatches(9, 4, matches);
    database.WriteTwoViewGeometry(9, 4, geometry);
    database.WriteMatches(1, 2, FeatureMatchesBlob(0, 2));
    EXPECT_THROW(database.WriteMatches(4, 9, matches), Error);  // Plain INSERT.

    EXPECT_TRUE(database.ExistsMatches(4, 9));
    EXPECT_TRUE(database.ExistsTwoViewGeometry(9, 4));
    EXPECT_FALSE(database.ExistsTwoViewGeometry(1, 2));
    EXPECT_EQ(database.ReadMatches(9, 4), matches);
    const FeatureMatchesBlob stored = database.ReadMatches(4, 9);
    EXPECT_EQ(stored.col(0), matches.col(1));
    EXPECT_EQ(stored.col(1), matches.col(0));
    EXPECT_EQ(database.NumMatches(), 3u);
    EXPECT_EQ(database.NumMatchedImagePairs(), 1u);
    EXPECT_EQ(database.NumInlierMatches(), 2u);
    EXPECT_EQ(database.NumVerifiedImagePairs(), 1u);

    const auto all = database.ReadAllMatches();
    ASSERT_EQ(all.size(), 2u);
    EXPECT_EQ(all[0].first, Database::ImagePairToPairId(1, 2));
    EXPECT_EQ(all[0].second.rows(), 0);
    EXPECT_EQ(all[1].first, Database::ImagePairToPairId(4, 9));

    // Same orientation as written.
    const std::optional<TwoViewGeometry> same =
        database.ReadTwoViewGeometry(9, 4);
    ASSERT_TRUE(same.has_value());
    EXPECT_EQ(same->config, TwoViewGeometryConfig::kCalibrated);
    EXPECT_EQ(same->inlier_matches, geometry.inlier_matches);
    EXPECT_TRUE(same->F.isApprox(geometry.F));
    EXPECT_TRUE(same->E.isApprox(geometry.E));
    EXPECT_TRUE(same->H.isApprox(geometry.H, 1e-12));
    EXPECT_TRUE(same->qvec.isApprox(geometry.qvec, 1e-12) ||
                same->qvec.isApprox(-geometry.qvec, 1e-12));
    EXPECT_TRUE(same->tvec.isApprox(geometry.tvec, 1e-12));
    // Stored orientation: F transposed, H inverted, pose inverted.
    const std::optional<TwoViewGeometry> stored_geometry =
        database.ReadTwoViewGeometry(4, 9);
    ASSERT_TRUE(stored_geometry.has_value());
    EXPECT_EQ(stored_geometry->F, geometry.F.transpose());
    EXPECT_TRUE((stored_geometry->H * geometry.H)
                    .isApprox(Eigen::Matrix3d::Identity(), 1e-12));
    const Rigid3d stored_pose(
        Eigen::Quaterniond(stored_geometry->qvec(0), stored_geometry->qvec(1),
                           stored_geometry->qvec(2), stored_geometry->qvec(3)),
        stored_geometry->tvec);
    const Rigid3d round =
        stored_pose * Rigid3d(q, geometry.tvec);  // Should be identity.
    EXPECT_LT(round.translation.norm(), 1e-12);
    EXPECT_NEAR(std::abs(round.rotation.w()), 1.0, 1e-12);
    EXPECT_EQ(database.ReadAllTwoViewGeometries().size(), 1u);
  }
  {
    RawDb raw(path);
    const image_pair_t pair_id = Database::ImagePairToPairId(4, 9);
    const std::string where = " WHERE pair_id = " + std::to_string(pair_id);
    std::vector<uint32_t> expected = {20, 10, 21, 11, 22, 12};
    EXPECT_EQ(raw.Blob("SELECT data FROM matches" + where),
              Bytes(expected.data(), expected.size()));
    EXPECT_EQ(raw.Int("SELECT cols FROM matches" + where), 2);
    expected.resize(4);
    EXPECT_EQ(raw.Blob("SELECT data FROM two_view_geometries" + where),
              Bytes(expected.data(), expected.size()));
    EXPECT_EQ(raw.Int("SELECT config FROM two_view_geometries" + where), 2);
    // F row-major in the stored (4 -> 9) orientation = geometry.F^T.
    const std::string f_bytes =
        raw.Blob("SELECT F FROM two_view_geometries" + where);
    ASSERT_EQ(f_bytes.size(), 72u);
    double f01 = 0;
    std::memcpy(&f01, f_bytes.data() + 8, 8);
    EXPECT_EQ(f01, geometry.F(1, 0));
    EXPECT_EQ(raw.Blob("SELECT qvec FROM two_view_geometries" + where).size(),
              32u);
    EXPECT_EQ(raw.Blob("SELECT tvec FROM two_view_geometries" + where).size(),
              24u);
    bool is_null = false;
    raw.Blob("SELECT data FROM matches WHERE pair_id = " +
                 std::to_string(Database::ImagePairToPairId(1, 2)),
             &is_null);
    EXPECT_TRUE(is_null);
    // An empty pair as colmap writes it: NULL blobs everywhere.
    raw.Exec("INSERT INTO two_view_geometries VALUES (" +
             std::to_string(Database::ImagePairToPairId(1, 2)) +
             ", 0, 2, NULL, 0, NULL, NULL, NULL, NULL, NULL)");
  }
  Database database(path);
  const std::optional<TwoViewGeometry> empty =
      database.ReadTwoViewGeometry(2, 1);
  ASSERT_TRUE(empty.has_value());
  EXPECT_EQ(empty->config, TwoViewGeometryConfig::kUndefined);
  EXPECT_EQ(empty->inlier_matches.rows(), 0);
  EXPECT_EQ(empty->F, Eigen::Matrix3d::Zero());
  EXPECT_EQ(empty->H, Eigen::Matrix3d::Zero());
  EXPECT_EQ(empty->qvec, Eigen::Vector4d::Zero());
  EXPECT_EQ(empty->tvec, Eigen::Vector3d::Zero());

  database.DeleteMatches(9, 4);
  EXPECT_FALSE(database.ExistsMatches(4, 9));
  database.DeleteTwoViewGeometry(4, 9);
  EXPECT_FALSE(database.ExistsTwoViewGeometry(4, 9));
  database.ClearMatches();
  database.ClearTwoViewGeometries();
  EXPECT_EQ(database.ReadAllMatches().size(), 0u);
  EXPECT_EQ(database.ReadAllTwoViewGeometries().size(), 0u);
}

TEST(Database, LidarScanFilePathIsRelativeToTheDatabasesFolder) {
  // As the importer writes it: beside database.db.
  EXPECT_EQ(LidarScanFilePath("/ws/database.db", "lidar/0001.bin"),
            "/ws/lidar/0001.bin");
  EXPECT_EQ(LidarScanFilePath("ws/database.db", "lidar/0001.bin"),
            "ws/lidar/0001.bin");
  // A database in the working directory: the path as stored.
  EXPECT_EQ(LidarScanFilePath("database.db", "lidar/0001.bin"),
            "lidar/0001.bin");
  EXPECT_EQ(LidarScanFilePath("/ws/sub/database.db", "../scans/./0001.pcd"),
            "/ws/scans/0001.pcd");
  // Absolute paths (scans kept outside the workspace) are not re-rooted.
  EXPECT_EQ(LidarScanFilePath("/ws/database.db", "/data/scans/0001.bin"),
            "/data/scans/0001.bin");
}

TEST(Database, LidarScansRoundTripAndCascade) {
  const std::string path = NewDbPath();
  LidarScanRecord scan;
  scan.image_id = 2;
  scan.path = "lidar/0000000002.ply";
  scan.num_points = 120345;
  scan.cam_from_lidar =
      Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(
                  -1.2, Eigen::Vector3d(0.2, 1, 0.1).normalized())),
              Eigen::Vector3d(0.06, -0.08, -0.27));
  {
    Database database(path);
    database.WriteCamera(MakePinhole(1));
    for (image_t id : {2u, 3u}) {
      DatabaseImage image;
      image.image_id = id;
      image.name = std::to_string(id) + ".png";
      image.camera_id = 1;
      database.WriteImage(image);
    }
    database.WriteLidarScan(scan);
    LidarScanRecord other = scan;
    other.image_id = 3;
    other.num_points = 1;
    database.WriteLidarScan(other);
    other.num_points = 2;  // Insert or replace.
    database.WriteLidarScan(other);
    EXPECT_EQ(database.NumLidarScans(), 2u);
    EXPECT_EQ(database.ReadLidarScan(3)->num_points, 2u);
    // The image must exist (foreign key).
    other.image_id = 4;
    ExpectErrorContaining([&] { database.WriteLidarScan(other); }, path);

    const std::optional<LidarScanRecord> read = database.ReadLidarScan(2);
    ASSERT_TRUE(read.has_value());
    EXPECT_EQ(read->path, scan.path);
    EXPECT_EQ(read->num_points, scan.num_points);
    EXPECT_TRUE(read->cam_from_lidar.ToMatrix().isApprox(
        scan.cam_from_lidar.ToMatrix(), 1e-14));
    EXPECT_FALSE(database.ReadLidarScan(9).has_value());
    EXPECT_TRUE(database.ExistsLidarScan(3));
    const std::vector<LidarScanRecord> all = database.ReadAllLidarScans();
    ASSERT_EQ(all.size(), 2u);
    EXPECT_EQ(all[0].image_id, 2u);
    EXPECT_EQ(all[1].image_id, 3u);
    database.DeleteLidarScan(3);
    EXPECT_FALSE(database.ExistsLidarScan(3));
  }
  {
    RawDb raw(path);
    // 12 float64, row-major [R|t]: element 3 is t_x, element 4 is R(1,0).
    const std::string bytes = raw.Blob(
        "SELECT cam_from_lidar FROM ext_lidar_scans WHERE image_id = 2");
    ASSERT_EQ(bytes.size(), 96u);
    double values[12];
    std::memcpy(values, bytes.data(), 96);
    const Eigen::Matrix3x4d matrix = scan.cam_from_lidar.ToMatrix();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) {
        EXPECT_DOUBLE_EQ(values[r * 4 + c], matrix(r, c));
      }
    }
    EXPECT_EQ(values[3], 0.06);
    EXPECT_EQ(raw.Int("SELECT num_points FROM ext_lidar_scans"), 120345);
  }
  // Deleting the image deletes its scan (ON DELETE CASCADE, as colmap's
  // database_cleaner would).
  Database database(path);
  database.Execute("DELETE FROM images WHERE image_id = 2");
  EXPECT_EQ(database.NumLidarScans(), 0u);
}

TEST(Database, TransactionRollbackAndCommit) {
  const std::string path = NewDbPath();
  Database database(path);
  database.WriteCamera(MakePinhole(1));
  {
    DatabaseTransaction transaction(&database);
    database.WriteCamera(MakePinhole(2));
    DatabaseImage image;
    image.name = "a.png";
    image.camera_id = 2;
    database.WriteImage(image);
    EXPECT_EQ(database.NumCameras(), 2u);
    // No Commit(): rolled back.
  }
  EXPECT_EQ(database.NumCameras(), 1u);
  EXPECT_EQ(database.NumImages(), 0u);
  EXPECT_FALSE(database.ExistsImageWithName("a.png"));
  // An exception inside the scope rolls back too.
  try {
    DatabaseTransaction transaction(&database);
    database.WriteCamera(MakePinhole(3));
    database.WriteCamera(MakePinhole(1));  // Duplicate: throws.
    transaction.Commit();
  } catch (const Error&) {
  }
  EXPECT_FALSE(database.ExistsCamera(3));
  {
    DatabaseTransaction outer(&database);
    database.WriteCamera(MakePinhole(4));
    {
      DatabaseTransaction inner(&database);
      database.WriteCamera(MakePinhole(5));
    }
    EXPECT_TRUE(database.ExistsCamera(4));
    EXPECT_FALSE(database.ExistsCamera(5));
    outer.Commit();
    EXPECT_THROW(outer.Commit(), Error);
  }
  database.Close();
  Database reopened(path);
  EXPECT_EQ(reopened.NumCameras(), 2u);
  EXPECT_TRUE(reopened.ExistsCamera(4));
}

TEST(Database, MoveTransfersConnection) {
  const std::string path = NewDbPath();
  Database database(path);
  database.WriteCamera(MakePinhole(1));
  Database moved = std::move(database);
  EXPECT_FALSE(database.IsOpen());  // NOLINT(bugprone-use-after-move)
  EXPECT_TRUE(moved.IsOpen());
  EXPECT_EQ(moved.NumCameras(), 1u);
  ExpectErrorContaining([&] { database.NumCameras(); }, "not open");
}

TEST(Database, RefusesCorruptFile) {
  const std::string path =
      JoinPaths(testing::CreateTestDir(), "random_bytes.db");
  {
    std::ofstream file(path, std::ios::binary);
    std::mt19937 rng(3);
    for (int i = 0; i < 8192; ++i) {
      file.put(static_cast<char>(rng() % 256));
    }
  }
  ExpectErrorContaining([&] { Database database(path); }, path);
  ExpectErrorContaining([&] { Database database(path); }, "not a database");
  // A missing folder.
  ExpectErrorContaining(
      [&] { Database database("/nonexistent/dir/database.db"); },
      "/nonexistent/dir/database.db");
}

TEST(Database, RefusesMissingColumnsAndNewerExtSchema) {
  const std::string dir = testing::CreateTestDir();
  const std::string no_columns = JoinPaths(dir, "no_columns.db");
  {
    sqlite3* handle = nullptr;
    ASSERT_EQ(sqlite3_open(no_columns.c_str(), &handle), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(handle,
                           "CREATE TABLE images (image_id INTEGER PRIMARY KEY, "
                           "name TEXT)",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(handle);
  }
  ExpectErrorContaining([&] { Database database(no_columns); }, no_columns);
  ExpectErrorContaining([&] { Database database(no_columns); }, "camera_id");

  const std::string newer = JoinPaths(dir, "newer.db");
  { Database database(newer); }
  {
    RawDb raw(newer);
    raw.Exec("UPDATE ext_schema SET value = '" +
             std::to_string(kExtSchemaVersion + 1) +
             "' WHERE key = 'ext_schema_version'");
  }
  ExpectErrorContaining([&] { Database database(newer); }, newer);
  ExpectErrorContaining([&] { Database database(newer); },
                        "ext schema version");
}

TEST(Database, FreshDatabaseVersions) {
  const std::string path = NewDbPath();
  Database database(path);
  EXPECT_EQ(database.UserVersion(), 3800);
  EXPECT_EQ(database.ExtSchemaVersion(), kExtSchemaVersion);
  // Reopening is idempotent.
  database.Close();
  database.Open(path);
  EXPECT_EQ(database.UserVersion(), 3800);
  EXPECT_EQ(database.NumCameras(), 0u);
  SqliteStatement statement = database.Prepare("PRAGMA journal_mode");
  ASSERT_TRUE(statement.Step());
  EXPECT_EQ(statement.ColumnText(0), "wal");
  SqliteStatement foreign_keys = database.Prepare("PRAGMA foreign_keys");
  ASSERT_TRUE(foreign_keys.Step());
  EXPECT_EQ(foreign_keys.ColumnInt64(0), 1);
}

}  // namespace
}  // namespace colmap_lidar
