#include "src/synth/scene_blocks.h"

#include <algorithm>
#include <cmath>

#include "colmap_ext/util/logging.h"
#include "src/synth/random.h"

namespace colmap_lidar {
namespace {

Eigen::Vector3d Lift(const Eigen::Vector2d& xy, double z) {
  return Eigen::Vector3d(xy.x(), xy.y(), z);
}

// The left normal of a horizontal direction.
Eigen::Vector2d LeftOf(const Eigen::Vector2d& direction) {
  return Eigen::Vector2d(-direction.y(), direction.x());
}

}  // namespace

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
        opening.frame_width = building.frame_width;
        opening.frame_protrusion = building.frame_protrusion;
      }
      openings.push_back(opening);
    }
  }
  return openings;
}

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

void AddFreeBuildingEnd(SceneBuilder* builder, const Eigen::Vector3d& corner,
                        const Eigen::Vector3d& facade_normal,
                        const Eigen::Vector3d& end_normal, double height,
                        double depth) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d back = -depth * facade_normal;
  const Eigen::Vector3d top = corner + height * up;
  builder->AddCreaseEdge(corner, top, facade_normal, end_normal, true);
  builder->AddCreaseEdge(corner, corner + back, end_normal, up, false);
  builder->AddCreaseEdge(top, top + back, end_normal, up, true);
}

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
    builder->AddTriangle(corners[0], corners[1], corners[2], Material::kFoliage,
                         seed + leaf);
  }
}

void AddGround(SceneBuilder* builder, double half_size, Material material) {
  builder->AddQuad(Eigen::Vector3d(-half_size, -half_size, 0),
                   Eigen::Vector3d(half_size, -half_size, 0),
                   Eigen::Vector3d(half_size, half_size, 0),
                   Eigen::Vector3d(-half_size, half_size, 0), material, 1);
}

