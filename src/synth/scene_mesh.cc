#include "src/synth/scene_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Appends the quad a-b-c-d with the winding that makes its normal point
// along `outward` (the caller knows which side is outside).
void AddOrientedQuad(SceneBuilder* builder, const Eigen::Vector3d& a,
                     const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                     const Eigen::Vector3d& d, const Eigen::Vector3d& outward,
                     Material material, uint32_t texture_seed) {
  builder->AddQuadFacing(a, b, c, d, outward, material, texture_seed);
}

}  // namespace

std::string MaterialName(Material material) {
  switch (material) {
    case Material::kBrick: return "brick";
    case Material::kStone: return "stone";
    case Material::kPlaster: return "plaster";
    case Material::kPaving: return "paving";
    case Material::kGlass: return "glass";
    case Material::kFrame: return "frame";
    case Material::kWood: return "wood";
    case Material::kConcrete: return "concrete";
    case Material::kFoliage: return "foliage";
    case Material::kBark: return "bark";
    case Material::kRoof: return "roof";
    case Material::kAsphalt: return "asphalt";
    case Material::kPaint: return "paint";
  }
  return "unknown";
}

double CreaseEdge::AngleDeg() const {
  const double cosine = std::clamp(normal1.dot(normal2), -1.0, 1.0);
  return std::acos(cosine) * 180.0 / M_PI;
}

std::vector<Material> SceneMesh::VertexMaterials() const {
  std::vector<Material> vertex_materials(vertices.size(), Material::kConcrete);
  for (size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      vertex_materials[triangles[t](k)] = materials[t];
    }
  }
  return vertex_materials;
}

void SceneBuilder::AddTriangle(const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c, Material material,
                               uint32_t texture_seed) {
  const Eigen::Vector3d normal = (b - a).cross(c - a);
  THROW_CHECK(normal.norm() > 1e-12, "Degenerate triangle in the scene");
  const int first = static_cast<int>(mesh_.vertices.size());
  mesh_.vertices.push_back(a.cast<float>());
  mesh_.vertices.push_back(b.cast<float>());
  mesh_.vertices.push_back(c.cast<float>());
  mesh_.triangles.emplace_back(first, first + 1, first + 2);
  mesh_.materials.push_back(material);
  mesh_.texture_seeds.push_back(texture_seed);
  mesh_.normals.push_back(normal.normalized().cast<float>());
}

void SceneBuilder::AddQuad(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const Eigen::Vector3d& c, const Eigen::Vector3d& d,
                           Material material, uint32_t texture_seed) {
  const Eigen::Vector3d normal = (b - a).cross(c - a);
  THROW_CHECK(normal.norm() > 1e-12, "Degenerate quad in the scene");
  const int first = static_cast<int>(mesh_.vertices.size());
  for (const Eigen::Vector3d* corner : {&a, &b, &c, &d}) {
    mesh_.vertices.push_back(corner->cast<float>());
  }
  mesh_.triangles.emplace_back(first, first + 1, first + 2);
  mesh_.triangles.emplace_back(first, first + 2, first + 3);
  for (int k = 0; k < 2; ++k) {
    mesh_.materials.push_back(material);
    mesh_.texture_seeds.push_back(texture_seed);
    mesh_.normals.push_back(normal.normalized().cast<float>());
  }
}

void SceneBuilder::AddQuadFacing(const Eigen::Vector3d& a,
                                 const Eigen::Vector3d& b,
                                 const Eigen::Vector3d& c,
                                 const Eigen::Vector3d& d,
                                 const Eigen::Vector3d& outward,
                                 Material material, uint32_t texture_seed) {
  if ((b - a).cross(c - a).dot(outward) >= 0.0) {
    AddQuad(a, b, c, d, material, texture_seed);
  } else {
    AddQuad(a, d, c, b, material, texture_seed);
  }
}

void SceneBuilder::AddCreaseEdge(const Eigen::Vector3d& start,
                                 const Eigen::Vector3d& end,
                                 const Eigen::Vector3d& normal1,
                                 const Eigen::Vector3d& normal2,
                                 bool convex) {
  if ((end - start).norm() < 1e-6) return;
  CreaseEdge edge;
  edge.start = start;
  edge.end = end;
  edge.normal1 = normal1.normalized();
  edge.normal2 = normal2.normalized();
  edge.convex = convex;
  crease_edges_.push_back(edge);
}

