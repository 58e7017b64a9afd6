// Database (database.h): the per-image feature blobs of the keypoints and
// descriptors tables, in COLMAP's shapes.
#include "colmap_ext/database/database.h"

namespace colmap_lidar {

void Database::WriteKeypoints(const image_t image_id,
                              const FeatureKeypointsBlob& keypoints) {
  THROW_CHECK(keypoints.cols() == 2 || keypoints.cols() == 4 ||
                  keypoints.cols() == 6 || keypoints.rows() == 0,
              "Keypoints of image " << image_id << " have " << keypoints.cols()
                                    << " columns; COLMAP reads 2, 4 or 6 ("
                                    << path_ << ")");
  SqliteStatement statement = Prepare(
      "INSERT OR REPLACE INTO keypoints (image_id, rows, cols, data) "
      "VALUES (?, ?, ?, ?)");
  statement.BindInt64(1, image_id);
  statement.BindInt64(2, keypoints.rows());
  statement.BindInt64(3, keypoints.rows() == 0 ? 6 : keypoints.cols());
  statement.BindBlobArray(4, keypoints.data(), keypoints.size());
  statement.Execute();
}

FeatureKeypointsBlob Database::ReadKeypoints(const image_t image_id) const {
  SqliteStatement statement =
      Prepare("SELECT rows, cols, data FROM keypoints WHERE image_id = ?");
  statement.BindInt64(1, image_id);
  if (!statement.Step()) {
    return FeatureKeypointsBlob(0, 6);
  }
  const int64_t rows = statement.ColumnInt64(0);
  const int64_t cols = statement.ColumnInt64(1);
  const std::string what = "keypoints of image " + std::to_string(image_id);
  THROW_CHECK(rows >= 0 && (cols == 2 || cols == 4 || cols == 6),
              "Bad shape " << rows << " x " << cols << " of " << what << " in "
                           << path_);
  // Compare the shape with the blob before allocating: a corrupt row count
  // must not size the matrix (ColumnBlobArray repeats the exact check).
  THROW_CHECK(static_cast<uint64_t>(rows) <=
                  statement.ColumnBytes(2) / (cols * sizeof(float)),
              "Blob of " << what << " in " << path_ << " has "
                         << statement.ColumnBytes(2) << " bytes, too few for "
                         << rows << " x " << cols);
  FeatureKeypointsBlob keypoints(rows, cols);
  statement.ColumnBlobArray(2, keypoints.size(), keypoints.data(), what);
  return keypoints;
}

void Database::WriteDescriptors(const image_t image_id,
                                const FeatureDescriptorsBlob& descriptors) {
  SqliteStatement statement = Prepare(
      "INSERT OR REPLACE INTO descriptors (image_id, rows, cols, data) "
      "VALUES (?, ?, ?, ?)");
  statement.BindInt64(1, image_id);
  statement.BindInt64(2, descriptors.rows());
  statement.BindInt64(3, descriptors.rows() == 0 ? 128 : descriptors.cols());
  statement.BindBlobArray(4, descriptors.data(), descriptors.size());
  statement.Execute();
}

FeatureDescriptorsBlob Database::ReadDescriptors(const image_t image_id) const {
  SqliteStatement statement =
      Prepare("SELECT rows, cols, data FROM descriptors WHERE image_id = ?");
  statement.BindInt64(1, image_id);
  if (!statement.Step()) {
    return FeatureDescriptorsBlob(0, 128);
  }
  const int64_t rows = statement.ColumnInt64(0);
  const int64_t cols = statement.ColumnInt64(1);
  const std::string what = "descriptors of image " + std::to_string(image_id);
  THROW_CHECK(rows >= 0 && cols >= 0, "Bad shape " << rows << " x " << cols
                                                   << " of " << what << " in "
                                                   << path_);
  // As for keypoints: check the shape against the blob before allocating.
  THROW_CHECK(cols == 0 || static_cast<uint64_t>(rows) <=
                               statement.ColumnBytes(2) /
                                   static_cast<uint64_t>(cols),
              "Blob of " << what << " in " << path_ << " has "
                         << statement.ColumnBytes(2) << " bytes, too few for "
                         << rows << " x " << cols);
  FeatureDescriptorsBlob descriptors(rows, cols);
  statement.ColumnBlobArray(2, descriptors.size(), descriptors.data(), what);
  return descriptors;
}

}  // namespace colmap_lidar
