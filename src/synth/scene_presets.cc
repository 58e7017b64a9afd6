#include "src/synth/scene_presets.h"

#include <algorithm>
#include <cmath>

#include "colmap_ext/util/logging.h"
#include "src/synth/random.h"

namespace colmap_lidar {
namespace {

// The layout randomness (window doors, tree leaves) uses a fixed seed: the
// scene is part of the benchmark definition, not of the noise.
constexpr uint64_t kLayoutSeed = 20240601;

// One building along a row of facades: its facade spans [u0, u1] of the
// row, `height` metres high.
struct Building {
  double u0 = 0.0;
  double u1 = 0.0;
  double height = 10.0;
  Material material = Material::kBrick;
  // Window columns every window_spacing metres (0: a blank wall).
  double window_spacing = 2.6;
  double window_width = 1.1;
  // Index of the ground-floor column that is a door (-1: none).
  int door_column = -1;
  double recess_depth = 0.15;
};

std::vector<FacadeOpening> MakeOpenings(const Building& building) {
  std::vector<FacadeOpening> openings;
  const double width = building.u1 - building.u0;
  if (building.window_spacing <= 0.0) {
    if (building.door_column >= 0) {
      FacadeOpening door;
      door.u_min = 0.5 * width - 0.6;
      door.u_max = 0.5 * width + 0.6;
      door.v_min = 0.0;
      door.v_max = 2.2;
      door.depth = 0.2;
      door.back_material = Material::kWood;
      door.has_sill = false;
      openings.push_back(door);
    }
    return openings;
  }
  const double margin = 0.9;
  const int num_columns = std::max(
      1, static_cast<int>((width - 2 * margin) / building.window_spacing));
  const double first_center =
      0.5 * width - 0.5 * (num_columns - 1) * building.window_spacing;
  const double floor_height = 3.2;
  for (int floor = 0;; ++floor) {
    const double v_min = 0.9 + floor * floor_height;
    const double v_max = v_min + 1.4;
    if (v_max > building.height - 0.8) break;
    for (int column = 0; column < num_columns; ++column) {
      const double center = first_center + column * building.window_spacing;
      FacadeOpening opening;
      opening.depth = building.recess_depth;
      if (floor == 0 && column == building.door_column) {
        opening.u_min = center - 0.6;
        opening.u_max = center + 0.6;
        opening.v_min = 0.0;
        opening.v_max = 2.3;
        opening.depth = building.recess_depth + 0.05;
        opening.back_material = Material::kWood;
        opening.has_sill = false;
      } else {
        opening.u_min = center - 0.5 * building.window_width;
        opening.u_max = center + 0.5 * building.window_width;
        opening.v_min = v_min;
        opening.v_max = v_max;
      }
      openings.push_back(opening);
    }
  }
  return openings;
}

// A row of buildings whose facades lie in one vertical plane through
// `origin` spanned by `u_dir`, facing `normal`; each building is a box
// `depth` metres deep behind its facade. Records the facade creases, the
// facade top edges and the vertical step edges between buildings of
// different heights.
void AddBuildingRow(SceneBuilder* builder, const Eigen::Vector3d& origin,
                    const Eigen::Vector3d& u_dir, const Eigen::Vector3d& normal,
                    const std::vector<Building>& buildings, double depth,
                    uint32_t seed_base) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d back = -normal;
  for (size_t i = 0; i < buildings.size(); ++i) {
    const Building& b = buildings[i];
    const uint32_t seed = seed_base + static_cast<uint32_t>(i) * 7919u;
    const Eigen::Vector3d p0 = origin + b.u0 * u_dir;
    const Eigen::Vector3d p1 = origin + b.u1 * u_dir;
    builder->AddFacade(p0, u_dir, normal, b.u1 - b.u0, b.height, b.material,
                       seed, MakeOpenings(b));
    const Eigen::Vector3d h(0, 0, b.height);
    // Roof, back wall and the parts of the side walls above the neighbours
    // (no creases: they are not seen from the courtyard or street).
    const Eigen::Vector3d d = depth * back;
    builder->AddQuadFacing(p0 + h, p1 + h, p1 + h + d, p0 + h + d, up,
                           Material::kRoof, seed);
    builder->AddQuadFacing(p0 + d, p1 + d, p1 + d + h, p0 + d + h, back,
                           b.material, seed);
    const double left_height = i > 0 ? buildings[i - 1].height : 0.0;
    const double right_height =
        i + 1 < buildings.size() ? buildings[i + 1].height : 0.0;
    if (left_height < b.height) {
      const Eigen::Vector3d z0(0, 0, left_height);
      builder->AddQuadFacing(p0 + z0, p0 + z0 + d, p0 + h + d, p0 + h, -u_dir,
                             b.material, seed);
      if (i > 0) {
        builder->AddCreaseEdge(p0 + z0, p0 + h, normal, -u_dir, true);
      }
    }
    if (right_height < b.height) {
      const Eigen::Vector3d z0(0, 0, right_height);
      builder->AddQuadFacing(p1 + z0, p1 + z0 + d, p1 + h + d, p1 + h, u_dir,
                             b.material, seed);
      if (i + 1 < buildings.size()) {
        builder->AddCreaseEdge(p1 + z0, p1 + h, normal, u_dir, true);
      }
    }
    // The facade's top edge against the roof.
    builder->AddCreaseEdge(p0 + h, p1 + h, normal, up, true);
  }
}

// A tree: a bark cylinder and a canopy of random triangles in a ball.
void AddTree(SceneBuilder* builder, const Eigen::Vector2d& center,
             double trunk_height, double canopy_radius, uint32_t seed) {
  builder->AddCylinder(center, 0.15, 0.0, trunk_height + 0.5, 10,
                       Material::kBark, seed, /*add_edges=*/false);
  const CounterRng rng(kLayoutSeed, StreamId(RandomStream::kSceneLayout, seed));
  const Eigen::Vector3d canopy_center(center.x(), center.y(),
                                      trunk_height + canopy_radius);
  uint64_t index = 0;
  for (int leaf = 0; leaf < 400; ++leaf) {
    Eigen::Vector3d offset;
    do {
      offset = Eigen::Vector3d(2 * rng.Uniform(index) - 1,
                               2 * rng.Uniform(index + 1) - 1,
                               2 * rng.Uniform(index + 2) - 1);
      index += 3;
    } while (offset.norm() > 1.0);
    const Eigen::Vector3d c = canopy_center + canopy_radius * offset;
    Eigen::Vector3d corners[3];
    for (int k = 0; k < 3; ++k) {
      corners[k] = c + 0.35 * Eigen::Vector3d(2 * rng.Uniform(index) - 1,
                                              2 * rng.Uniform(index + 1) - 1,
                                              2 * rng.Uniform(index + 2) - 1);
      index += 3;
    }
    if ((corners[1] - corners[0]).cross(corners[2] - corners[0]).norm() <
        1e-3) {
      continue;
    }
    builder->AddTriangle(corners[0], corners[1], corners[2],
                         Material::kFoliage, seed + leaf);
  }
}

void AddGround(SceneBuilder* builder, double half_size) {
  builder->AddQuad(Eigen::Vector3d(-half_size, -half_size, 0),
                   Eigen::Vector3d(half_size, -half_size, 0),
                   Eigen::Vector3d(half_size, half_size, 0),
                   Eigen::Vector3d(-half_size, half_size, 0),
                   Material::kPaving, 1);
}

// The concave vertical edge where two perpendicular facades of the
// courtyard meet, and above the lower one the convex edge of the taller
// facade with its own end wall (whose outward normal is `end_normal_*`).
void AddCourtyardCorner(SceneBuilder* builder, const Eigen::Vector2d& corner,
                        const Eigen::Vector3d& normal_a, double height_a,
                        const Eigen::Vector3d& end_normal_a,
                        const Eigen::Vector3d& normal_b, double height_b,
                        const Eigen::Vector3d& end_normal_b) {
  const Eigen::Vector3d base(corner.x(), corner.y(), 0.0);
  const double low = std::min(height_a, height_b);
  builder->AddCreaseEdge(base, base + Eigen::Vector3d(0, 0, low), normal_a,
                         normal_b, false);
  if (height_a > height_b) {
    builder->AddCreaseEdge(base + Eigen::Vector3d(0, 0, low),
                           base + Eigen::Vector3d(0, 0, height_a), normal_a,
                           end_normal_a, true);
  } else if (height_b > height_a) {
    builder->AddCreaseEdge(base + Eigen::Vector3d(0, 0, low),
                           base + Eigen::Vector3d(0, 0, height_b), normal_b,
                           end_normal_b, true);
  }
}

std::vector<Eigen::Vector2d> Ellipse(double a, double b, int num_points) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < num_points; ++i) {
    const double angle = 2.0 * M_PI * i / num_points - 0.5 * M_PI;
    points.emplace_back(a * std::cos(angle), b * std::sin(angle));
  }
  return points;
}

}  // namespace

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
  AddCourtyardCorner(&builder, {-15, -10}, ey, south.front().height, -ex, ex,
                     west.front().height, -ey);
  AddCourtyardCorner(&builder, {15, -10}, ey, south.back().height, ex, -ex,
                     east.front().height, -ey);
  AddCourtyardCorner(&builder, {-15, 10}, -ey, north.front().height, -ex, ex,
                     west.back().height, ey);
  AddCourtyardCorner(&builder, {15, 10}, -ey, north.back().height, ex, -ex,
                     east.back().height, ey);

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
  builder.AddCylinder({10.5, -7.2}, 0.08, 0.0, 4.0, 8, Material::kConcrete,
                      508, true);
  builder.AddBox({-0.6, -0.6, 0.0}, {0.6, 0.6, 1.0}, Material::kStone, 509,
                 true);

  SynthScene scene;
  scene.name = "quad";
  scene.mesh = std::move(builder.mesh());
  scene.crease_edges = std::move(builder.crease_edges());
  scene.survey_stations = {{-8, -4}, {8, 4},  {-6, 5}, {7, -5},
                           {0, -7},  {0, 7},  {-12, 0}, {12, -1}};
  scene.path.waypoints = Ellipse(9.5, 5.5, 120);
  scene.path.closed = true;
  // Counter-clockwise walk: outwards is to the right; look 60 degrees right
  // of the walking direction, i.e. obliquely forward at the walls.
  scene.path.look_yaw_offset_deg = -60.0;
  scene.path.yaw_amplitude_deg = 10.0;
  scene.path.yaw_period_frames = 9.0;
  return scene;
}

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
  scene.survey_stations = {{-30, 0}, {-15, 0}, {0, 0},   {15, 0},
                           {30, 0},  {-22, 1}, {8, -1},  {22, 1}};
  scene.path.waypoints = {{-32.0, 0.0}, {32.0, 0.0}};
  scene.path.closed = false;
  scene.path.look_yaw_offset_deg = 0.0;
  scene.path.yaw_amplitude_deg = 8.0;
  scene.path.yaw_period_frames = 16.0;
  return scene;
}

SynthScene BuildScene(const std::string& preset) {
  if (preset == "quad") return BuildQuadScene();
  if (preset == "street") return BuildStreetScene();
  if (preset == "corridor") return BuildCorridorScene();
  THROW_ERROR("Unknown Synthesis.preset '"
              << preset << "' (expected quad, street or corridor)");
}

}  // namespace colmap_lidar
