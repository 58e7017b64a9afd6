#include "src/mesh/crease_snapping.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// A crease along z from (0, 0, 0) to (0, 0, 1) whose faces leave it along +x
// (the plane y = 0) and +y (the plane x = 0).
MeshCrease ZCrease() {
  MeshCrease crease;
  crease.start = Eigen::Vector3d(0, 0, 0);
  crease.end = Eigen::Vector3d(0, 0, 1);
  crease.face_directions = {Eigen::Vector3d::UnitX(),
                            Eigen::Vector3d::UnitY()};
  return crease;
}

// Surface points on the two faces of ZCrease(), every 5 mm up to 0.3 m
// from the crease, over z in [0, 1].
std::vector<Eigen::Vector3d> WedgePoints() {
  std::vector<Eigen::Vector3d> points;
  for (double z = 0; z <= 1.0; z += 0.005) {
    for (double u = 0; u <= 0.3; u += 0.005) {
      points.emplace_back(u, 0, z);
      points.emplace_back(0, u, z);
    }
  }
  return points;
}

TEST(CreaseSnapping, MovesNearVerticesOntoTheWedge) {
  // s = 0.02 m: candidates within 0.1 m of the crease, moves <= 0.02 m.
  const double spacing = 0.02;
  TriangleMesh mesh;
  mesh.vertices = {
      {0.05, 0.004, 0.5},     // 0: on the x face, 4 mm off -> onto it
      {0.01, 0.012, 0.5},     // 1: cuts the corner, nearer the y face
      {-0.005, -0.004, 0.5},  // 2: outside the corner -> onto the crease
      {0.05, 0.05, 0.5},      // 3: 5 cm from both faces: other structure
      {0.05, 0.004, 1.2},     // 4: beyond the segment's end
      {0.3, 0.004, 0.5},      // 5: beyond the candidate radius
      {0.0, 0.0, 0.25},       // 6: on the crease already
  };
  mesh.faces = {{0, 1, 2}, {3, 4, 5}, {0, 5, 6}};
  const TriangleMesh before = mesh;
  const CreaseSnappingSummary summary =
      SnapMeshToCreases(CreaseSnappingOptions(), {ZCrease()}, WedgePoints(),
                        spacing, &mesh);
  EXPECT_TRUE(mesh.vertices[0].isApprox(Eigen::Vector3d(0.05, 0, 0.5)));
  EXPECT_TRUE(mesh.vertices[1].isApprox(Eigen::Vector3d(0, 0.012, 0.5)));
  EXPECT_TRUE(mesh.vertices[2].isApprox(Eigen::Vector3d(0, 0, 0.5)));
  for (const int v : {3, 4, 5}) {
    EXPECT_EQ(mesh.vertices[v], before.vertices[v]) << v;
  }
  EXPECT_EQ(mesh.vertices[6], before.vertices[6]);
  EXPECT_EQ(mesh.faces, before.faces);
  EXPECT_EQ(summary.num_creases, 1u);
  EXPECT_EQ(summary.num_vertices_moved, 3u);
  EXPECT_NEAR(summary.max_move_m, 0.01, 1e-12);
  EXPECT_NEAR(summary.median_move_m, std::hypot(0.005, 0.004), 1e-12);

  // A larger max_move_factor reaches vertex 3 (5 cm from both faces), but
  // no surface point lies within s of it: it stays, unless the local check
  // looks as far as the faces.
  CreaseSnappingOptions options;
  options.max_move_factor = 3.0;
  TriangleMesh far = before;
  EXPECT_EQ(SnapMeshToCreases(options, {ZCrease()}, WedgePoints(), spacing,
                              &far)
                .num_vertices_off_wedge,
            1u);
  EXPECT_EQ(far.vertices[3], before.vertices[3]);
  options.local_radius_factor = 3.0;
  far = before;
  SnapMeshToCreases(options, {ZCrease()}, WedgePoints(), spacing, &far);
  EXPECT_TRUE(far.vertices[3].isApprox(Eigen::Vector3d(0.05, 0, 0.5)) ||
              far.vertices[3].isApprox(Eigen::Vector3d(0, 0.05, 0.5)));
}

TEST(CreaseSnapping, VerticesWhereThePointsLeaveTheWedgeStay) {
  // Beyond x = 5 cm the x face carries a frame 1.5 cm proud of it (the
  // wedge, fitted over the whole support, does not know): a vertex on the
  // frame is within reach of the wedge (1.4 cm < s = 2 cm) but the points
  // around it lie 1.5 cm off the wedge, beyond the plane band (0.3 s).
  std::vector<Eigen::Vector3d> points;
  for (double z = 0; z <= 1.0; z += 0.005) {
    for (double u = 0; u <= 0.3; u += 0.005) {
      points.emplace_back(u, u < 0.05 ? 0.0 : 0.015, z);
      points.emplace_back(0, u, z);
    }
  }
  TriangleMesh mesh;
  mesh.vertices = {{0.02, 0.004, 0.5}, {0.08, 0.014, 0.5}};
  const CreaseSnappingSummary summary = SnapMeshToCreases(
      CreaseSnappingOptions(), {ZCrease()}, points, 0.02, &mesh);
  EXPECT_TRUE(mesh.vertices[0].isApprox(Eigen::Vector3d(0.02, 0, 0.5)));
  EXPECT_EQ(mesh.vertices[1], Eigen::Vector3d(0.08, 0.014, 0.5));
  EXPECT_EQ(summary.num_vertices_moved, 1u);
  EXPECT_EQ(summary.num_vertices_off_wedge, 1u);
}

