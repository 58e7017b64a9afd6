// Database (database.h): the per-pair blobs of the matches and
// two_view_geometries tables. Pairs are stored in (smaller, larger) image id
// order and converted on read and write, as COLMAP does.
#include "colmap_ext/database/database.h"
#include "colmap_ext/database/database_internal.h"

namespace colmap_lidar {
namespace {

using database_internal::ToSqliteId;
using RowMajorMatrix3d = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

// COLMAP stores swapped pairs in (smaller, larger) orientation and converts
// on read and write (base/database.cc); this is that conversion.
FeatureMatchesBlob SwapMatchColumns(const FeatureMatchesBlob& matches) {
  FeatureMatchesBlob swapped(matches.rows(), 2);
  // Eigen's column block of an empty matrix offsets its null data pointer,
  // which is undefined behaviour (UBSan reports it).
  if (matches.rows() == 0) {
    return swapped;
  }
  swapped.col(0) = matches.col(1);
  swapped.col(1) = matches.col(0);
  return swapped;
}

TwoViewGeometry InvertTwoViewGeometry(const TwoViewGeometry& geometry) {
  TwoViewGeometry inverted;
  inverted.config = geometry.config;
  inverted.inlier_matches = SwapMatchColumns(geometry.inlier_matches);
  inverted.F = geometry.F.transpose();
  inverted.E = geometry.E.transpose();
  // An unset (zero) H stays zero instead of becoming inf.
  if (geometry.H.determinant() != 0.0) {
    inverted.H = geometry.H.inverse();
  }
  if (geometry.qvec.squaredNorm() > 0.0) {
    const Eigen::Quaterniond q2_from_1(geometry.qvec(0), geometry.qvec(1),
                                       geometry.qvec(2), geometry.qvec(3));
    const Rigid3d inverse =
        Rigid3d(q2_from_1.normalized(), geometry.tvec).Inverse();
    inverted.qvec << inverse.rotation.w(), inverse.rotation.x(),
        inverse.rotation.y(), inverse.rotation.z();
    inverted.tvec = inverse.translation;
  }
  return inverted;
}

void BindMatrix3d(SqliteStatement* statement, const int index,
                  const Eigen::Matrix3d& matrix) {
  const RowMajorMatrix3d row_major = matrix;
  statement->BindBlobArray(index, row_major.data(), 9);
}

// NULL and zero-length blobs read as zero, as COLMAP does.
template <int Rows, int Cols>
Eigen::Matrix<double, Rows, Cols> ReadFixedBlob(
    const SqliteStatement& statement, const int column,
    const std::string& what) {
  Eigen::Matrix<double, Rows, Cols, (Cols > 1 ? Eigen::RowMajor : 0)> matrix =
      decltype(matrix)::Zero();
  if (!statement.ColumnIsNull(column) && statement.ColumnBytes(column) > 0) {
    statement.ColumnBlobArray(column, Rows * Cols, matrix.data(), what);
  }
  return matrix;
}

FeatureMatchesBlob ReadMatchesBlob(const SqliteStatement& statement,
                                   const int rows_column,
                                   const std::string& what) {
  const int64_t rows = statement.ColumnInt64(rows_column);
  const int64_t cols = statement.ColumnInt64(rows_column + 1);
  THROW_CHECK(rows >= 0 && (cols == 2 || rows == 0),
              "Bad shape " << rows << " x " << cols << " of " << what);
  // Check the row count against the blob before allocating (a corrupt count
  // must not size the matrix); ColumnBlobArray repeats the exact check.
  THROW_CHECK(static_cast<uint64_t>(rows) <=
                  statement.ColumnBytes(rows_column + 2) /
                      (2 * sizeof(point2D_t)),
              "Blob of " << what << " has "
                         << statement.ColumnBytes(rows_column + 2)
                         << " bytes, too few for " << rows << " matches");
  FeatureMatchesBlob matches(rows, 2);
  statement.ColumnBlobArray(rows_column + 2, static_cast<size_t>(rows) * 2,
                            matches.data(), what);
  return matches;
}

std::string PairName(const image_t image_id1, const image_t image_id2) {
  return "image pair (" + std::to_string(image_id1) + ", " +
         std::to_string(image_id2) + ")";
}

constexpr const char* kSelectTwoViewGeometry =
    "SELECT pair_id, rows, cols, data, config, F, E, H, qvec, tvec "
    "FROM two_view_geometries";

TwoViewGeometry ReadTwoViewGeometryRow(const SqliteStatement& statement,
                                       const std::string& what) {
  TwoViewGeometry geometry;
  geometry.inlier_matches = ReadMatchesBlob(statement, 1, what);
  geometry.config =
      static_cast<TwoViewGeometryConfig>(statement.ColumnInt64(4));
  geometry.F = ReadFixedBlob<3, 3>(statement, 5, "F of " + what);
  geometry.E = ReadFixedBlob<3, 3>(statement, 6, "E of " + what);
  geometry.H = ReadFixedBlob<3, 3>(statement, 7, "H of " + what);
  geometry.qvec = ReadFixedBlob<4, 1>(statement, 8, "qvec of " + what);
  geometry.tvec = ReadFixedBlob<3, 1>(statement, 9, "tvec of " + what);
  return geometry;
}

}  // namespace

void Database::WriteMatches(const image_t image_id1, const image_t image_id2,
                            const FeatureMatchesBlob& matches) {
  const image_pair_t pair_id = ImagePairToPairId(image_id1, image_id2);
  SqliteStatement statement = Prepare(
      "INSERT INTO matches (pair_id, rows, cols, data) VALUES (?, ?, ?, ?)");
  statement.BindInt64(1, ToSqliteId(pair_id));
  statement.BindInt64(2, matches.rows());
  statement.BindInt64(3, 2);
  if (matches.rows() == 0) {
    statement.BindNull(4);
  } else if (SwapImagePair(image_id1, image_id2)) {
    const FeatureMatchesBlob swapped = SwapMatchColumns(matches);
    statement.BindBlobArray(4, swapped.data(), swapped.size());
  } else {
    statement.BindBlobArray(4, matches.data(), matches.size());
  }
  statement.Execute();
}

FeatureMatchesBlob Database::ReadMatches(const image_t image_id1,
                                         const image_t image_id2) const {
  SqliteStatement statement =
      Prepare("SELECT rows, cols, data FROM matches WHERE pair_id = ?");
  statement.BindInt64(1, ToSqliteId(ImagePairToPairId(image_id1, image_id2)));
  if (!statement.Step()) {
    return FeatureMatchesBlob(0, 2);
  }
  const FeatureMatchesBlob matches = ReadMatchesBlob(
      statement, 0,
      "matches of " + PairName(image_id1, image_id2) + " in " + path_);
  return SwapImagePair(image_id1, image_id2) ? SwapMatchColumns(matches)
                                             : matches;
}

std::vector<std::pair<image_pair_t, FeatureMatchesBlob>>
Database::ReadAllMatches() const {
  SqliteStatement statement =
      Prepare("SELECT pair_id, rows, cols, data FROM matches ORDER BY pair_id");
  std::vector<std::pair<image_pair_t, FeatureMatchesBlob>> all_matches;
  while (statement.Step()) {
    const image_pair_t pair_id =
        static_cast<image_pair_t>(statement.ColumnInt64(0));
    all_matches.emplace_back(
        pair_id, ReadMatchesBlob(statement, 1,
                                 "matches of pair_id " +
                                     std::to_string(pair_id) + " in " + path_));
  }
  return all_matches;
}

void Database::DeleteMatches(const image_t image_id1, const image_t image_id2) {
  SqliteStatement statement = Prepare("DELETE FROM matches WHERE pair_id = ?");
  statement.BindInt64(1, ToSqliteId(ImagePairToPairId(image_id1, image_id2)));
  statement.Execute();
}

void Database::ClearMatches() { Execute("DELETE FROM matches"); }

// ---------------------------------------------------------------------------
// Two-view geometries.

void Database::WriteTwoViewGeometry(const image_t image_id1,
                                    const image_t image_id2,
                                    const TwoViewGeometry& geometry) {
  const image_pair_t pair_id = ImagePairToPairId(image_id1, image_id2);
  const TwoViewGeometry stored = SwapImagePair(image_id1, image_id2)
                                     ? InvertTwoViewGeometry(geometry)
                                     : geometry;
  SqliteStatement statement = Prepare(
      "INSERT INTO two_view_geometries (pair_id, rows, cols, data, config, "
      "F, E, H, qvec, tvec) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  statement.BindInt64(1, ToSqliteId(pair_id));
  statement.BindInt64(2, stored.inlier_matches.rows());
  statement.BindInt64(3, 2);
  if (stored.inlier_matches.rows() == 0) {
    statement.BindNull(4);
  } else {
    statement.BindBlobArray(4, stored.inlier_matches.data(),
                            stored.inlier_matches.size());
  }
  statement.BindInt64(5, static_cast<int64_t>(stored.config));
  BindMatrix3d(&statement, 6, stored.F);
  BindMatrix3d(&statement, 7, stored.E);
  BindMatrix3d(&statement, 8, stored.H);
  statement.BindBlobArray(9, stored.qvec.data(), 4);
  statement.BindBlobArray(10, stored.tvec.data(), 3);
  statement.Execute();
}

std::optional<TwoViewGeometry> Database::ReadTwoViewGeometry(
    const image_t image_id1, const image_t image_id2) const {
  SqliteStatement statement =
      Prepare(std::string(kSelectTwoViewGeometry) + " WHERE pair_id = ?");
  statement.BindInt64(1, ToSqliteId(ImagePairToPairId(image_id1, image_id2)));
  if (!statement.Step()) {
    return std::nullopt;
  }
  const TwoViewGeometry geometry = ReadTwoViewGeometryRow(
      statement, "two-view geometry of " + PairName(image_id1, image_id2) +
                     " in " + path_);
  return SwapImagePair(image_id1, image_id2) ? InvertTwoViewGeometry(geometry)
                                             : geometry;
}

std::vector<std::pair<image_pair_t, TwoViewGeometry>>
Database::ReadAllTwoViewGeometries() const {
  SqliteStatement statement =
      Prepare(std::string(kSelectTwoViewGeometry) + " ORDER BY pair_id");
  std::vector<std::pair<image_pair_t, TwoViewGeometry>> geometries;
  while (statement.Step()) {
    const image_pair_t pair_id =
        static_cast<image_pair_t>(statement.ColumnInt64(0));
    geometries.emplace_back(
        pair_id, ReadTwoViewGeometryRow(
                     statement, "two-view geometry of pair_id " +
                                    std::to_string(pair_id) + " in " + path_));
  }
  return geometries;
}

void Database::DeleteTwoViewGeometry(const image_t image_id1,
                                     const image_t image_id2) {
  SqliteStatement statement =
      Prepare("DELETE FROM two_view_geometries WHERE pair_id = ?");
  statement.BindInt64(1, ToSqliteId(ImagePairToPairId(image_id1, image_id2)));
  statement.Execute();
}

void Database::ClearTwoViewGeometries() {
  Execute("DELETE FROM two_view_geometries");
}

}  // namespace colmap_lidar
