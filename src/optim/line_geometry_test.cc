#include "src/optim/line_geometry.h"

#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

Vector6d RandomLine(std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(-5.0, 5.0);
  const Eigen::Vector3d a(uniform(*rng), uniform(*rng), uniform(*rng));
  const Eigen::Vector3d b(uniform(*rng), uniform(*rng), uniform(*rng));
  return PluckerFromPoints(a, b);
}

Camera MakePinhole() {
  return Camera::FromModelName("PINHOLE", 640, 480, {500, 510, 320, 240});
}

Camera MakeOpenCV() {
  return Camera::FromModelName("OPENCV", 640, 480,
                               {500, 510, 320, 240, -0.2, 0.05, 0.001, -0.002});
}

TEST(LineGeometry, PluckerOrthonormalRoundTrip) {
  std::mt19937 rng(1);
  for (int i = 0; i < 100; ++i) {
    const Vector6d plucker = NormalizePlucker(RandomLine(&rng));
    const Vector6d orthonormal = PluckerToOrthonormal(plucker);
    EXPECT_NEAR(orthonormal.head<4>().norm(), 1.0, 1e-12);
    EXPECT_NEAR(orthonormal.tail<2>().norm(), 1.0, 1e-12);
    EXPECT_GT(orthonormal[5], 0.0);
    const Vector6d back = OrthonormalToPlucker(orthonormal);
    EXPECT_LT((back - plucker).norm(), 1e-10) << back.transpose() << " vs "
                                              << plucker.transpose();
  }
}

TEST(LineGeometry, OrthonormalPluckerRoundTrip) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  for (int i = 0; i < 100; ++i) {
    Vector6d orthonormal;
    orthonormal.head<4>() = Eigen::Quaterniond::UnitRandom().coeffs();
    const double phi = angle(rng);
    orthonormal.tail<2>() << std::cos(phi), std::sin(phi);
    if (std::abs(orthonormal[5]) < 1e-3) continue;
    const Vector6d plucker = OrthonormalToPlucker(orthonormal);
    // Klein constraint and |d| = 1.
    EXPECT_NEAR(plucker.head<3>().dot(plucker.tail<3>()), 0.0, 1e-12);
    EXPECT_NEAR(plucker.head<3>().norm(), 1.0, 1e-12);
    // Back to orthonormal: the same line, possibly with U's columns
    // flipped, so compare the lines.
    const Vector6d again = OrthonormalToPlucker(PluckerToOrthonormal(plucker));
    EXPECT_LT((again - plucker).norm(), 1e-10);
    // Distance to the origin is |w1 / w2|.
    EXPECT_NEAR(plucker.tail<3>().norm(),
                std::abs(orthonormal[4] / orthonormal[5]), 1e-9);
  }
}

TEST(LineGeometry, LineThroughOrigin) {
  const Vector6d plucker =
      PluckerFromPoints(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 2));
  const Vector6d orthonormal = PluckerToOrthonormal(plucker);
  EXPECT_NEAR(orthonormal[4], 0.0, 1e-15);
  const Vector6d back = OrthonormalToPlucker(orthonormal);
  EXPECT_LT((back - Vector6d((Vector6d() << 0, 0, 1, 0, 0, 0).finished())).norm(),
            1e-12);
}

TEST(LineGeometry, NormalizeRejectsZeroDirection) {
  EXPECT_THROW(NormalizePlucker(Vector6d::Zero()), Error);
  Vector6d orthonormal;
  orthonormal << 0, 0, 0, 1, 1, 0;
  EXPECT_THROW(OrthonormalToPlucker(orthonormal), Error);
}

TEST(LineGeometry, TransformMatchesTransformedPoints) {
  std::mt19937 rng(3);
  const Rigid3d b_from_a(Eigen::Quaterniond::UnitRandom(),
                         Eigen::Vector3d(1.0, -2.0, 0.5));
  const Eigen::Vector3d p(0.3, 1.0, 4.0), q(-1.0, 2.0, 6.0);
  const Vector6d expected =
      NormalizePlucker(PluckerFromPoints(b_from_a * p, b_from_a * q));
  const Vector6d actual =
      NormalizePlucker(TransformPlucker(b_from_a, PluckerFromPoints(p, q)));
  EXPECT_LT((expected - actual).norm(), 1e-12);
}

