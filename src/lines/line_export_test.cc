#include "src/lines/line_export.h"

#include <gtest/gtest.h>

#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/string.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

TEST(LineExport, WorldFramePlyAndObj) {
  const std::string dir = testing::CreateTestDir();
  Database database(JoinPaths(dir, "database.db"));
  Camera camera = Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
  camera.camera_id = database.WriteCamera(camera);
  DatabaseImage db_image;
  db_image.name = "a.png";
  db_image.camera_id = camera.camera_id;
  db_image.image_id = database.WriteImage(db_image);
  DatabaseImage other = db_image;
  other.image_id = kInvalidImageId;
  other.name = "not_in_model.png";
  other.image_id = database.WriteImage(other);

  LineSegmentRecord record;
  record.start3D_in_cam = Eigen::Vector3d(0, 0, 5);
  record.end3D_in_cam = Eigen::Vector3d(1, 0, 5);
  WriteLineSegments(&database, db_image.image_id, {record});
  WriteLineSegments(&database, other.image_id, {record});

  Reconstruction model;
  model.cameras[camera.camera_id] = camera;
  Image image;
  image.image_id = 7;  // ids differ from the database: matched by name
  image.name = "a.png";
  image.camera_id = camera.camera_id;
  // The camera sits at (10, 0, 0) in the world, axes aligned.
  image.cam_from_world.translation = Eigen::Vector3d(-10, 0, 0);
  model.images.push_back(image);

  const std::string ply_path = JoinPaths(dir, "lines.ply");
  const LineExportSummary summary =
      ExportWorldLineSegments(database, model, ply_path);
  EXPECT_EQ(summary.num_images, 1);
  EXPECT_EQ(summary.num_images_missing, 1);
  EXPECT_EQ(summary.num_segments, 1);
  const PlyData ply = ReadPly(ply_path);
  const std::vector<Eigen::Vector3d> points = ply.Positions(ply_path);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0], Eigen::Vector3d(10, 0, 5));
  EXPECT_EQ(points[1], Eigen::Vector3d(11, 0, 5));
  EXPECT_NE(ReadTextFile(ply_path).find("element edge 1"), std::string::npos);

  const std::string obj_path = JoinPaths(dir, "lines.OBJ");
  ExportWorldLineSegments(database, model, obj_path);
  const std::string obj = ReadTextFile(obj_path);
  EXPECT_NE(obj.find("v 10 0 5 "), std::string::npos) << obj;
  EXPECT_NE(obj.find("v 11 0 5 "), std::string::npos) << obj;
  EXPECT_NE(obj.find("l 1 2\n"), std::string::npos) << obj;

  EXPECT_THROW(ExportWorldLineSegments(database, model,
                                       JoinPaths(dir, "lines.xyz")),
               Error);
}

}  // namespace
}  // namespace colmap_lidar
