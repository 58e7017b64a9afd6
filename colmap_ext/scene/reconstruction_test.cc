#include "colmap_ext/scene/reconstruction.h"

#include <gtest/gtest.h>

namespace colmap_lidar {
namespace {

// Two images of one camera observing one 3D point and one 3D line.
Reconstruction TestReconstruction() {
  Reconstruction reconstruction;
  Camera camera =
      Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
  camera.camera_id = 3;
  reconstruction.cameras[3] = camera;
  for (const image_t image_id : {20u, 10u}) {
    Image image;
    image.image_id = image_id;
    image.name = "img_" + std::to_string(image_id) + ".png";
    image.camera_id = 3;
    image.points2D.resize(2);
    image.points2D[1].point3D_id = 5;
    reconstruction.images.push_back(image);
  }
  Point3D point3D;
  point3D.track = {{20, 1}, {10, 1}};
  reconstruction.points3D[5] = point3D;
  Line3D line3D;
  line3D.track = {{10, 0}};
  reconstruction.lines3D[1] = line3D;
  return reconstruction;
}

TEST(Reconstruction, Lookups) {
  Reconstruction reconstruction = TestReconstruction();
  ASSERT_NE(reconstruction.FindImage(10), nullptr);
  EXPECT_EQ(reconstruction.FindImage(10)->name, "img_10.png");
  EXPECT_EQ(reconstruction.FindImage(11), nullptr);
  EXPECT_EQ(reconstruction.FindImageByName("img_20.png")->image_id, 20u);
  EXPECT_EQ(reconstruction.FindImageByName("img_30.png"), nullptr);
  // File order, not id order.
  EXPECT_EQ(reconstruction.ImageIndex(20), 0);
  EXPECT_EQ(reconstruction.ImageIndex(10), 1);
  EXPECT_EQ(reconstruction.ImageIndex(30), -1);
  // Mutable lookup edits in place.
  reconstruction.FindImage(10)->name = "renamed.png";
  EXPECT_EQ(reconstruction.images[1].name, "renamed.png");
  const Reconstruction& const_ref = reconstruction;
  EXPECT_EQ(const_ref.FindImageByName("renamed.png"),
            &reconstruction.images[1]);
}

TEST(Reconstruction, WriteOrderFollowsFileOrderThenIds) {
  Reconstruction reconstruction = TestReconstruction();
  reconstruction.points3D[1];
  reconstruction.points3D[9];
  reconstruction.points3D[7];
  EXPECT_EQ(reconstruction.Point3DIdsInWriteOrder(),
            (std::vector<point3D_t>{1, 5, 7, 9}));
  // Stale ids (42) and duplicates are skipped; unlisted ids come after.
  reconstruction.point3D_file_order = {9, 42, 5, 9};
  EXPECT_EQ(reconstruction.Point3DIdsInWriteOrder(),
            (std::vector<point3D_t>{9, 5, 1, 7}));
  EXPECT_EQ(reconstruction.CameraIdsInWriteOrder(), (std::vector<camera_t>{3}));
}

TEST(Reconstruction, CheckConsistencyAcceptsAConsistentModel) {
  EXPECT_NO_THROW(TestReconstruction().CheckConsistency());
}

void ExpectInconsistent(const Reconstruction& reconstruction,
                        const std::string& expected_substring) {
  try {
    reconstruction.CheckConsistency();
    ADD_FAILURE() << "no error, expected: " << expected_substring;
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(expected_substring),
              std::string::npos)
        << error.what();
  }
}

TEST(Reconstruction, CheckConsistencyFindsBrokenReferences) {
  Reconstruction missing_camera = TestReconstruction();
  missing_camera.images[0].camera_id = 4;
  ExpectInconsistent(missing_camera, "missing camera 4");

  Reconstruction missing_image = TestReconstruction();
  missing_image.points3D[5].track.push_back({99, 0});
  ExpectInconsistent(missing_image, "missing image 99");

  Reconstruction bad_idx = TestReconstruction();
  bad_idx.points3D[5].track[0].point2D_idx = 2;
  ExpectInconsistent(bad_idx, "has only 2");

  Reconstruction missing_point = TestReconstruction();
  missing_point.images[1].points2D[0].point3D_id = 6;
  ExpectInconsistent(missing_point, "missing 3D point 6");

  Reconstruction no_back_reference = TestReconstruction();
  no_back_reference.images[1].points2D[1].point3D_id = kInvalidPoint3DId;
  ExpectInconsistent(no_back_reference, "refers to 3D point");

  Reconstruction duplicate = TestReconstruction();
  duplicate.images[1].image_id = 20;
  ExpectInconsistent(duplicate, "Duplicate image id 20");

  Reconstruction line_image = TestReconstruction();
  line_image.lines3D[1].track[0].image_id = 77;
  ExpectInconsistent(line_image, "missing image 77");
}

}  // namespace
}  // namespace colmap_lidar
