#include "src/synth/scene_mesh.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"
#include "src/synth/ray_tracer.h"
#include "src/synth/scene_presets.h"

namespace colmap_lidar {
namespace {

// Within face 1 of the edge, the unit direction pointing away from the
// edge: towards face 2's side for an inner corner, away from it for an
// outer one.
Eigen::Vector3d InFaceDirection(const CreaseEdge& edge, bool first) {
  const Eigen::Vector3d& n = first ? edge.normal1 : edge.normal2;
  const Eigen::Vector3d& other = first ? edge.normal2 : edge.normal1;
  const Eigen::Vector3d projected = other - other.dot(n) * n;
  return (edge.convex ? -1.0 : 1.0) * projected.normalized();
}

// True when, at fractions 0.25/0.5/0.75 along the edge, a ray cast from
// 3 cm in front of each face, 1 cm away from the edge within the face, hits
// that face head-on at 3 cm with the expected normal.
bool EdgeIsCrease(const RayTracer& tracer, const CreaseEdge& edge) {
  const double d = 0.03;
  const double s = 0.01;
  for (double fraction : {0.25, 0.5, 0.75}) {
    const Eigen::Vector3d p = edge.start + fraction * (edge.end - edge.start);
    for (bool first : {true, false}) {
      const Eigen::Vector3d& n = first ? edge.normal1 : edge.normal2;
      const Eigen::Vector3d origin = p + d * n + s * InFaceDirection(edge, first);
      const RayHit hit = tracer.Intersect(origin, -n);
      if (!hit.Valid() || std::abs(hit.distance - d) > 1e-4) return false;
      if (tracer.mesh().normals[hit.triangle].cast<double>().dot(n) < 0.999) {
        return false;
      }
    }
  }
  return true;
}

void CheckScene(const SynthScene& scene, size_t min_edges) {
  ASSERT_GE(scene.crease_edges.size(), min_edges);
  ASSERT_EQ(scene.mesh.materials.size(), scene.mesh.NumTriangles());
  ASSERT_EQ(scene.mesh.normals.size(), scene.mesh.NumTriangles());
  const RayTracer tracer(scene.mesh);
  int num_convex = 0;
  for (size_t i = 0; i < scene.crease_edges.size(); ++i) {
    const CreaseEdge& edge = scene.crease_edges[i];
    EXPECT_GE(edge.AngleDeg(), 20.0) << "edge " << i;
    EXPECT_TRUE(EdgeIsCrease(tracer, edge))
        << "edge " << i << " from " << edge.start.transpose() << " to "
        << edge.end.transpose() << " convex " << edge.convex;
    num_convex += edge.convex ? 1 : 0;
  }
  EXPECT_GT(num_convex, 0);
  EXPECT_LT(num_convex, static_cast<int>(scene.crease_edges.size()));
}

TEST(SceneMesh, QuadCreaseEdgesLieOnCreases) {
  CheckScene(BuildQuadScene(), 500);
}

TEST(SceneMesh, StreetCreaseEdgesLieOnCreases) {
  CheckScene(BuildStreetScene(), 500);
}

TEST(SceneMesh, CorridorCreaseEdgesLieOnCreases) {
  const SynthScene scene = BuildScene("corridor");
  EXPECT_EQ(scene.name, "corridor");
  CheckScene(scene, 100);
  // The walk stays in free space: from every waypoint at camera height,
  // the nearest wall across the corridor is at least 1 m away.
  const RayTracer tracer(scene.mesh);
  for (const Eigen::Vector2d& w : scene.path.waypoints) {
    const Eigen::Vector3d origin(w.x(), w.y(), scene.path.height_m);
    for (const double sign : {1.0, -1.0}) {
      const Eigen::Vector3d dir(0.0, sign, 0.0);
      const RayHit hit = tracer.Intersect(origin, dir);
      ASSERT_TRUE(hit.Valid());
      EXPECT_GT(hit.distance, 1.0);
      // Seen from inside free space, the wall faces the camera.
      EXPECT_LT(tracer.mesh().normals[hit.triangle].cast<double>().dot(dir),
                0.0);
    }
  }
}

TEST(SceneMesh, StreetBentCreaseEdgesIncludeTheKerbs) {
  const SynthScene scene = BuildScene("street_bent");
  EXPECT_EQ(scene.name, "street_bent");
  CheckScene(scene, 1000);
  // The kerbs: per side and leg a long convex lip on the pavement's top
  // (z = 0.13, between the up normal and a horizontal one) and a long
  // concave foot on the road (z = 0); at the bend a short vertical kerb
  // edge per side, convex inside the bend and concave outside.
  const double kerb_height = 0.13;
  int num_lips = 0;
  int num_feet = 0;
  int num_kerb_corners = 0;
  for (const CreaseEdge& edge : scene.crease_edges) {
    const double length = (edge.end - edge.start).norm();
    const bool horizontal_and_up =
        std::max(edge.normal1.z(), edge.normal2.z()) > 0.999 &&
        std::abs(std::min(edge.normal1.z(), edge.normal2.z())) < 1e-9;
    if (length > 20.0 && horizontal_and_up && edge.convex &&
        std::abs(edge.start.z() - kerb_height) < 1e-9 &&
        std::abs(edge.end.z() - kerb_height) < 1e-9) {
      ++num_lips;
    }
    if (length > 20.0 && horizontal_and_up && !edge.convex &&
        std::abs(edge.start.z()) < 1e-9 && std::abs(edge.end.z()) < 1e-9) {
      ++num_feet;
    }
    if (std::abs(length - kerb_height) < 1e-9 &&
        std::abs(edge.start.z()) < 1e-9 && edge.AngleDeg() > 20.0 &&
        edge.AngleDeg() < 35.0) {
      ++num_kerb_corners;
    }
  }
  EXPECT_EQ(num_lips, 4);
  EXPECT_EQ(num_feet, 4);
  EXPECT_EQ(num_kerb_corners, 2);

  // The window frames stand 7 cm proud of the left facade of leg 0 (the
  // plane y = 6 seen from the road): rays across the road at the height of
  // the ground-floor windows hit frames at y = 5.93, the wall at y = 6.
  const RayTracer tracer(scene.mesh);
  int num_frame_hits = 0;
  int num_wall_hits = 0;
  for (double x = -40.0; x < -5.0; x += 0.02) {
    const RayHit hit =
        tracer.Intersect({x, 0.0, kerb_height + 1.6}, {0.0, 1.0, 0.0});
    ASSERT_TRUE(hit.Valid());
    const Material material = scene.mesh.materials[hit.triangle];
    if (material == Material::kFrame && std::abs(hit.distance - 5.93) < 1e-4) {
      ++num_frame_hits;
    }
    if (material != Material::kFrame && std::abs(hit.distance - 6.0) < 1e-4) {
      ++num_wall_hits;
    }
  }
  EXPECT_GT(num_frame_hits, 50);
  EXPECT_GT(num_wall_hits, 500);
}

// Total length of a polyline in the ground plane.
double PolylineLength(const std::vector<Eigen::Vector2d>& points) {
  double length = 0.0;
  for (size_t i = 1; i < points.size(); ++i) {
    length += (points[i] - points[i - 1]).norm();
  }
  return length;
}

TEST(SceneMesh, StreetBentLengthFactorMakesTheSameStreetLonger) {
  const SynthScene preset = BuildScene("street_bent");
  // Factor 1 is the preset itself, triangle for triangle.
  const SynthScene same = BuildScene("street_bent", 1.0);
  ASSERT_EQ(same.mesh.NumTriangles(), preset.mesh.NumTriangles());
  EXPECT_EQ(same.mesh.vertices, preset.mesh.vertices);
  EXPECT_EQ(same.crease_edges.size(), preset.crease_edges.size());
  EXPECT_EQ(same.survey_stations, preset.survey_stations);
  EXPECT_EQ(same.path.waypoints, preset.path.waypoints);

  const SynthScene longer = BuildScene("street_bent", 3.0);
  CheckScene(longer, 3000);
  // Legs of 135 m instead of 45, the walk 10 m short of each end: 2 x 125 m
  // instead of 2 x 35 m (less the bend's rounding, the same in both).
  const double walk = PolylineLength(preset.path.waypoints);
  const double longer_walk = PolylineLength(longer.path.waypoints);
  EXPECT_NEAR(longer_walk - walk, 180.0, 1e-6);
  // Facades, kerbs and window frames all along it: the crease edges (and
  // the triangles) grow with the street, about threefold.
  EXPECT_GT(longer.crease_edges.size(), 2.5 * preset.crease_edges.size());
  EXPECT_GT(longer.mesh.NumTriangles(), 2.5 * preset.mesh.NumTriangles());
  // The furniture and cars (concrete, above the kerbs) repeat along both
  // legs: on the preset within 45 m of the bend, here beyond 60 m on both
  // sides.
  auto concrete_extent = [](const SceneMesh& mesh) {
    Eigen::Vector2d extent(0.0, 0.0);  // min x, max x
    for (size_t t = 0; t < mesh.NumTriangles(); ++t) {
      // Above the (concrete) kerbs.
      const Eigen::Vector3f& vertex = mesh.vertices[mesh.triangles[t](0)];
      if (mesh.materials[t] != Material::kConcrete || vertex.z() < 0.5) {
        continue;
      }
      const float x = vertex.x();
      extent(0) = std::min(extent(0), static_cast<double>(x));
      extent(1) = std::max(extent(1), static_cast<double>(x));
    }
    return extent;
  };
  EXPECT_GT(concrete_extent(preset.mesh)(0), -45.0);
  EXPECT_LT(concrete_extent(preset.mesh)(1), 45.0);
  EXPECT_LT(concrete_extent(longer.mesh)(0), -60.0);
  EXPECT_GT(concrete_extent(longer.mesh)(1), 60.0);
  // The survey stations stand on the road, every 9 m along the whole
  // centre line (first every 18 m, then between those), none off its ends.
  ASSERT_EQ(longer.survey_stations.size(), 29u);
  for (const Eigen::Vector2d& station : longer.survey_stations) {
    EXPECT_LT(station.norm(), 135.0 - 8.0);
  }
  EXPECT_LT(
      (longer.survey_stations.front() - Eigen::Vector2d(-126.0, 0.0)).norm(),
      1e-9);
  EXPECT_THROW(BuildScene("street_bent", 0.5), Error);
  EXPECT_THROW(BuildScene("quad", 2.0), Error);
  EXPECT_THROW(BuildScene("no_such_scene"), Error);
}

TEST(SceneMesh, StreetBentPaintIsFlatAndNoCrease) {
  const SynthScene scene = BuildScene("street_bent");
  ASSERT_GT(scene.paint_edges.size(), 40u);
  const RayTracer tracer(scene.mesh);
  const Eigen::Vector3d down(0.0, 0.0, -1.0);
  int num_borders = 0;
  for (const PaintEdge& edge : scene.paint_edges) {
    EXPECT_NEAR(edge.start.z(), 0.003, 1e-9);
    EXPECT_NEAR(edge.end.z(), 0.003, 1e-9);
    // Seen from above, 1 cm to one side of the border is paint and 1 cm to
    // the other side the road.
    const Eigen::Vector3d mid = 0.5 * (edge.start + edge.end);
    const Eigen::Vector3d d = (edge.end - edge.start).normalized();
    const Eigen::Vector3d side = d.cross(Eigen::Vector3d::UnitZ());
    Material materials[2];
    for (int k = 0; k < 2; ++k) {
      const RayHit hit = tracer.Intersect(
          mid + (k == 0 ? 0.01 : -0.01) * side + Eigen::Vector3d(0, 0, 1),
          down);
      ASSERT_TRUE(hit.Valid());
      materials[k] = scene.mesh.materials[hit.triangle];
    }
    num_borders += (materials[0] == Material::kPaint) !=
                   (materials[1] == Material::kPaint);
    // No crease edge runs along a paint border.
    for (const CreaseEdge& crease : scene.crease_edges) {
      const Eigen::Vector3d c = crease.end - crease.start;
      const double t = std::clamp((mid - crease.start).dot(c) / c.dot(c),
                                  0.0, 1.0);
      EXPECT_GT((crease.start + t * c - mid).norm(), 0.05);
    }
  }
  EXPECT_EQ(num_borders, static_cast<int>(scene.paint_edges.size()));
}

TEST(SceneMesh, SquareCreaseEdgesLieOnCreases) {
  const SynthScene scene = BuildScene("square");
  EXPECT_EQ(scene.name, "square");
  CheckScene(scene, 500);
  EXPECT_TRUE(scene.paint_edges.empty());
  // The walk keeps clear of the objects: nothing within 1.5 m of the
  // camera around any waypoint at camera height.
  const RayTracer tracer(scene.mesh);
  for (const Eigen::Vector2d& w : scene.path.waypoints) {
    EXPECT_GT(tracer.DistanceToSurface({w.x(), w.y(), scene.path.height_m}),
              1.45);
  }
}

TEST(SceneMesh, FramedWindowStandsProud) {
  SceneBuilder builder;
  FacadeOpening window;
  window.u_min = 1.0;
  window.u_max = 2.0;
  window.v_min = 1.0;
  window.v_max = 2.5;
  window.depth = 0.15;
  window.frame_width = 0.12;
  window.frame_protrusion = 0.07;
  // The ground the wall stands on (for the wall-ground crease).
  builder.AddQuadFacing({-1, -3, 0}, {4, -3, 0}, {4, 3, 0}, {-1, 3, 0},
                        Eigen::Vector3d::UnitZ(), Material::kPaving, 0);
  builder.AddFacade({0, 0, 0}, Eigen::Vector3d::UnitX(),
                    -Eigen::Vector3d::UnitY(), 3.0, 4.0, Material::kBrick, 0,
                    {window});
  const RayTracer tracer(builder.mesh());
  const RayHit wall = tracer.Intersect({0.5, -5, 1.5}, {0, 1, 0});
  const RayHit frame = tracer.Intersect({0.94, -5, 1.5}, {0, 1, 0});
  const RayHit glass = tracer.Intersect({1.5, -5, 1.75}, {0, 1, 0});
  ASSERT_TRUE(wall.Valid() && frame.Valid() && glass.Valid());
  EXPECT_NEAR(wall.distance, 5.0, 1e-6);
  EXPECT_NEAR(frame.distance, 4.93, 1e-6);
  EXPECT_NEAR(glass.distance, 5.15, 1e-6);
  EXPECT_EQ(builder.mesh().materials[frame.triangle], Material::kFrame);
  // 1 wall-ground line + 8 recess edges + 12 frame edges (4 lips, 4 lines
  // on the wall, 4 corners) + 12 sill edges.
  EXPECT_EQ(builder.crease_edges().size(), 33u);
  SynthScene scene;
  scene.mesh = builder.mesh();
  scene.crease_edges = builder.crease_edges();
  CheckScene(scene, 33);
  // A frame on a door is refused.
  FacadeOpening door = window;
  door.v_min = 0.0;
  door.has_sill = false;
  EXPECT_THROW(builder.AddFacade({0, 0, 0}, Eigen::Vector3d::UnitX(),
                                 -Eigen::Vector3d::UnitY(), 3.0, 4.0,
                                 Material::kBrick, 0, {door}),
               Error);
}

TEST(SceneMesh, DisplacedEdgesAreRejected) {
  // The checker must fail for edges that are not on a crease: shift every
  // edge by 5 cm into the free space in front of it, or flip its convexity.
  const SynthScene scene = BuildQuadScene();
  const RayTracer tracer(scene.mesh);
  int accepted_shifted = 0;
  int accepted_flipped = 0;
  for (const CreaseEdge& edge : scene.crease_edges) {
    CreaseEdge shifted = edge;
    const Eigen::Vector3d offset =
        0.05 * (edge.normal1 + edge.normal2).normalized();
    shifted.start += offset;
    shifted.end += offset;
    accepted_shifted += EdgeIsCrease(tracer, shifted) ? 1 : 0;
    CreaseEdge flipped = edge;
    flipped.convex = !edge.convex;
    accepted_flipped += EdgeIsCrease(tracer, flipped) ? 1 : 0;
  }
  EXPECT_EQ(accepted_shifted, 0);
  EXPECT_LT(accepted_flipped, static_cast<int>(scene.crease_edges.size()) / 20);
}

TEST(SceneMesh, BoxHasTwelveEdgesAndOutwardNormals) {
  SceneBuilder builder;
  builder.AddBox({0, 0, 1}, {1, 2, 3}, Material::kConcrete, 0, true);
  EXPECT_EQ(builder.mesh().NumTriangles(), 12u);
  EXPECT_EQ(builder.crease_edges().size(), 12u);
  const Eigen::Vector3f center(0.5f, 1.0f, 2.0f);
  for (size_t t = 0; t < builder.mesh().NumTriangles(); ++t) {
    const Eigen::Vector3f& a =
        builder.mesh().vertices[builder.mesh().triangles[t](0)];
    EXPECT_GT(builder.mesh().normals[t].dot(a - center), 0.0f);
  }
  for (const CreaseEdge& edge : builder.crease_edges()) {
    EXPECT_TRUE(edge.convex);
    EXPECT_NEAR(edge.AngleDeg(), 90.0, 1e-9);
  }
  // On the ground: no bottom face, 4 concave ground lines.
  SceneBuilder ground_builder;
  ground_builder.AddBox({0, 0, 0}, {1, 1, 1}, Material::kConcrete, 0, true);
  EXPECT_EQ(ground_builder.mesh().NumTriangles(), 10u);
  int concave = 0;
  for (const CreaseEdge& edge : ground_builder.crease_edges()) {
    concave += edge.convex ? 0 : 1;
  }
  EXPECT_EQ(concave, 4);
}

TEST(SceneMesh, FacadeOpeningIsRecessed) {
  SceneBuilder builder;
  FacadeOpening window;
  window.u_min = 1.0;
  window.u_max = 2.0;
  window.v_min = 1.0;
  window.v_max = 2.5;
  window.depth = 0.15;
  builder.AddFacade({0, 0, 0}, Eigen::Vector3d::UnitX(),
                    -Eigen::Vector3d::UnitY(), 3.0, 4.0, Material::kBrick, 0,
                    {window});
  const RayTracer tracer(builder.mesh());
  // Through the window centre the ray stops 15 cm deeper than on the wall.
  const RayHit wall = tracer.Intersect({0.5, -5, 1.5}, {0, 1, 0});
  const RayHit glass = tracer.Intersect({1.5, -5, 1.75}, {0, 1, 0});
  ASSERT_TRUE(wall.Valid());
  ASSERT_TRUE(glass.Valid());
  EXPECT_NEAR(wall.distance, 5.0, 1e-6);
  EXPECT_NEAR(glass.distance, 5.15, 1e-6);
  EXPECT_EQ(builder.mesh().materials[glass.triangle], Material::kGlass);
  // 1 wall-ground line + 8 recess edges + 12 sill edges.
  EXPECT_EQ(builder.crease_edges().size(), 21u);
}

TEST(SceneMesh, DistanceToSurface) {
  SceneBuilder builder;
  builder.AddTriangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, Material::kConcrete, 0);
  const RayTracer tracer(builder.mesh());
  EXPECT_NEAR(tracer.DistanceToSurface({0.2, 0.2, 0.5}), 0.5, 1e-7);
  EXPECT_NEAR(tracer.DistanceToSurface({-1, 0, 0}), 1.0, 1e-7);
  EXPECT_NEAR(tracer.DistanceToSurface({1, 1, 0}), std::sqrt(0.5), 1e-7);
  EXPECT_NEAR(tracer.DistanceToSurface({0.5, -2, 0}), 2.0, 1e-7);
  const RayHit hit = tracer.Intersect({0.25, 0.25, 3.0}, {0, 0, -2.0});
  ASSERT_TRUE(hit.Valid());
  EXPECT_NEAR(hit.distance, 1.5, 1e-12);
}

}  // namespace
}  // namespace colmap_lidar
