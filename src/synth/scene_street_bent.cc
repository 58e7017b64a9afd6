// The "street_bent" preset: a street canyon with a bend, raised pavements
// with kerbs, painted lane lines, repetitive brick facades with protruding
// window frames, street furniture and parked cars.
#include <algorithm>
#include <cmath>
#include <vector>

#include "colmap_ext/util/logging.h"
#include "src/synth/random.h"
#include "src/synth/scene_blocks.h"
#include "src/synth/scene_presets.h"

namespace colmap_lidar {
namespace {

constexpr double kBendDeg = 28.0;
// Of the preset at length_factor 1; each leg is length_factor times longer.
constexpr double kLegLength = 45.0;
// Lateral offsets from the centre line of the road (metres, positive to
// the left of the walking direction).
constexpr double kFacadeOffset = 6.0;
constexpr double kKerbOffset = 3.5;
// The pavement slab reaches 0.5 m behind the facades: the floor of the
// door recesses.
constexpr double kPavementBackOffset = 6.5;
constexpr double kKerbHeight = 0.13;
constexpr double kEdgeLineOffset = 3.2;
constexpr double kWalkOffset = -1.5;
// The walk ends this far before each end of the street.
constexpr double kWalkEndMargin = 10.0;
constexpr double kWalkBendRadius = 12.0;
// The street furniture and parked cars repeat every this many metres along
// a longer street.
constexpr double kFurniturePeriod = 2.0 * kLegLength;

Eigen::Vector2d Direction(int leg) {
  const double angle = leg == 0 ? 0.0 : kBendDeg * M_PI / 180.0;
  return Eigen::Vector2d(std::cos(angle), std::sin(angle));
}

Eigen::Vector2d LeftOf(const Eigen::Vector2d& d) {
  return Eigen::Vector2d(-d.y(), d.x());
}

// The road's centre line: leg 0 from (-leg_length, 0) to the bend at the
// origin, leg 1 from there along Direction(1).
std::vector<Eigen::Vector2d> CenterLine(double leg_length) {
  return {-leg_length * Direction(0), Eigen::Vector2d::Zero(),
          leg_length * Direction(1)};
}

// The positions s + k * kFurniturePeriod (integer k) of an object placed at
// `s` on the preset's street that lie on a street of legs `leg_length` long,
// more than 3 m from its ends; {s} on the preset's street.
std::vector<double> Repeated(double s, double leg_length) {
  std::vector<double> positions;
  const int max_k = static_cast<int>(std::ceil(leg_length / kFurniturePeriod));
  for (int k = -max_k; k <= max_k; ++k) {
    const double position = s + k * kFurniturePeriod;
    if (k == 0 ||
        (leg_length > kLegLength && std::abs(position) < leg_length - 3.0)) {
      positions.push_back(position);
    }
  }
  return positions;
}

// The point `s` metres along the centre line from the bend (negative on
// leg 0), `offset` metres to its left; objects are kept > 3 m from the
// bend, where the mitred offset lines differ from this.
Eigen::Vector2d StreetPoint(double s, double offset) {
  const Eigen::Vector2d d = Direction(s < 0.0 ? 0 : 1);
  return s * d + offset * LeftOf(d);
}

// A row of repetitive brick houses (a few in stone) of 8-14 m along a
// facade `length` metres long, 9-18 m high, all with the same window grid
// and protruding frames; random doors.
std::vector<Building> MakeRow(double length, uint64_t stream) {
  const CounterRng rng(kLayoutSeed,
                       StreamId(RandomStream::kSceneLayout, stream));
  std::vector<Building> row;
  uint64_t index = 0;
  double u = 0.0;
  while (u < length - 1e-9) {
    Building b;
    b.u0 = u;
    b.u1 = std::min(length, u + 8.0 + 6.0 * rng.Uniform(index++));
    if (length - b.u1 < 6.0) b.u1 = length;
    b.height = 9.0 + 9.0 * rng.Uniform(index++);
    b.material =
        rng.Uniform(index++) < 0.8 ? Material::kBrick : Material::kStone;
    b.window_spacing = 2.6;
    b.window_width = 1.1;
    b.door_column = static_cast<int>(3 * rng.Uniform(index++)) - 1;
    b.recess_depth = 0.12;
    b.frame_width = 0.12;
    b.frame_protrusion = 0.07;
    row.push_back(b);
    u = b.u1;
  }
  return row;
}

// The walk: the right lane's centre line with the bend rounded by an arc.
std::vector<Eigen::Vector2d> WalkWaypoints(double leg_length) {
  const double walk_half_length = leg_length - kWalkEndMargin;
  const std::vector<Eigen::Vector2d> lane =
      OffsetPolyline({-walk_half_length * Direction(0), Eigen::Vector2d::Zero(),
                      walk_half_length * Direction(1)},
                     kWalkOffset);
  const double half_turn = 0.5 * kBendDeg * M_PI / 180.0;
  const double tangent_length = kWalkBendRadius * std::tan(half_turn);
  const Eigen::Vector2d start_of_arc = lane[1] - tangent_length * Direction(0);
  // A left turn: the arc's centre is on the left.
  const Eigen::Vector2d arc_center =
      start_of_arc + kWalkBendRadius * LeftOf(Direction(0));
  std::vector<Eigen::Vector2d> points = {lane[0]};
  const int num_arc_points = 9;
  for (int k = 0; k < num_arc_points; ++k) {
    const double angle = 2.0 * half_turn * k / (num_arc_points - 1);
    const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
    points.push_back(arc_center - kWalkBendRadius * LeftOf(d));
  }
  points.push_back(lane[2]);
  return points;
}

}  // namespace

SynthScene BuildStreetBentScene(double length_factor) {
  THROW_CHECK(std::isfinite(length_factor) && length_factor >= 1.0,
              "street_bent: length_factor must be >= 1, got " << length_factor);
  const double leg_length = kLegLength * length_factor;
  SceneBuilder builder;
  AddGround(&builder, leg_length + 35.0, Material::kAsphalt);
  const std::vector<Eigen::Vector2d> center = CenterLine(leg_length);

  // Facades on both sides, standing on the pavements, one row per leg and
  // side; the rows meet at the bend, convex on the inner (left) side,
  // concave on the outer (right) side.
  for (const double side : {1.0, -1.0}) {
    const std::vector<Eigen::Vector2d> facade =
        OffsetPolyline(center, side * kFacadeOffset);
    std::vector<Building> rows[2];
    Eigen::Vector3d normals[2];
    Eigen::Vector3d u_dirs[2];
    for (int leg = 0; leg < 2; ++leg) {
      const Eigen::Vector2d d = (facade[leg + 1] - facade[leg]).normalized();
      u_dirs[leg] = Eigen::Vector3d(d.x(), d.y(), 0.0);
      // The facades face the road: to the right of a left-hand row.
      const Eigen::Vector2d n = -side * LeftOf(d);
      normals[leg] = Eigen::Vector3d(n.x(), n.y(), 0.0);
      const int row_index = 2 * leg + (side > 0.0 ? 0 : 1);
      const uint64_t stream = 1400 + row_index;
      rows[leg] = MakeRow((facade[leg + 1] - facade[leg]).norm(), stream);
      AddBuildingRow(
          &builder,
          Eigen::Vector3d(facade[leg].x(), facade[leg].y(), kKerbHeight),
          u_dirs[leg], normals[leg], rows[leg], 10.0, 1100 + 50 * row_index);
    }
    AddFacadeCorner(&builder,
                    Eigen::Vector3d(facade[1].x(), facade[1].y(), kKerbHeight),
                    normals[0], rows[0].back().height, u_dirs[0], normals[1],
                    rows[1].front().height, -u_dirs[1],
                    /*convex=*/side > 0.0);
  }

  // Pavements with kerbs on both sides of the 7 m road.
  AddPavement(&builder, OffsetPolyline(center, kPavementBackOffset),
              OffsetPolyline(center, kKerbOffset), kKerbHeight,
              Material::kPaving, 1500);
  AddPavement(&builder, OffsetPolyline(center, -kPavementBackOffset),
              OffsetPolyline(center, -kKerbOffset), kKerbHeight,
              Material::kPaving, 1510);

  // Road marks: continuous edge lines, a dashed centre line (3 m dashes
  // every 8 m, none within 1.5 m of the bend or across the crossing) and a
  // zebra crossing on leg 0 (bars 0.5 m wide, 3 m long, every 0.9 m).
  AddPaintLine(&builder, OffsetPolyline(center, kEdgeLineOffset), 0.1, 1600);
  AddPaintLine(&builder, OffsetPolyline(center, -kEdgeLineOffset), 0.1, 1601);
  const double crossing_start = -21.5;
  const double crossing_end = -18.5;
  uint32_t seed = 1610;
  for (double s = -leg_length + 2.0; s + 3.0 < leg_length; s += 8.0) {
    const double s_end = s + 3.0;
    if (s < 1.5 && s_end > -1.5) continue;
    if (s < crossing_end + 1.0 && s_end > crossing_start - 1.0) continue;
    AddPaintLine(&builder, {StreetPoint(s, 0.0), StreetPoint(s_end, 0.0)}, 0.12,
                 seed++);
  }
  for (int bar = 0; bar < 7; ++bar) {
    const double y = -2.7 + 0.9 * bar;
    AddPaintLine(&builder, {{crossing_start, y}, {crossing_end, y}}, 0.5, 1630);
  }

  // Street furniture on the pavements: benches facing the road, bollards
  // along the kerbs, trees; parked cars (boxes) in the left lane, clear of
  // the paint.
  const double bench_s[4] = {-30.0, -8.0, 10.0, 33.0};
  // Along a longer street they repeat every kFurniturePeriod (Repeated).
  for (int k = 0; k < 4; ++k) {
    const double side = k % 2 == 0 ? 1.0 : -1.0;
    for (const double s : Repeated(bench_s[k], leg_length)) {
      const Eigen::Vector2d d = Direction(s < 0.0 ? 0 : 1);
      // The sitter looks to the left of `along`: towards the road.
      AddBench(&builder, StreetPoint(s, side * 4.2),
               side > 0 ? Eigen::Vector2d(-d) : d, kKerbHeight, 1.8,
               1700 + 2 * k);
    }
  }
  for (int k = 0; k < 5; ++k) {
    for (const double s : Repeated(-16.0 + 1.6 * k, leg_length)) {
      builder.AddCylinder(StreetPoint(s, -3.8), 0.1, kKerbHeight, 0.9, 12,
                          Material::kConcrete, 1720 + k, true,
                          /*on_support=*/true);
    }
  }
  for (int k = 0; k < 4; ++k) {
    for (const double s : Repeated(18.0 + 1.6 * k, leg_length)) {
      builder.AddCylinder(StreetPoint(s, 3.8), 0.1, kKerbHeight, 0.9, 12,
                          Material::kConcrete, 1730 + k, true,
                          /*on_support=*/true);
    }
  }
  const double tree_s[3] = {-24.0, -4.0, 24.0};
  const double tree_offset[3] = {-4.2, 4.3, -4.2};
  for (int k = 0; k < 3; ++k) {
    for (const double s : Repeated(tree_s[k], leg_length)) {
      AddTree(&builder, StreetPoint(s, tree_offset[k]), 2.6, 1.2, 1740 + k);
    }
  }
  const double car_s[4] = {-38.0, -27.0, 14.0, 29.0};
  for (int k = 0; k < 4; ++k) {
    for (const double s : Repeated(car_s[k], leg_length)) {
      const Eigen::Vector2d d = Direction(s < 0.0 ? 0 : 1);
      AddStandingBox(&builder, StreetPoint(s, 2.15), d, 0.0,
                     Eigen::Vector3d(4.2, 1.8, 1.4), Material::kConcrete,
                     1750 + k);
    }
  }

  SynthScene scene;
  scene.name = "street_bent";
  scene.mesh = std::move(builder.mesh());
  scene.crease_edges = std::move(builder.crease_edges());
  scene.paint_edges = std::move(builder.paint_edges());
  scene.notes =
      "The pavements are raised: their tops are at z = 0.13 m (kerbs 0.13 m "
      "high); only the road is at z = 0. The facades stand on the "
      "pavements. Painted road marks are 3 mm above the road.";
  // On the road's centre line, first the four that cover the street.
  scene.survey_stations = {StreetPoint(-27, 0), StreetPoint(-9, 0),
                           StreetPoint(9, 0),   StreetPoint(27, 0),
                           StreetPoint(-36, 1), StreetPoint(-18, -1),
                           StreetPoint(18, 1),  StreetPoint(36, -1)};
  if (length_factor > 1.0) {
    // A longer street: one station every 18 m along the centre line, 9 m
    // from its ends and from each other's neighbours (the preset's spacing),
    // first those, then the same shifted by 9 m and 1 m to the side.
    scene.survey_stations.clear();
    for (const double shift : {0.0, 9.0}) {
      for (double s = -leg_length + 9.0 + shift; s <= leg_length - 9.0;
           s += 18.0) {
        scene.survey_stations.push_back(
            StreetPoint(s, shift == 0.0 ? 0.0 : (s < 0.0 ? 1.0 : -1.0)));
      }
    }
  }
  scene.path.waypoints = WalkWaypoints(leg_length);
  scene.path.closed = false;
  scene.path.look_yaw_offset_deg = 0.0;
  scene.path.yaw_amplitude_deg = 45.0;
  scene.path.yaw_period_frames = 16.0;
  return scene;
}

}  // namespace colmap_lidar
