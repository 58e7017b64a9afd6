// Database (database.h): rows of the images table, with the prior pose in
// the prior_q* / prior_t* columns (NULL when unknown).
#include "colmap_ext/database/database.h"

#include <sqlite3.h>

namespace colmap_lidar {
namespace {

// Column order: image_id, name, camera_id, prior_qw..qz, prior_tx..tz.
DatabaseImage ReadImageRow(const SqliteStatement& statement) {
  DatabaseImage image;
  image.image_id = static_cast<image_t>(statement.ColumnInt64(0));
  image.name = statement.ColumnText(1);
  image.camera_id = static_cast<camera_t>(statement.ColumnInt64(2));
  bool has_q = true;
  for (int i = 3; i < 7; ++i) {
    has_q = has_q && !statement.ColumnIsNull(i);
  }
  if (has_q) {
    image.prior_q = Eigen::Quaterniond(
        statement.ColumnDouble(3), statement.ColumnDouble(4),
        statement.ColumnDouble(5), statement.ColumnDouble(6));
  }
  bool has_t = true;
  for (int i = 7; i < 10; ++i) {
    has_t = has_t && !statement.ColumnIsNull(i);
  }
  if (has_t) {
    image.prior_t =
        Eigen::Vector3d(statement.ColumnDouble(7), statement.ColumnDouble(8),
                        statement.ColumnDouble(9));
  }
  return image;
}

// Binds name, camera_id and the seven prior columns from `first_index` on.
void BindImageColumns(SqliteStatement* statement, const int first_index,
                      const DatabaseImage& image) {
  statement->BindText(first_index, image.name);
  statement->BindInt64(first_index + 1, image.camera_id);
  for (int i = 0; i < 4; ++i) {
    if (image.prior_q) {
      const Eigen::Quaterniond& q = *image.prior_q;
      const double values[4] = {q.w(), q.x(), q.y(), q.z()};
      statement->BindDouble(first_index + 2 + i, values[i]);
    } else {
      statement->BindNull(first_index + 2 + i);
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (image.prior_t) {
      statement->BindDouble(first_index + 6 + i, (*image.prior_t)(i));
    } else {
      statement->BindNull(first_index + 6 + i);
    }
  }
}

constexpr const char* kSelectImage =
    "SELECT image_id, name, camera_id, prior_qw, prior_qx, prior_qy, "
    "prior_qz, prior_tx, prior_ty, prior_tz FROM images";

}  // namespace

image_t Database::WriteImage(const DatabaseImage& image) {
  THROW_CHECK(!image.name.empty(), "Image without a name for " << path_);
  SqliteStatement statement = Prepare(
      "INSERT INTO images (image_id, name, camera_id, prior_qw, prior_qx, "
      "prior_qy, prior_qz, prior_tx, prior_ty, prior_tz) "
      "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  if (image.image_id != kInvalidImageId) {
    statement.BindInt64(1, image.image_id);
  } else {
    statement.BindNull(1);
  }
  BindImageColumns(&statement, 2, image);
  statement.Execute();
  return static_cast<image_t>(sqlite3_last_insert_rowid(handle_));
}

void Database::UpdateImage(const DatabaseImage& image) {
  SqliteStatement statement = Prepare(
      "UPDATE images SET name = ?, camera_id = ?, prior_qw = ?, prior_qx = ?, "
      "prior_qy = ?, prior_qz = ?, prior_tx = ?, prior_ty = ?, prior_tz = ? "
      "WHERE image_id = ?");
  BindImageColumns(&statement, 1, image);
  statement.BindInt64(10, image.image_id);
  statement.Execute();
  THROW_CHECK(sqlite3_changes(handle_) == 1, "Cannot update image "
                                                 << image.image_id << " in "
                                                 << path_ << ": no such image");
}

std::optional<DatabaseImage> Database::ReadImage(const image_t image_id) const {
  SqliteStatement statement =
      Prepare(std::string(kSelectImage) + " WHERE image_id = ?");
  statement.BindInt64(1, image_id);
  if (!statement.Step()) {
    return std::nullopt;
  }
  return ReadImageRow(statement);
}

std::optional<DatabaseImage> Database::ReadImageWithName(
    const std::string& name) const {
  SqliteStatement statement =
      Prepare(std::string(kSelectImage) + " WHERE name = ?");
  statement.BindText(1, name);
  if (!statement.Step()) {
    return std::nullopt;
  }
  return ReadImageRow(statement);
}

std::vector<DatabaseImage> Database::ReadAllImages() const {
  SqliteStatement statement =
      Prepare(std::string(kSelectImage) + " ORDER BY image_id");
  std::vector<DatabaseImage> images;
  while (statement.Step()) {
    images.push_back(ReadImageRow(statement));
  }
  return images;
}

}  // namespace colmap_lidar
