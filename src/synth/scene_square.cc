// The "square" preset: an open, paved town square with buildings on three
// sides only and a few objects, so that the ground dominates the views.
#include <cmath>

#include "src/synth/scene_blocks.h"
#include "src/synth/scene_presets.h"

namespace colmap_lidar {
namespace {

Building MakeBuilding(double u0, double u1, double height, Material material,
                      double spacing, int door) {
  Building b;
  b.u0 = u0;
  b.u1 = u1;
  b.height = height;
  b.material = material;
  b.window_spacing = spacing;
  b.door_column = door;
  b.recess_depth = 0.15;
  return b;
}

}  // namespace

SynthScene BuildSquareScene() {
  SceneBuilder builder;
  // A large ground plane: the east side is open, its far edge should lie
  // beyond the LIDAR's range and near the horizon of the images.
  AddGround(&builder, 200.0, Material::kPaving);
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d ey = Eigen::Vector3d::UnitY();
  const double depth = 10.0;
  // The square is x in [-25, 25], y in [-20, 20]: buildings along the west
  // side (x = -25), the north side up to x = 15 and the south side up to
  // x = 0; the east opens onto more paving.
  const std::vector<Building> west = {
      MakeBuilding(0, 11, 16, Material::kStone, 2.8, 1),
      MakeBuilding(11, 19, 12, Material::kPlaster, 3.5, -1),
      MakeBuilding(19, 30, 18, Material::kBrick, 2.6, 2),
      MakeBuilding(30, 40, 14.5, Material::kStone, 2.7, 0)};
  const std::vector<Building> north = {
      MakeBuilding(0, 12, 15, Material::kBrick, 2.6, 1),
      MakeBuilding(12, 22, 19, Material::kStone, 3.0, -1),
      MakeBuilding(22, 31, 13, Material::kPlaster, 0.0, 0),
      MakeBuilding(31, 40, 16, Material::kBrick, 2.5, 2)};
  const std::vector<Building> south = {
      MakeBuilding(0, 13, 13, Material::kBrick, 2.6, 1),
      MakeBuilding(13, 25, 17, Material::kStone, 2.8, -1)};
  AddBuildingRow(&builder, Eigen::Vector3d(-25, -20, 0), ey, ex, west, depth,
                 2000);
  AddBuildingRow(&builder, Eigen::Vector3d(-25, 20, 0), ex, -ey, north, depth,
                 2100);
  AddBuildingRow(&builder, Eigen::Vector3d(-25, -20, 0), ex, ey, south, depth,
                 2200);
  AddFacadeCorner(&builder, {-25, -20, 0}, ey, south.front().height, -ex, ex,
                  west.front().height, -ey, /*convex=*/false);
  AddFacadeCorner(&builder, {-25, 20, 0}, -ey, north.front().height, -ex, ex,
                  west.back().height, ey, /*convex=*/false);
  AddFreeBuildingEnd(&builder, {15, 20, 0}, -ey, ex, north.back().height,
                     depth);
  AddFreeBuildingEnd(&builder, {0, -20, 0}, ey, ex, south.back().height, depth);

  // Objects, clear of the walk: a fountain basin with benches around it,
  // a kiosk, trees, lamp posts, a line of bollards along the open side.
  builder.AddCylinder({-4.0, 8.0}, 2.5, 0.0, 0.5, 24, Material::kStone, 2300,
                      true);
  AddBench(&builder, {-4.0, 4.2}, {1.0, 0.0}, 0.0, 1.8, 2310);
  AddBench(&builder, {-4.0, 11.8}, {-1.0, 0.0}, 0.0, 1.8, 2312);
  AddBench(&builder, {-7.8, 8.0}, {0.0, -1.0}, 0.0, 1.8, 2314);
  AddBench(&builder, {-14.0, -16.0}, {1.0, 0.0}, 0.0, 2.0, 2316);
  AddStandingBox(&builder, {10.0, -8.0}, {1.0, 0.0}, 0.0,
                 Eigen::Vector3d(3.0, 2.4, 2.6), Material::kWood, 2320);
  AddTree(&builder, {-14.0, 6.0}, 2.6, 1.3, 2330);
  AddTree(&builder, {0.0, -12.0}, 2.6, 1.3, 2331);
  AddTree(&builder, {14.0, 12.0}, 2.6, 1.3, 2332);
  AddTree(&builder, {-18.0, -4.0}, 2.6, 1.3, 2333);
  const Eigen::Vector2d lamps[3] = {{-10.0, -7.0}, {6.0, 6.0}, {18.0, -4.0}};
  for (int k = 0; k < 3; ++k) {
    builder.AddCylinder(lamps[k], 0.08, 0.0, 4.5, 8, Material::kConcrete,
                        2340 + k, true);
  }
  for (int k = 0; k < 7; ++k) {
    builder.AddCylinder({23.0, -9.0 + 3.0 * k}, 0.12, 0.0, 0.9, 12,
                        Material::kConcrete, 2350 + k, true);
  }

  SynthScene scene;
  scene.name = "square";
  scene.mesh = std::move(builder.mesh());
  scene.crease_edges = std::move(builder.crease_edges());
  scene.survey_stations = {{-14, -6}, {-2, 2}, {10, -4}, {8, 12},
                           {-18, 12}, {18, 4}, {0, -14}, {-8, 16}};
  // An S-curve across the square from the open east side to the south-west,
  // looking ahead at the west and north facades 20-45 m away.
  const int num_points = 21;
  for (int k = num_points - 1; k >= 0; --k) {
    const double t = static_cast<double>(k) / (num_points - 1);
    scene.path.waypoints.emplace_back(
        -20.0 + 40.0 * t, -10.0 + 18.0 * t + 3.0 * std::sin(2.0 * M_PI * t));
  }
  scene.path.closed = false;
  scene.path.look_yaw_offset_deg = 0.0;
  scene.path.yaw_amplitude_deg = 45.0;
  scene.path.yaw_period_frames = 16.0;
  return scene;
}

}  // namespace colmap_lidar
