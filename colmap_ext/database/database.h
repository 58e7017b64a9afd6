// Reader and writer of COLMAP 3.8's database.db (colmap-formats.md §1) plus
// our ext_* tables (schema.h). The file stays usable by the stock colmap
// binary: stock tables are created with COLMAP's exact statements, blobs have
// COLMAP's layouts, and PRAGMA user_version is only set (to 3800) on a
// database we create.
//
// Like COLMAP, the connection runs with journal_mode=WAL and
// foreign_keys=ON. A database file must not be open in colmap and here at
// the same time. All failures throw colmap_lidar::Error naming the database
// path and, for SQLite failures, SQLite's message.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "colmap_ext/database/sqlite_statement.h"
#include "colmap_ext/scene/camera.h"
#include "colmap_ext/scene/rigid3.h"
#include "colmap_ext/util/types.h"

struct sqlite3;

namespace colmap_lidar {

// Keypoints rows x {2, 4, 6}: (x, y), (x, y, scale, orientation) or
// (x, y, a11, a12, a21, a22), in pixels with the (0.5, 0.5) pixel-centre
// convention.
using FeatureKeypointsBlob =
    Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
// Descriptors rows x 128 (SIFT), one row per keypoint.
using FeatureDescriptorsBlob =
    Eigen::Matrix<uint8_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
// Matches rows x 2: keypoint index in the first image, in the second.
using FeatureMatchesBlob =
    Eigen::Matrix<point2D_t, Eigen::Dynamic, 2, Eigen::RowMajor>;

// A row of the images table.
struct DatabaseImage {
  image_t image_id = kInvalidImageId;
  // Path relative to the image folder, '/' separated, unique.
  std::string name;
  camera_t camera_id = kInvalidCameraId;
  // In this project: prior world-to-camera rotation (cam_from_world), stored
  // in prior_qw..qz. NULL columns when unknown.
  std::optional<Eigen::Quaterniond> prior_q;
  // In this project: prior camera position in the world (the projection
  // centre, not a translation), stored in prior_tx..tz. NULL when unknown.
  std::optional<Eigen::Vector3d> prior_t;
};

// two_view_geometries.config, as COLMAP's TwoViewGeometry::ConfigurationType.
enum class TwoViewGeometryConfig : int {
  kUndefined = 0,
  kDegenerate = 1,
  kCalibrated = 2,
  kUncalibrated = 3,
  kPlanar = 4,
  kPanoramic = 5,
  kPlanarOrPanoramic = 6,
  kWatermark = 7,
  kMultiple = 8,
};

// A row of two_view_geometries, oriented from image 1 to image 2 of the call
// that wrote or read it: x2^T F x1 = 0, x2 ~ H x1 and X2 = R(qvec) X1 + tvec.
struct TwoViewGeometry {
  TwoViewGeometryConfig config = TwoViewGeometryConfig::kUndefined;
  FeatureMatchesBlob inlier_matches;
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  // (w, x, y, z); all zero when COLMAP did not compute the relative pose.
  Eigen::Vector4d qvec = Eigen::Vector4d::Zero();
  Eigen::Vector3d tvec = Eigen::Vector3d::Zero();
};

// A row of ext_lidar_scans: the LIDAR scan taken with an image.
struct LidarScanRecord {
  image_t image_id = kInvalidImageId;
  // Where the scan's points are stored (as the importer wrote it).
  std::string path;
  uint64_t num_points = 0;
  // p_cam = cam_from_lidar * p_lidar.
  Rigid3d cam_from_lidar;
};

// The file that holds a scan record's points: `scan_path` (a record's
// path) itself when absolute, else relative to the folder of the database
// file `database_path` (the importer writes "lidar/<file>" beside
// database.db), lexically normalised. The one rule for every stage that
// reads a workspace's scans.
std::string LidarScanFilePath(const std::string& database_path,
                              const std::string& scan_path);

class Database {
 public:
  // A closed database; call Open().
  Database() = default;
  // Opens or creates `path` (see Open).
  explicit Database(const std::string& path);
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;
  // Moving transfers the connection; the source is left closed. Do not move
  // while a DatabaseTransaction refers to the database.
  Database(Database&& other) noexcept;
  Database& operator=(Database&& other) noexcept;

  // Opens or creates the database: creates missing stock tables (COLMAP's
  // statements), missing ext_* tables, sets user_version=3800 only when the
  // file had no tables before. Throws naming the path when the file is not
  // an SQLite database, a known table lacks a required column, or its
  // ext_schema_version is newer than kExtSchemaVersion.
  void Open(const std::string& path);
  void Close();
  bool IsOpen() const { return handle_ != nullptr; }
  const std::string& path() const { return path_; }

  // Low-level access for modules with their own ext_* tables.
  SqliteStatement Prepare(const std::string& sql) const;
  // Runs one or more statements that return no rows.
  void Execute(const std::string& sql) const;
  // PRAGMA user_version (COLMAP's schema version; 3800 for 3.8).
  int UserVersion() const;
  // The stored ext_schema_version.
  int ExtSchemaVersion() const;

  // pair_id = min * kMaxNumImages + max, as COLMAP 3.8. Ids must be
  // < kMaxNumImages.
  static image_pair_t ImagePairToPairId(image_t image_id1, image_t image_id2);
  // Inverse of ImagePairToPairId: (smaller id, larger id).
  static std::pair<image_t, image_t> PairIdToImagePair(image_pair_t pair_id);
  // True when the pair is stored in (image_id2, image_id1) order.
  static bool SwapImagePair(image_t image_id1, image_t image_id2) {
    return image_id1 > image_id2;
  }

