// Building blocks shared by the scene presets (scene_<preset>.cc): rows of
// buildings with windows and doors, their corners, trees, the ground,
// raised pavements with kerbs, painted road marks and street furniture.
// Each block adds triangles and crease edges to a SceneBuilder; frames and
// units as in scene_mesh.h (world, metres, z up, the ground is z = 0).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "src/synth/scene_mesh.h"

namespace colmap_lidar {

// The layout randomness (window doors, tree leaves, building sizes) uses a
// fixed seed: the scene is part of the benchmark definition, not of the
// noise.
constexpr uint64_t kLayoutSeed = 20240601;

// One building along a row of facades: its facade spans [u0, u1] of the
// row, `height` metres high (above the row's origin).
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
  // Window frames standing proud of the wall (FacadeOpening::frame_*); 0:
  // plain recesses. Doors never get one.
  double frame_width = 0.0;
  double frame_protrusion = 0.0;
};

// The windows (floors every 3.2 m, columns every window_spacing) and the
// door of a building's facade, in facade coordinates.
std::vector<FacadeOpening> MakeOpenings(const Building& building);

// A row of buildings whose facades lie in one vertical plane through
// `origin` spanned by `u_dir`, facing `normal`; each building is a box
// `depth` metres deep behind its facade. Records the facade creases, the
// facade top edges and the vertical step edges between buildings of
// different heights (not at the two ends of the row).
void AddBuildingRow(SceneBuilder* builder, const Eigen::Vector3d& origin,
                    const Eigen::Vector3d& u_dir, const Eigen::Vector3d& normal,
                    const std::vector<Building>& buildings, double depth,
                    uint32_t seed_base);

// Where two rows of facades meet at the vertical line through `corner`
// (z from corner.z()): facade a (outward normal normal_a, height_a) and
// facade b. Up to the lower height the corner edge is recorded, concave
// (an inside corner, courtyard) or convex (an outside corner); above it the
// convex edge between the taller facade and its own end wall, whose
// outward normal is `end_normal_*`.
void AddFacadeCorner(SceneBuilder* builder, const Eigen::Vector3d& corner,
                     const Eigen::Vector3d& normal_a, double height_a,
                     const Eigen::Vector3d& end_normal_a,
                     const Eigen::Vector3d& normal_b, double height_b,
                     const Eigen::Vector3d& end_normal_b, bool convex);

// The free end of a row of buildings (nothing beyond it), at `corner` on
// the ground line of the last facade: the convex vertical edge between the
// facade (outward normal `facade_normal`) and the building's end wall
// (`end_normal`), the end wall's line on the ground (concave) and its top
// edge against the roof (convex); the building is `depth` metres deep.
void AddFreeBuildingEnd(SceneBuilder* builder, const Eigen::Vector3d& corner,
                        const Eigen::Vector3d& facade_normal,
                        const Eigen::Vector3d& end_normal, double height,
                        double depth);

// A tree: a bark cylinder and a canopy of random triangles in a ball; the
// trunk stands on z = 0 (it may pass through a raised pavement).
void AddTree(SceneBuilder* builder, const Eigen::Vector2d& center,
             double trunk_height, double canopy_radius, uint32_t seed);

// The ground plane z = 0 over [-half_size, half_size]^2.
void AddGround(SceneBuilder* builder, double half_size,
               Material material = Material::kPaving);

// `num_points` points on the ellipse with semi-axes a (x) and b (y),
// counter-clockwise from (0, -b).
std::vector<Eigen::Vector2d> Ellipse(double a, double b, int num_points);

// The polyline `points` shifted sideways by `offset` metres (positive to
// the left of the direction of travel), corners joined by mitres (the
// intersection of the shifted segments). Throws on fewer than two points
// or a reversal.
std::vector<Eigen::Vector2d> OffsetPolyline(
    const std::vector<Eigen::Vector2d>& points, double offset);

// A raised pavement between the polylines `back_line` (behind the facades,
// so that door recesses have a floor) and `kerb_line` (the kerb), both
// with the same number of points, `height` metres above the road (z = 0):
// its top faces, the vertical kerb faces towards the road (outward normals
// pointing from the back line to the kerb line) and the two end faces.
// Crease edges: the kerb's top lip (convex) and its foot on the road
// (concave) along every leg, and the short vertical kerb edges where the
// polyline turns (convex or concave as the kerb turns).
void AddPavement(SceneBuilder* builder,
                 const std::vector<Eigen::Vector2d>& back_line,
                 const std::vector<Eigen::Vector2d>& kerb_line, double height,
                 Material top_material, uint32_t seed);

// A painted line on the road (z = 0), raised by kPaintThickness so that
// the ray tracer sees it in front of the road: `width` metres wide along
// the polyline `center_line` (mitred corners). Not a crease; its borders
// at least 0.3 m long become paint edges (SceneBuilder::paint_edges).
constexpr double kPaintThickness = 0.003;
void AddPaintLine(SceneBuilder* builder,
                  const std::vector<Eigen::Vector2d>& center_line, double width,
                  uint32_t seed);

// A box standing on the horizontal surface z = `base_z`, centred at
// `center`: `size` = (length along the horizontal unit `along`, width
// across it, height). Its bottom edges are concave creases with the
// surface, the others convex.
void AddStandingBox(SceneBuilder* builder, const Eigen::Vector2d& center,
                    const Eigen::Vector2d& along, double base_z,
                    const Eigen::Vector3d& size, Material material,
                    uint32_t seed);

// A bench standing on z = `base_z`, `length` metres long along the
// horizontal unit `along`, centred at `center`: a wooden seat block
// (0.5 m deep, 0.45 m high) and, 0.1 m behind it (on the right of
// `along`), a wooden backrest slab 0.9 m high; the sitter looks to the
// left of `along`.
void AddBench(SceneBuilder* builder, const Eigen::Vector2d& center,
              const Eigen::Vector2d& along, double base_z, double length,
              uint32_t seed);

}  // namespace colmap_lidar