void SceneBuilder::AddPaintEdge(const Eigen::Vector3d& start,
                                const Eigen::Vector3d& end) {
  if ((end - start).norm() < 1e-6) return;
  paint_edges_.push_back({start, end});
}

void SceneBuilder::AddOrientedBox(const Eigen::Vector3d& origin,
                                  const std::array<Eigen::Vector3d, 3>& axes,
                                  const Eigen::Vector3d& sizes,
                                  Material material, uint32_t texture_seed,
                                  bool add_edges, int attached_face) {
  auto corner = [&](int i, int j, int k) {
    return Eigen::Vector3d(origin + i * sizes(0) * axes[0] +
                           j * sizes(1) * axes[1] + k * sizes(2) * axes[2]);
  };
  auto face_normal = [&](int face) {
    return Eigen::Vector3d((face % 2 == 1 ? 1.0 : -1.0) * axes[face / 2]);
  };
  for (int face = 0; face < 6; ++face) {
    if (face == attached_face) continue;
    const int axis = face / 2;
    const int side = face % 2;
    const int a1 = (axis + 1) % 3;
    const int a2 = (axis + 2) % 3;
    std::array<Eigen::Vector3d, 4> corners;
    const int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int c = 0; c < 4; ++c) {
      int index[3];
      index[axis] = side;
      index[a1] = uv[c][0];
      index[a2] = uv[c][1];
      corners[c] = corner(index[0], index[1], index[2]);
    }
    AddOrientedQuad(this, corners[0], corners[1], corners[2], corners[3],
                    face_normal(face), material, texture_seed);
  }
  if (!add_edges) return;
  // The 12 edges: for each axis, 4 edges parallel to it, each between the
  // faces of the two other axes at the given sides.
  for (int axis = 0; axis < 3; ++axis) {
    const int a1 = (axis + 1) % 3;
    const int a2 = (axis + 2) % 3;
    for (int s1 = 0; s1 < 2; ++s1) {
      for (int s2 = 0; s2 < 2; ++s2) {
        int start_index[3];
        start_index[axis] = 0;
        start_index[a1] = s1;
        start_index[a2] = s2;
        int end_index[3] = {start_index[0], start_index[1], start_index[2]};
        end_index[axis] = 1;
        const Eigen::Vector3d start =
            corner(start_index[0], start_index[1], start_index[2]);
        const Eigen::Vector3d end =
            corner(end_index[0], end_index[1], end_index[2]);
        const int face1 = 2 * a1 + s1;
        const int face2 = 2 * a2 + s2;
        if (face1 == attached_face) {
          AddCreaseEdge(start, end, face_normal(face2), -face_normal(face1),
                        /*convex=*/false);
        } else if (face2 == attached_face) {
          AddCreaseEdge(start, end, face_normal(face1), -face_normal(face2),
                        /*convex=*/false);
        } else {
          AddCreaseEdge(start, end, face_normal(face1), face_normal(face2),
                        /*convex=*/true);
        }
      }
    }
  }
}

void SceneBuilder::AddBox(const Eigen::Vector3d& min,
                          const Eigen::Vector3d& max, Material material,
                          uint32_t texture_seed, bool add_edges,
                          bool ground_edges) {
  THROW_CHECK((max - min).minCoeff() > 0.0, "Empty box in the scene");
  const bool on_ground = std::abs(min.z()) < 1e-9;
  AddOrientedBox(min,
                 {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                  Eigen::Vector3d::UnitZ()},
                 max - min, material, texture_seed, add_edges,
                 on_ground ? 4 : -1);
  if (on_ground && !ground_edges && add_edges) {
    // Drop the 4 concave ground edges just added (the last 12 edges hold
    // them at fixed places; simpler to filter by height and convexity).
    auto& edges = crease_edges_;
    edges.erase(std::remove_if(edges.end() - 12, edges.end(),
                               [](const CreaseEdge& edge) {
                                 return !edge.convex;
                               }),
                edges.end());
  }
}

