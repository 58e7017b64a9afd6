// The "corridor" preset: a narrow alley between tall, sparsely windowed
// walls.
#include "src/synth/scene_blocks.h"
#include "src/synth/scene_presets.h"

namespace colmap_lidar {

SynthScene BuildCorridorScene() {
  SceneBuilder builder;
  AddGround(&builder, 80.0);
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d ey = Eigen::Vector3d::UnitY();
  // Two rows of tall, sparsely windowed walls 6 m apart along x in
  // [-40, 40]: the roll about the straight walk is weakly observed.
  auto wall = [](double u0, double u1, double height, Material material,
                 double spacing, int door) {
    Building b;
    b.u0 = u0;
    b.u1 = u1;
    b.height = height;
    b.material = material;
    b.window_spacing = spacing;
    b.door_column = door;
    b.recess_depth = 0.12;
    return b;
  };
  const std::vector<Building> south = {
      wall(0, 22, 14, Material::kBrick, 7.0, 1),
      wall(22, 47, 16, Material::kStone, 0.0, -1),
      wall(47, 80, 15, Material::kBrick, 8.0, -1)};
  const std::vector<Building> north = {
      wall(0, 30, 15, Material::kStone, 9.0, -1),
      wall(30, 52, 14, Material::kBrick, 0.0, 0),
      wall(52, 80, 17, Material::kPlaster, 7.5, 2)};
  AddBuildingRow(&builder, Eigen::Vector3d(-40, -3, 0), ex, ey, south, 10.0,
                 900);
  AddBuildingRow(&builder, Eigen::Vector3d(-40, 3, 0), ex, -ey, north, 10.0,
                 950);

  SynthScene scene;
  scene.name = "corridor";
  scene.mesh = std::move(builder.mesh());
  scene.crease_edges = std::move(builder.crease_edges());
  scene.survey_stations = {{-30, 0}, {-15, 0}, {0, 0},  {15, 0},
                           {30, 0},  {-22, 1}, {8, -1}, {22, 1}};
  scene.path.waypoints = {{-32.0, 0.0}, {32.0, 0.0}};
  scene.path.closed = false;
  scene.path.look_yaw_offset_deg = 0.0;
  scene.path.yaw_amplitude_deg = 8.0;
  scene.path.yaw_period_frames = 16.0;
  return scene;
}

}  // namespace colmap_lidar