TEST(CreaseSnapping, TheLocalCheckUsesTheValidationsPlaneBand) {
  // Surface points with 1 cm of noise across the faces (alternating +-1 cm):
  // their median distance to the wedge, 1 cm, exceeds 0.3 s (6 mm) but not
  // the band the line validation measured on them (2.5 sigma).
  std::vector<Eigen::Vector3d> points;
  double sign = 1;
  for (double z = 0; z <= 1.0; z += 0.005) {
    for (double u = 0.02; u <= 0.3; u += 0.005, sign = -sign) {
      points.emplace_back(u, 0.01 * sign, z);
      points.emplace_back(0.01 * sign, u, z);
    }
  }
  TriangleMesh mesh;
  mesh.vertices = {{0.05, 0.008, 0.5}};
  const TriangleMesh before = mesh;
  EXPECT_EQ(SnapMeshToCreases(CreaseSnappingOptions(), {ZCrease()}, points,
                              0.02, &mesh)
                .num_vertices_off_wedge,
            1u);
  EXPECT_EQ(mesh.vertices[0], before.vertices[0]);
  MeshCrease noisy = ZCrease();
  noisy.plane_band_m = 0.025;
  EXPECT_EQ(
      SnapMeshToCreases(CreaseSnappingOptions(), {noisy}, points, 0.02, &mesh)
          .num_vertices_moved,
      1u);
  EXPECT_TRUE(mesh.vertices[0].isApprox(Eigen::Vector3d(0.05, 0, 0.5)));
  // A negative band is refused.
  noisy.plane_band_m = -1;
  EXPECT_THROW(
      SnapMeshToCreases(CreaseSnappingOptions(), {noisy}, points, 0.02, &mesh),
      Error);
}

TEST(CreaseSnapping, AVertexNearTwoCreasesFollowsTheNearestWedge) {
  // A second crease 10 cm along x whose faces leave along -x and +y (the
  // two sides of a 10 cm wide recess): the vertex is 1.5 cm above the first
  // crease's x face and 1 cm beside the second one's y face; it goes to the
  // nearer.
  MeshCrease second = ZCrease();
  second.start.x() = 0.1;
  second.end.x() = 0.1;
  second.face_directions[0] = -Eigen::Vector3d::UnitX();
  TriangleMesh mesh;
  mesh.vertices = {{0.09, 0.015, 0.5}};
  SnapMeshToCreases(CreaseSnappingOptions(), {ZCrease(), second},
                    {{0.1, 0.015, 0.5}, {0.1, 0.02, 0.5}, {0.1, 0.01, 0.5}},
                    0.02, &mesh);
  EXPECT_TRUE(mesh.vertices[0].isApprox(Eigen::Vector3d(0.1, 0.015, 0.5)));
}

TEST(CreaseSnapping, NoCreasesOrEmptyMeshChangeNothing) {
  TriangleMesh mesh;
  mesh.vertices = {{0.05, 0.004, 0.5}};
  const CreaseSnappingSummary summary =
      SnapMeshToCreases(CreaseSnappingOptions(), {}, WedgePoints(), 0.02,
                        &mesh);
  EXPECT_EQ(summary.num_vertices_moved, 0u);
  EXPECT_EQ(mesh.vertices[0], Eigen::Vector3d(0.05, 0.004, 0.5));
  TriangleMesh empty;
  EXPECT_EQ(SnapMeshToCreases(CreaseSnappingOptions(), {ZCrease()},
                              WedgePoints(), 0.02, &empty)
                .num_vertices_moved,
            0u);
}

TEST(CreaseSnapping, OptionsAndInputAreChecked) {
  CreaseSnappingOptions options;
  EXPECT_TRUE(options.Check());
  options.radius_factor = 0;
  EXPECT_FALSE(options.Check());
  options = CreaseSnappingOptions();
  options.max_local_offset_factor = -1;
  EXPECT_FALSE(options.Check());
  options = CreaseSnappingOptions();
  options.min_local_points = 0;
  EXPECT_FALSE(options.Check());
  options = CreaseSnappingOptions();
  options.max_move_factor = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(options.Check());
  TriangleMesh mesh;
  mesh.vertices = {{0.05, 0.004, 0.5}};
  EXPECT_THROW(SnapMeshToCreases(options, {ZCrease()}, {}, 0.02, &mesh),
               Error);
  EXPECT_THROW(
      SnapMeshToCreases(CreaseSnappingOptions(), {ZCrease()}, {}, 0.0, &mesh),
      Error);
  MeshCrease bad = ZCrease();
  bad.face_directions[1] = Eigen::Vector3d(0, 1, 1);  // neither unit nor ⟂
  EXPECT_THROW(
      SnapMeshToCreases(CreaseSnappingOptions(), {bad}, {}, 0.02, &mesh),
      Error);
}

}  // namespace
}  // namespace colmap_lidar
