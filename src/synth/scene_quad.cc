// The "quad" preset: a courtyard enclosed by ten buildings.
#include "src/synth/scene_blocks.h"
#include "src/synth/scene_presets.h"

namespace colmap_lidar {

SynthScene BuildQuadScene() {
  SceneBuilder builder;
  AddGround(&builder, 60.0);
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d ey = Eigen::Vector3d::UnitY();
  const double depth = 10.0;
  auto building = [](double u0, double u1, double height, Material material,
                     double spacing, int door, double recess) {
    Building b;
    b.u0 = u0;
    b.u1 = u1;
    b.height = height;
    b.material = material;
    b.window_spacing = spacing;
    b.door_column = door;
    b.recess_depth = recess;
    return b;
  };
  // Rows run along +x (south, north) or +y (west, east) from the corner
  // (-15, -10); u is measured from that corner.
  const std::vector<Building> south = {
      building(0, 11, 12, Material::kStone, 2.6, 1, 0.15),
      building(11, 21, 9, Material::kPlaster, 3.2, 1, 0.12),
      building(21, 30, 14, Material::kBrick, 2.4, -1, 0.18)};
  const std::vector<Building> north = {
      building(0, 12, 10, Material::kBrick, 2.6, 2, 0.15),
      building(12, 23, 15, Material::kStone, 2.8, -1, 0.2),
      building(23, 30, 8, Material::kPlaster, 0.0, 0, 0.15)};
  const std::vector<Building> west = {
      building(0, 12, 11, Material::kBrick, 2.5, 0, 0.15),
      building(12, 20, 13, Material::kStone, 2.7, 1, 0.15)};
  const std::vector<Building> east = {
      building(0, 9, 9, Material::kPlaster, 4.0, -1, 0.1),
      building(9, 20, 12, Material::kBrick, 2.6, 3, 0.15)};
  AddBuildingRow(&builder, Eigen::Vector3d(-15, -10, 0), ex, ey, south, depth,
                 100);
  AddBuildingRow(&builder, Eigen::Vector3d(-15, 10, 0), ex, -ey, north, depth,
                 200);
  AddBuildingRow(&builder, Eigen::Vector3d(-15, -10, 0), ey, ex, west, depth,
                 300);
  AddBuildingRow(&builder, Eigen::Vector3d(15, -10, 0), ey, -ex, east, depth,
                 400);
  // Corners: south/west, south/east, north/west, north/east. The end wall
  // of a south/north building faces -x or +x; of a west/east one -y or +y.
  AddFacadeCorner(&builder, {-15, -10, 0}, ey, south.front().height, -ex, ex,
                  west.front().height, -ey, /*convex=*/false);
  AddFacadeCorner(&builder, {15, -10, 0}, ey, south.back().height, ex, -ex,
                  east.front().height, -ey, /*convex=*/false);
  AddFacadeCorner(&builder, {-15, 10, 0}, -ey, north.front().height, -ex, ex,
                  west.back().height, ey, /*convex=*/false);
  AddFacadeCorner(&builder, {15, 10, 0}, -ey, north.back().height, ex, -ex,
                  east.back().height, ey, /*convex=*/false);

  // Objects in the courtyard, clear of the walking path.
  AddTree(&builder, {-10.0, -6.8}, 2.4, 1.6, 501);
  builder.AddBox({12.2, 2.0, 0.0}, {13.4, 4.6, 0.6}, Material::kConcrete, 502,
                 true);
  builder.AddBox({-3.0, 8.8, 0.0}, {-1.0, 9.4, 0.45}, Material::kWood, 503,
                 true);
  for (int k = 0; k < 3; ++k) {
    builder.AddCylinder({2.0 + 1.5 * k, -8.6}, 0.12, 0.0, 0.9, 12,
                        Material::kConcrete, 504 + k, true);
  }
  builder.AddCylinder({10.5, -7.2}, 0.08, 0.0, 4.0, 8, Material::kConcrete, 508,
                      true);
  builder.AddBox({-0.6, -0.6, 0.0}, {0.6, 0.6, 1.0}, Material::kStone, 509,
                 true);

  SynthScene scene;
  scene.name = "quad";
  scene.mesh = std::move(builder.mesh());
  scene.crease_edges = std::move(builder.crease_edges());
  scene.survey_stations = {{-8, -4}, {8, 4}, {-6, 5},  {7, -5},
                           {0, -7},  {0, 7}, {-12, 0}, {12, -1}};
  scene.path.waypoints = Ellipse(9.5, 5.5, 120);
  scene.path.closed = true;
  // Counter-clockwise walk: outwards is to the right; look 60 degrees right
  // of the walking direction, i.e. obliquely forward at the walls.
  scene.path.look_yaw_offset_deg = -60.0;
  scene.path.yaw_amplitude_deg = 10.0;
  scene.path.yaw_period_frames = 9.0;
  return scene;
}

}  // namespace colmap_lidar
