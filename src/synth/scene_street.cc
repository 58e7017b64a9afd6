// The "street" preset: a straight 80 m street canyon.
#include <algorithm>

#include "src/synth/random.h"
#include "src/synth/scene_blocks.h"
#include "src/synth/scene_presets.h"

namespace colmap_lidar {

SynthScene BuildStreetScene() {
  SceneBuilder builder;
  AddGround(&builder, 80.0);
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d ey = Eigen::Vector3d::UnitY();
  const CounterRng rng(kLayoutSeed, StreamId(RandomStream::kSceneLayout, 77));
  const Material materials[3] = {Material::kBrick, Material::kStone,
                                 Material::kPlaster};
  uint64_t index = 0;
  for (int side = 0; side < 2; ++side) {
    std::vector<Building> row;
    double u = 0.0;
    while (u < 80.0 - 1e-9) {
      Building b;
      b.u0 = u;
      b.u1 = std::min(80.0, u + 8.0 + 6.0 * rng.Uniform(index++));
      if (80.0 - b.u1 < 6.0) b.u1 = 80.0;
      b.height = 9.0 + 9.0 * rng.Uniform(index++);
      b.material = materials[static_cast<int>(3 * rng.Uniform(index++)) % 3];
      b.window_spacing = 2.4 + 0.8 * rng.Uniform(index++);
      b.door_column = static_cast<int>(3 * rng.Uniform(index++)) - 1;
      b.recess_depth = 0.1 + 0.1 * rng.Uniform(index++);
      row.push_back(b);
      u = b.u1;
    }
    if (side == 0) {
      AddBuildingRow(&builder, Eigen::Vector3d(-40, -6, 0), ex, ey, row, 10.0,
                     600);
    } else {
      AddBuildingRow(&builder, Eigen::Vector3d(-40, 6, 0), ex, -ey, row, 10.0,
                     700);
    }
  }
  // Parked cars (boxes), trees and bollards along the pavements.
  const double car_x[4] = {-30.0, -12.0, 6.0, 21.0};
  for (int k = 0; k < 4; ++k) {
    const double y = (k % 2 == 0) ? 3.6 : -5.4;
    builder.AddBox({car_x[k], y, 0.0}, {car_x[k] + 4.2, y + 1.8, 1.4},
                   Material::kConcrete, 800 + k, true);
  }
  AddTree(&builder, {-20.0, 3.8}, 2.6, 1.3, 810);
  AddTree(&builder, {15.0, -3.8}, 2.6, 1.3, 811);
  for (int k = 0; k < 4; ++k) {
    builder.AddCylinder({-4.0 + 1.5 * k, -4.9}, 0.12, 0.0, 0.9, 12,
                        Material::kConcrete, 820 + k, true);
  }

  SynthScene scene;
  scene.name = "street";
  scene.mesh = std::move(builder.mesh());
  scene.crease_edges = std::move(builder.crease_edges());
  scene.survey_stations = {{-24, 0}, {-8, 0}, {8, 0},   {24, 0},
                           {-16, 1}, {0, 1},  {16, -1}, {32, 0}};
  scene.path.waypoints = {{-25.0, -1.5}, {25.0, -1.5}};
  scene.path.closed = false;
  scene.path.look_yaw_offset_deg = 0.0;
  scene.path.yaw_amplitude_deg = 50.0;
  scene.path.yaw_period_frames = 16.0;
  return scene;
}

}  // namespace colmap_lidar