TEST(LineGeometry, DistancesAndCoordinates) {
  // Line x = 1, z = 2 along y.
  const Vector6d line = PluckerFromPointAndDirection(Eigen::Vector3d(1, 5, 2),
                                                     Eigen::Vector3d(0, 3, 0));
  EXPECT_NEAR(PointToPluckerLineDistance(line, Eigen::Vector3d(4, 7, 6)), 5.0,
              1e-12);
  EXPECT_LT((PluckerClosestPointToOrigin(line) - Eigen::Vector3d(1, 0, 2)).norm(),
            1e-12);
  EXPECT_NEAR(PluckerLineCoordinate(line, Eigen::Vector3d(4, 7, 6)), 7.0, 1e-12);
  EXPECT_LT((PluckerPointAt(line, -2.0) - Eigen::Vector3d(1, -2, 2)).norm(),
            1e-12);
  // A ray from (0, 3, -10) towards +z meets the line's closest point at y=3.
  double coordinate = 0.0;
  ASSERT_TRUE(ClosestLineCoordinateToRay(line, Eigen::Vector3d(0, 3, -10),
                                         Eigen::Vector3d(0, 0, 1), &coordinate));
  EXPECT_NEAR(coordinate, 3.0, 1e-12);
  // Pointing away: behind the ray origin.
  EXPECT_FALSE(ClosestLineCoordinateToRay(line, Eigen::Vector3d(0, 3, -10),
                                          Eigen::Vector3d(0, 0, -1), &coordinate));
  // Parallel.
  EXPECT_FALSE(ClosestLineCoordinateToRay(line, Eigen::Vector3d(0, 3, -10),
                                          Eigen::Vector3d(0, 1, 0), &coordinate));
}

TEST(LineGeometry, ProjectionContainsProjectedPoints) {
  for (const Camera& camera : {MakePinhole(), MakeOpenCV()}) {
    const Eigen::Vector3d p(-0.5, 0.3, 4.0), q(0.7, -0.2, 6.0);
    const Eigen::Vector3d image_line =
        ProjectPluckerToImageLine(camera, PluckerFromPoints(p, q));
    for (const double t : {-0.5, 0.0, 0.3, 1.0, 1.5}) {
      const Eigen::Vector2d pixel = camera.ImgFromCam(p + t * (q - p));
      EXPECT_NEAR(ImageLinePointDistance(image_line, UndistortPixel(camera, pixel)),
                  0.0, 1e-6)
          << camera.ModelName() << " t=" << t;
    }
    // A point 3 pixels off the line (in undistorted pixels).
    const Eigen::Vector2d on_line =
        UndistortPixel(camera, camera.ImgFromCam(0.5 * (p + q)));
    const Eigen::Vector2d normal = image_line.head<2>().normalized();
    EXPECT_NEAR(ImageLinePointDistance(image_line, on_line + 3.0 * normal), 3.0,
                1e-9);
  }
  // Undistortion is the identity for pinhole models and not for OPENCV.
  const Eigen::Vector2d corner(20.0, 30.0);
  EXPECT_LT((UndistortPixel(MakePinhole(), corner) - corner).norm(), 1e-9);
  EXPECT_GT((UndistortPixel(MakeOpenCV(), corner) - corner).norm(), 1.0);
}

TEST(LineGeometry, ViewingPlanesIntersectInTheLine) {
  const Camera camera = MakePinhole();
  const Eigen::Vector3d p(-0.5, 0.3, 4.0), q(0.7, -0.2, 6.0);
  const Rigid3d cam1_from_world;
  const Rigid3d cam2_from_world(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY())),
      Eigen::Vector3d(-1.0, 0.2, 0.1));
  const Eigen::Vector4d plane1 = ViewingPlaneInWorld(
      camera, cam1_from_world, camera.ImgFromCam(cam1_from_world * p),
      camera.ImgFromCam(cam1_from_world * q));
  const Eigen::Vector4d plane2 = ViewingPlaneInWorld(
      camera, cam2_from_world, camera.ImgFromCam(cam2_from_world * p),
      camera.ImgFromCam(cam2_from_world * q));
  EXPECT_NEAR(plane1.head<3>().dot(p) + plane1[3], 0.0, 1e-9);
  EXPECT_NEAR(plane2.head<3>().dot(q) + plane2[3], 0.0, 1e-9);
  const Vector6d line = NormalizePlucker(IntersectPlanes(plane1, plane2));
  const Vector6d expected = NormalizePlucker(PluckerFromPoints(p, q));
  EXPECT_LT(std::min((line - expected).norm(), (line + expected).norm()), 1e-8);
}

}  // namespace
}  // namespace colmap_lidar