void SceneBuilder::AddCylinder(const Eigen::Vector2d& center, double radius,
                               double z_base, double height, int sides,
                               Material material, uint32_t texture_seed,
                               bool add_edges, bool on_support) {
  THROW_CHECK(sides >= 3 && radius > 0.0 && height > 0.0,
              "Invalid cylinder in the scene");
  const double z_top = z_base + height;
  const Eigen::Vector3d top_center(center.x(), center.y(), z_top);
  for (int i = 0; i < sides; ++i) {
    const double angle0 = 2.0 * M_PI * i / sides;
    const double angle1 = 2.0 * M_PI * (i + 1) / sides;
    const Eigen::Vector3d p0(center.x() + radius * std::cos(angle0),
                             center.y() + radius * std::sin(angle0), z_base);
    const Eigen::Vector3d p1(center.x() + radius * std::cos(angle1),
                             center.y() + radius * std::sin(angle1), z_base);
    const Eigen::Vector3d q0 = p0 + Eigen::Vector3d(0, 0, height);
    const Eigen::Vector3d q1 = p1 + Eigen::Vector3d(0, 0, height);
    const double mid = 0.5 * (angle0 + angle1);
    const Eigen::Vector3d side_normal(std::cos(mid), std::sin(mid), 0.0);
    AddOrientedQuad(this, p0, p1, q1, q0, side_normal, material, texture_seed);
    AddTriangle(top_center, q0, q1, material, texture_seed);
    if (add_edges) {
      AddCreaseEdge(q0, q1, Eigen::Vector3d::UnitZ(), side_normal, true);
      if (on_support || std::abs(z_base) < 1e-9) {
        AddCreaseEdge(p0, p1, side_normal, Eigen::Vector3d::UnitZ(), false);
      }
    }
  }
}