void AddFacadeCorner(SceneBuilder* builder, const Eigen::Vector3d& corner,
                     const Eigen::Vector3d& normal_a, double height_a,
                     const Eigen::Vector3d& end_normal_a,
                     const Eigen::Vector3d& normal_b, double height_b,
                     const Eigen::Vector3d& end_normal_b, bool convex) {
  const Eigen::Vector3d& base = corner;
  const double low = std::min(height_a, height_b);
  builder->AddCreaseEdge(base, base + Eigen::Vector3d(0, 0, low), normal_a,
                         normal_b, convex);
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

std::vector<Eigen::Vector2d> OffsetPolyline(
    const std::vector<Eigen::Vector2d>& points, double offset) {
  THROW_CHECK(points.size() >= 2, "A polyline needs at least two points");
  std::vector<Eigen::Vector2d> normals;
  for (size_t k = 0; k + 1 < points.size(); ++k) {
    const Eigen::Vector2d step = points[k + 1] - points[k];
    THROW_CHECK(step.norm() > 1e-9, "Repeated polyline point");
    normals.push_back(LeftOf(step.normalized()));
  }
  std::vector<Eigen::Vector2d> shifted;
  shifted.push_back(points.front() + offset * normals.front());
  for (size_t k = 1; k + 1 < points.size(); ++k) {
    // The mitre: along the bisector of the two normals, as far as makes
    // both shifted segments `offset` away.
    const Eigen::Vector2d bisector = normals[k - 1] + normals[k];
    THROW_CHECK(bisector.norm() > 1e-6, "The polyline reverses at point " << k);
    const Eigen::Vector2d mitre = bisector.normalized();
    shifted.push_back(points[k] + offset / mitre.dot(normals[k]) * mitre);
  }
  shifted.push_back(points.back() + offset * normals.back());
  return shifted;
}

void AddPavement(SceneBuilder* builder,
                 const std::vector<Eigen::Vector2d>& back_line,
                 const std::vector<Eigen::Vector2d>& kerb_line, double height,
                 Material top_material, uint32_t seed) {
  THROW_CHECK(back_line.size() >= 2 && back_line.size() == kerb_line.size(),
              "A pavement needs two polylines of the same length");
  THROW_CHECK(height > 0.0, "A pavement needs a positive kerb height");
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const size_t num_legs = kerb_line.size() - 1;
  // The kerb's outward normal per leg: across the leg, away from the back.
  std::vector<Eigen::Vector3d> kerb_normals;
  for (size_t k = 0; k < num_legs; ++k) {
    Eigen::Vector2d n = LeftOf((kerb_line[k + 1] - kerb_line[k]).normalized());
    if (n.dot(kerb_line[k] - back_line[k]) < 0.0) n = -n;
    kerb_normals.push_back(Lift(n, 0.0));
  }
  for (size_t k = 0; k < num_legs; ++k) {
    const uint32_t leg_seed = seed + 17u * static_cast<uint32_t>(k);
    const Eigen::Vector3d& n = kerb_normals[k];
    builder->AddQuadFacing(
        Lift(back_line[k], height), Lift(back_line[k + 1], height),
        Lift(kerb_line[k + 1], height), Lift(kerb_line[k], height), up,
        top_material, leg_seed);
    builder->AddQuadFacing(Lift(kerb_line[k], 0.0), Lift(kerb_line[k + 1], 0.0),
                           Lift(kerb_line[k + 1], height),
                           Lift(kerb_line[k], height), n, Material::kConcrete,
                           leg_seed + 1);
    builder->AddCreaseEdge(Lift(kerb_line[k], height),
                           Lift(kerb_line[k + 1], height), up, n, true);
    builder->AddCreaseEdge(Lift(kerb_line[k], 0.0), Lift(kerb_line[k + 1], 0.0),
                           n, up, false);
    if (k > 0) {
      // The slab's corner is convex where the kerb turns towards the
      // pavement (away from the road).
      const Eigen::Vector3d& previous = kerb_normals[k - 1];
      const Eigen::Vector2d direction = kerb_line[k + 1] - kerb_line[k];
      const bool convex = direction.dot(previous.head<2>()) < 0.0;
      builder->AddCreaseEdge(Lift(kerb_line[k], 0.0),
                             Lift(kerb_line[k], height), previous, n, convex);
    }
  }
  // The ends of the slab, facing along the first and the last leg.
  const Eigen::Vector2d first = kerb_line[0] - kerb_line[1];
  const Eigen::Vector2d last = kerb_line[num_legs] - kerb_line[num_legs - 1];
  builder->AddQuadFacing(Lift(back_line[0], 0.0), Lift(kerb_line[0], 0.0),
                         Lift(kerb_line[0], height), Lift(back_line[0], height),
                         Lift(first.normalized(), 0.0), Material::kConcrete,
                         seed + 2);
  builder->AddQuadFacing(
      Lift(back_line[num_legs], 0.0), Lift(kerb_line[num_legs], 0.0),
      Lift(kerb_line[num_legs], height), Lift(back_line[num_legs], height),
      Lift(last.normalized(), 0.0), Material::kConcrete, seed + 3);
}

void AddPaintLine(SceneBuilder* builder,
                  const std::vector<Eigen::Vector2d>& center_line, double width,
                  uint32_t seed) {
  THROW_CHECK(width > 0.0, "A paint line needs a positive width");
  const std::vector<Eigen::Vector2d> left =
      OffsetPolyline(center_line, 0.5 * width);
  const std::vector<Eigen::Vector2d> right =
      OffsetPolyline(center_line, -0.5 * width);
  const double z = kPaintThickness;
  auto border = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    if ((b - a).norm() >= 0.3) builder->AddPaintEdge(Lift(a, z), Lift(b, z));
  };
  for (size_t k = 0; k + 1 < center_line.size(); ++k) {
    builder->AddQuadFacing(Lift(right[k], z), Lift(right[k + 1], z),
                           Lift(left[k + 1], z), Lift(left[k], z),
                           Eigen::Vector3d::UnitZ(), Material::kPaint, seed);
    border(right[k], right[k + 1]);
    border(left[k], left[k + 1]);
  }
  border(right.front(), left.front());
  border(right.back(), left.back());
}

void AddStandingBox(SceneBuilder* builder, const Eigen::Vector2d& center,
                    const Eigen::Vector2d& along, double base_z,
                    const Eigen::Vector3d& size, Material material,
                    uint32_t seed) {
  THROW_CHECK(std::abs(along.norm() - 1.0) < 1e-9 && size.minCoeff() > 0.0,
              "A standing box needs a unit direction and a positive size");
  const Eigen::Vector3d u = Lift(along, 0.0);
  const Eigen::Vector3d v = Lift(LeftOf(along), 0.0);
  const Eigen::Vector3d origin =
      Lift(center, base_z) - 0.5 * size.x() * u - 0.5 * size.y() * v;
  // Face 4 (the -z side) rests on the surface.
  builder->AddOrientedBox(origin, {u, v, Eigen::Vector3d::UnitZ()}, size,
                          material, seed, /*add_edges=*/true,
                          /*attached_face=*/4);
}

void AddBench(SceneBuilder* builder, const Eigen::Vector2d& center,
              const Eigen::Vector2d& along, double base_z, double length,
              uint32_t seed) {
  const Eigen::Vector2d right = -LeftOf(along);
  AddStandingBox(builder, center, along, base_z,
                 Eigen::Vector3d(length, 0.5, 0.45), Material::kWood, seed);
  // The backrest: 0.1 m behind the seat's back face (0.25 m from the
  // centre), 0.08 m thick.
  AddStandingBox(builder, center + (0.25 + 0.1 + 0.04) * right, along, base_z,
                 Eigen::Vector3d(length, 0.08, 0.9), Material::kWood, seed + 1);
}

}  // namespace colmap_lidar