  // ---- Existence and counts.
  bool ExistsCamera(camera_t camera_id) const;
  bool ExistsImage(image_t image_id) const;
  bool ExistsImageWithName(const std::string& name) const;
  bool ExistsKeypoints(image_t image_id) const;
  bool ExistsDescriptors(image_t image_id) const;
  bool ExistsMatches(image_t image_id1, image_t image_id2) const;
  bool ExistsTwoViewGeometry(image_t image_id1, image_t image_id2) const;
  bool ExistsLidarScan(image_t image_id) const;

  size_t NumCameras() const;
  size_t NumImages() const;
  // Sum of rows over all images.
  size_t NumKeypoints() const;
  size_t NumKeypointsForImage(image_t image_id) const;
  size_t NumDescriptors() const;
  size_t NumDescriptorsForImage(image_t image_id) const;
  // Sum of rows over all pairs.
  size_t NumMatches() const;
  size_t NumInlierMatches() const;
  // Pairs with at least one (inlier) match.
  size_t NumMatchedImagePairs() const;
  size_t NumVerifiedImagePairs() const;
  size_t NumLidarScans() const;

  // ---- cameras.
  // Writes a new camera: with camera.camera_id when it is not
  // kInvalidCameraId, otherwise with the next AUTOINCREMENT id. Returns the
  // id. Throws naming the camera when the parameter count does not match
  // the model.
  camera_t WriteCamera(const Camera& camera);
  void UpdateCamera(const Camera& camera);
  std::optional<Camera> ReadCamera(camera_t camera_id) const;
  std::vector<Camera> ReadAllCameras() const;

  // ---- images.
  // Like WriteCamera, with image.image_id or AUTOINCREMENT.
  image_t WriteImage(const DatabaseImage& image);
  // Rewrites name, camera_id and the prior columns of an existing image.
  void UpdateImage(const DatabaseImage& image);
  std::optional<DatabaseImage> ReadImage(image_t image_id) const;
  std::optional<DatabaseImage> ReadImageWithName(const std::string& name) const;
  std::vector<DatabaseImage> ReadAllImages() const;

  // ---- keypoints and descriptors (insert or replace).
  void WriteKeypoints(image_t image_id, const FeatureKeypointsBlob& keypoints);
  // Empty (0 rows) when the image has none.
  FeatureKeypointsBlob ReadKeypoints(image_t image_id) const;
  void WriteDescriptors(image_t image_id,
                        const FeatureDescriptorsBlob& descriptors);
  FeatureDescriptorsBlob ReadDescriptors(image_t image_id) const;

  // ---- matches. Column 0 of `matches` indexes keypoints of image_id1; the
  // row is stored with column 0 = smaller image id (columns are swapped when
  // image_id1 > image_id2). Plain INSERT as COLMAP: throws if the pair
  // exists; delete it first.
  void WriteMatches(image_t image_id1, image_t image_id2,
                    const FeatureMatchesBlob& matches);
  // In the (image_id1, image_id2) orientation; empty when none.
  FeatureMatchesBlob ReadMatches(image_t image_id1, image_t image_id2) const;
  // Every stored pair in stored orientation (pair id decodes to (a < b)).
  std::vector<std::pair<image_pair_t, FeatureMatchesBlob>> ReadAllMatches()
      const;
  void DeleteMatches(image_t image_id1, image_t image_id2);
  void ClearMatches();

  // ---- two_view_geometries. Same orientation rules as matches; when the
  // order is swapped F and E are transposed, H inverted and the pose
  // inverted, as COLMAP does.
  void WriteTwoViewGeometry(image_t image_id1, image_t image_id2,
                            const TwoViewGeometry& geometry);
  std::optional<TwoViewGeometry> ReadTwoViewGeometry(image_t image_id1,
                                                     image_t image_id2) const;
  std::vector<std::pair<image_pair_t, TwoViewGeometry>>
  ReadAllTwoViewGeometries() const;
  void DeleteTwoViewGeometry(image_t image_id1, image_t image_id2);
  void ClearTwoViewGeometries();

  // ---- ext_lidar_scans (insert or replace; the image must exist).
  void WriteLidarScan(const LidarScanRecord& scan);
  std::optional<LidarScanRecord> ReadLidarScan(image_t image_id) const;
  std::vector<LidarScanRecord> ReadAllLidarScans() const;
  void DeleteLidarScan(image_t image_id);

 private:
  friend class DatabaseTransaction;

  void CheckOpen() const;
  void CreateAndCheckSchema(bool is_new);
  std::vector<std::string> TableColumns(const std::string& table) const;
  size_t CountRows(const std::string& sql, int64_t id = -1) const;
  size_t SumRows(const std::string& table) const;

  sqlite3* handle_ = nullptr;
  std::string path_;
  // Names the savepoints of nested DatabaseTransactions.
  int next_savepoint_id_ = 0;
};

// A scoped transaction: begins on construction, rolls back on destruction
// unless Commit() was called. Transactions nest (SQLite savepoints): an
// inner rollback undoes only the inner changes; nothing is durable until the
// outermost one commits.
class DatabaseTransaction {
 public:
  explicit DatabaseTransaction(Database* database);
  ~DatabaseTransaction();
  DatabaseTransaction(const DatabaseTransaction&) = delete;
  DatabaseTransaction& operator=(const DatabaseTransaction&) = delete;

  void Commit();

 private:
  Database* database_;
  std::string savepoint_;
  bool finished_ = false;
};

}  // namespace colmap_lidar