void SceneBuilder::AddFacade(const Eigen::Vector3d& origin,
                             const Eigen::Vector3d& u_dir,
                             const Eigen::Vector3d& normal, double width,
                             double height, Material material,
                             uint32_t texture_seed,
                             const std::vector<FacadeOpening>& openings) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  THROW_CHECK(std::abs(u_dir.norm() - 1.0) < 1e-9 &&
                  std::abs(normal.norm() - 1.0) < 1e-9 &&
                  std::abs(u_dir.dot(normal)) < 1e-9 &&
                  std::abs(normal.z()) < 1e-9,
              "Facade axes must be orthonormal and horizontal");
  auto point = [&](double u, double v, double w) {
    return Eigen::Vector3d(origin + u * u_dir + v * up + w * normal);
  };
  // The hole each opening cuts into the wall plane: the opening itself, or
  // the outline of its frame.
  struct Hole {
    double u_min, u_max, v_min, v_max;
  };
  std::vector<Hole> holes;
  // A stone sill 2 cm below the opening (5 cm below a frame), 5 cm wider
  // on each side, 6 cm high and 6 cm proud of the wall (4 cm proud of a
  // frame); its back rests on the wall.
  const double sill_height = 0.06;
  const double overhang = 0.05;
  for (const FacadeOpening& opening : openings) {
    const bool framed = opening.frame_width > 0.0;
    THROW_CHECK(opening.frame_width >= 0.0 && opening.frame_protrusion >= 0.0 &&
                    framed == (opening.frame_protrusion > 0.0),
                "A window frame needs both a width and a protrusion > 0");
    THROW_CHECK(!framed || opening.v_min > 0.0,
                "Only windows (not doors) can have a protruding frame");
    const double fw = opening.frame_width;
    const Hole hole = {opening.u_min - fw, opening.u_max + fw,
                       framed ? opening.v_min - fw : opening.v_min,
                       opening.v_max + fw};
    THROW_CHECK(hole.u_min > 0.0 && hole.u_max < width &&
                    opening.u_min < opening.u_max && hole.v_min >= 0.0 &&
                    hole.v_max < height && opening.v_min < opening.v_max,
                "Facade opening outside the facade");
    THROW_CHECK(!opening.has_sill ||
                    hole.v_min >= (framed ? 0.05 + sill_height : 0.1),
                "A window with a sill must start at least 0.1 m up");
    holes.push_back(hole);
  }

  // The wall: a grid over all hole boundaries, minus the holes.
  std::vector<double> us = {0.0, width};
  std::vector<double> vs = {0.0, height};
  for (const Hole& hole : holes) {
    us.push_back(hole.u_min);
    us.push_back(hole.u_max);
    vs.push_back(hole.v_min);
    vs.push_back(hole.v_max);
  }
  for (std::vector<double>* breaks : {&us, &vs}) {
    std::sort(breaks->begin(), breaks->end());
    breaks->erase(std::unique(breaks->begin(), breaks->end()),
                  breaks->end());
  }
  for (size_t i = 0; i + 1 < us.size(); ++i) {
    for (size_t j = 0; j + 1 < vs.size(); ++j) {
      const double uc = 0.5 * (us[i] + us[i + 1]);
      const double vc = 0.5 * (vs[j] + vs[j + 1]);
      const bool in_hole =
          std::any_of(holes.begin(), holes.end(), [&](const Hole& o) {
            return uc > o.u_min && uc < o.u_max && vc > o.v_min &&
                   vc < o.v_max;
          });
      if (in_hole) continue;
      AddOrientedQuad(this, point(us[i], vs[j], 0), point(us[i + 1], vs[j], 0),
                      point(us[i + 1], vs[j + 1], 0),
                      point(us[i], vs[j + 1], 0), normal, material,
                      texture_seed);
    }
  }

  // Wall-ground line, interrupted by doors (openings down to the ground).
  std::vector<std::pair<double, double>> doors;
  for (const FacadeOpening& opening : openings) {
    if (opening.v_min <= 0.0) doors.emplace_back(opening.u_min, opening.u_max);
  }
  std::sort(doors.begin(), doors.end());
  double u_start = 0.0;
  for (const auto& door : doors) {
    AddCreaseEdge(point(u_start, 0, 0), point(door.first, 0, 0), normal, up,
                  false);
    u_start = door.second;
  }
  AddCreaseEdge(point(u_start, 0, 0), point(width, 0, 0), normal, up, false);

  // Recesses: reveals, back, sill, frame, and their crease edges.
  for (size_t k = 0; k < openings.size(); ++k) {
    const FacadeOpening& o = openings[k];
    const double d = -o.depth;
    const bool door = o.v_min <= 0.0;
    const bool framed = o.frame_width > 0.0;
    // The reveals start at the wall, or at the front of the frame.
    const double w0 = framed ? o.frame_protrusion : 0.0;
    const uint32_t seed = texture_seed * 131u + static_cast<uint32_t>(k);
    // Back face.
    AddOrientedQuad(this, point(o.u_min, o.v_min, d), point(o.u_max, o.v_min, d),
                    point(o.u_max, o.v_max, d), point(o.u_min, o.v_max, d),
                    normal, o.back_material, seed);
    // Left and right reveals face the opening's centre.
    AddOrientedQuad(this, point(o.u_min, o.v_min, w0),
                    point(o.u_min, o.v_min, d), point(o.u_min, o.v_max, d),
                    point(o.u_min, o.v_max, w0), u_dir, o.reveal_material,
                    seed);
    AddOrientedQuad(this, point(o.u_max, o.v_min, w0),
                    point(o.u_max, o.v_min, d), point(o.u_max, o.v_max, d),
                    point(o.u_max, o.v_max, w0), -u_dir, o.reveal_material,
                    seed);
    // Top reveal faces down; the bottom one (windows only) faces up.
    AddOrientedQuad(this, point(o.u_min, o.v_max, w0),
                    point(o.u_max, o.v_max, w0), point(o.u_max, o.v_max, d),
                    point(o.u_min, o.v_max, d), -up, o.reveal_material, seed);
    if (!door) {
      AddOrientedQuad(this, point(o.u_min, o.v_min, w0),
                      point(o.u_max, o.v_min, w0), point(o.u_max, o.v_min, d),
                      point(o.u_min, o.v_min, d), up, o.reveal_material, seed);
    }
    // Outer lips (convex) and inner corners with the back (concave).
    AddCreaseEdge(point(o.u_min, o.v_min, w0), point(o.u_min, o.v_max, w0),
                  normal, u_dir, true);
    AddCreaseEdge(point(o.u_max, o.v_min, w0), point(o.u_max, o.v_max, w0),
                  normal, -u_dir, true);
    AddCreaseEdge(point(o.u_min, o.v_max, w0), point(o.u_max, o.v_max, w0),
                  normal, -up, true);
    AddCreaseEdge(point(o.u_min, o.v_min, d), point(o.u_min, o.v_max, d),
                  normal, u_dir, false);
    AddCreaseEdge(point(o.u_max, o.v_min, d), point(o.u_max, o.v_max, d),
                  normal, -u_dir, false);
    AddCreaseEdge(point(o.u_min, o.v_max, d), point(o.u_max, o.v_max, d),
                  normal, -up, false);
    if (door) {
      // The recess floor is the ground: reveal-ground and back-ground lines.
      AddCreaseEdge(point(o.u_min, 0, 0), point(o.u_min, 0, d), u_dir, up,
                    false);
      AddCreaseEdge(point(o.u_max, 0, 0), point(o.u_max, 0, d), -u_dir, up,
                    false);
      AddCreaseEdge(point(o.u_min, 0, d), point(o.u_max, 0, d), normal, up,
                    false);
    } else {
      AddCreaseEdge(point(o.u_min, o.v_min, w0), point(o.u_max, o.v_min, w0),
                    normal, up, true);
      AddCreaseEdge(point(o.u_min, o.v_min, d), point(o.u_max, o.v_min, d),
                    normal, up, false);
    }
    if (framed) {
      // The frame: a ring in front of the wall around the opening, its
      // four outer sides, their lips (convex), their lines on the wall
      // (concave) and the four short corner edges (convex).
      const Hole& h = holes[k];
      const double fp = o.frame_protrusion;
      const Material m = o.reveal_material;
      auto front = [&](double u0, double v0, double u1, double v1) {
        AddOrientedQuad(this, point(u0, v0, fp), point(u1, v0, fp),
                        point(u1, v1, fp), point(u0, v1, fp), normal, m, seed);
      };
      front(h.u_min, h.v_min, o.u_min, h.v_max);
      front(o.u_max, h.v_min, h.u_max, h.v_max);
      front(o.u_min, h.v_min, o.u_max, o.v_min);
      front(o.u_min, o.v_max, o.u_max, h.v_max);
      // Vertical sides (at u = h.u_min, h.u_max) and horizontal ones (at
      // v = h.v_min, h.v_max), each with its lip and its wall line.
      for (const bool high : {false, true}) {
        const double u = high ? h.u_max : h.u_min;
        const Eigen::Vector3d side_normal = high ? u_dir : Eigen::Vector3d(-u_dir);
        AddOrientedQuad(this, point(u, h.v_min, 0), point(u, h.v_max, 0),
                        point(u, h.v_max, fp), point(u, h.v_min, fp),
                        side_normal, m, seed);
        AddCreaseEdge(point(u, h.v_min, fp), point(u, h.v_max, fp), normal,
                      side_normal, true);
        AddCreaseEdge(point(u, h.v_min, 0), point(u, h.v_max, 0), normal,
                      side_normal, false);
      }
      for (const bool high : {false, true}) {
        const double v = high ? h.v_max : h.v_min;
        const Eigen::Vector3d side_normal = high ? up : Eigen::Vector3d(-up);
        AddOrientedQuad(this, point(h.u_min, v, 0), point(h.u_max, v, 0),
                        point(h.u_max, v, fp), point(h.u_min, v, fp),
                        side_normal, m, seed);
        AddCreaseEdge(point(h.u_min, v, fp), point(h.u_max, v, fp), normal,
                      side_normal, true);
        AddCreaseEdge(point(h.u_min, v, 0), point(h.u_max, v, 0), normal,
                      side_normal, false);
      }
      for (const bool high_u : {false, true}) {
        for (const bool high_v : {false, true}) {
          const double u = high_u ? h.u_max : h.u_min;
          const double v = high_v ? h.v_max : h.v_min;
          AddCreaseEdge(point(u, v, 0), point(u, v, fp),
                        high_u ? u_dir : Eigen::Vector3d(-u_dir),
                        high_v ? up : Eigen::Vector3d(-up), true);
        }
      }
    }
    if (o.has_sill) {
      const Hole& hole = holes[k];
      const double sill_depth = framed ? o.frame_protrusion + 0.04 : 0.06;
      const double gap = framed ? 0.05 : 0.02;
      AddOrientedBox(
          point(hole.u_min - overhang, hole.v_min - gap - sill_height, 0),
          {u_dir, up, normal},
          Eigen::Vector3d(hole.u_max - hole.u_min + 2 * overhang, sill_height,
                          sill_depth),
          o.reveal_material, seed, /*add_edges=*/true,
          /*attached_face=*/4);
    }
  }
}

}  // namespace colmap_lidar
