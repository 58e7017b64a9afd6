// The synthetic scene: a triangle soup with one material and one texture
// seed per triangle, the list of its ground-truth crease edges, and a
// builder for the primitives the presets are made of (quads, boxes,
// cylinders, facades with recessed or framed windows and doors).
//
// Conventions: world frame in metres, z up, the ground is the plane z = 0.
// Every primitive gets its own vertices (no sharing between primitives), so
// a per-vertex material is well defined when the mesh is written as PLY.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace colmap_lidar {

// Surface materials; the procedural textures are in textures.h.
enum class Material : uint8_t {
  kBrick = 0,     // Red-brown bricks with mortar joints: many features.
  kStone = 1,     // Ashlar limestone blocks: medium texture.
  kPlaster = 2,   // Painted render: nearly uniform, very low frequency only.
  kPaving = 3,    // Square paving slabs with joints (the ground).
  kGlass = 4,     // Dark window panes at the back of the window recesses.
  kFrame = 5,     // Painted stone of window/door reveals and sills.
  kWood = 6,      // Doors, benches.
  kConcrete = 7,  // Planters, bollards, kerbs.
  kFoliage = 8,   // Tree canopy (unstructured random triangles).
  kBark = 9,      // Tree trunk.
  kRoof = 10,     // Roof tops (rarely seen).
  kAsphalt = 11,  // Road surface: dark, fine aggregate grain, no joints.
  kPaint = 12,    // Road marking paint (lane lines, crossings): white.
};
constexpr int kNumMaterials = 13;
std::string MaterialName(Material material);

// A straight segment where two planar surfaces meet at an angle (the
// "crease edges" of the ground truth). normal1/normal2 are the outward unit
// normals of the two surfaces; `convex` is true for an outer corner (box
// edge, window reveal lip) and false for an inner corner (wall-ground line,
// back of a recess).
struct CreaseEdge {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal1 = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal2 = Eigen::Vector3d::Zero();
  bool convex = false;

  // Angle between the two normals in degrees (90 for a wall corner).
  double AngleDeg() const;
};

// A straight segment where the albedo changes abruptly on a flat surface
// (the border of a painted road mark): an image edge without geometry, so
// NOT a crease edge (LIDAR sees no depth change along it).
struct PaintEdge {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
};

struct SceneMesh {
  std::vector<Eigen::Vector3f> vertices;
  // Counter-clockwise seen from outside: the face normal is outward.
  std::vector<Eigen::Vector3i> triangles;
  std::vector<Material> materials;         // One per triangle.
  std::vector<uint32_t> texture_seeds;     // One per triangle.
  std::vector<Eigen::Vector3f> normals;    // One per triangle, unit.

  size_t NumTriangles() const { return triangles.size(); }
  // Material per vertex (from the triangles using it); for PLY export.
  std::vector<Material> VertexMaterials() const;
};

// A rectangular opening in a facade, in facade coordinates: u along the
// facade (metres from its start), v up (metres above its base).
struct FacadeOpening {
  double u_min = 0.0;
  double u_max = 0.0;
  double v_min = 0.0;
  double v_max = 0.0;
  // How far the back (glass, door panel) sits behind the facade plane.
  double depth = 0.15;
  Material back_material = Material::kGlass;
  Material reveal_material = Material::kFrame;
  // A sill box under the opening (windows); a door has none.
  bool has_sill = true;
  // A window frame standing proud of the wall (windows only): a ring
  // `frame_width` metres wide around the opening whose front face is
  // `frame_protrusion` metres in front of the facade plane (the reveals
  // then start at the frame's front). 0 (default): a plain recess. With a
  // frame the sill sits 5 cm below the frame.
  double frame_width = 0.0;
  double frame_protrusion = 0.0;
};

// Builds a SceneMesh and its CreaseEdge list together.
class SceneBuilder {
 public:
  // A planar quad a-b-c-d (counter-clockwise seen from the side its normal
  // points to). Not a crease source by itself.
  void AddQuad(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
               const Eigen::Vector3d& c, const Eigen::Vector3d& d,
               Material material, uint32_t texture_seed);
  // The same with the winding chosen so that the normal points along
  // `outward` (convenient when the corner order is not oriented).
  void AddQuadFacing(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                     const Eigen::Vector3d& c, const Eigen::Vector3d& d,
                     const Eigen::Vector3d& outward, Material material,
                     uint32_t texture_seed);
  void AddTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                   const Eigen::Vector3d& c, Material material,
                   uint32_t texture_seed);

  // An axis-aligned box [min, max], all six faces (the bottom too, unless it
  // stands on the ground: bottom at z = 0 is left out). With
  // `add_edges`, its 12 edges become convex crease edges, except the 4
  // bottom ones of a box on the ground, which become concave wall-ground
  // lines (when `ground_edges`).
  void AddBox(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
              Material material, uint32_t texture_seed, bool add_edges,
              bool ground_edges = true);

  // A box spanned from `origin` by sizes[i] * axes[i] (an orthonormal
  // frame, any orientation). attached_face is -1 or the index of the face
  // that rests on a supporting surface (2 * axis + (positive side ? 1 :
  // 0)): that face is not emitted and, with `add_edges`, its 4 edges
  // become concave creases with the support (whose normal is the opposite
  // of the face's outward normal); all other edges are convex creases.
  void AddOrientedBox(const Eigen::Vector3d& origin,
                      const std::array<Eigen::Vector3d, 3>& axes,
                      const Eigen::Vector3d& sizes, Material material,
                      uint32_t texture_seed, bool add_edges,
                      int attached_face);

  // A vertical cylinder standing on z = z_base, approximated by `sides`
  // flat faces with a top cap. The top rim is a convex crease and, on the
  // ground (z_base = 0) or with `on_support` (z_base is the top of a
  // horizontal surface such as a raised pavement), the bottom rim a concave
  // one; the side facets are treated as a smooth surface (no creases
  // between them).
  void AddCylinder(const Eigen::Vector2d& center, double radius,
                   double z_base, double height, int sides, Material material,
                   uint32_t texture_seed, bool add_edges,
                   bool on_support = false);

  // A vertical facade rectangle from `origin` (on the ground) along the
  // horizontal unit vector `u_dir` for `width` metres and `height` metres up,
  // its outward normal `normal` (horizontal, perpendicular to u_dir).
  // Openings are recessed into it with reveals (inner sides), a back face
  // and an optional sill box; their crease edges and the facade's
  // wall-ground line (interrupted by doors) are recorded.
  void AddFacade(const Eigen::Vector3d& origin, const Eigen::Vector3d& u_dir,
                 const Eigen::Vector3d& normal, double width, double height,
                 Material material, uint32_t texture_seed,
                 const std::vector<FacadeOpening>& openings);

  void AddCreaseEdge(const Eigen::Vector3d& start, const Eigen::Vector3d& end,
                     const Eigen::Vector3d& normal1,
                     const Eigen::Vector3d& normal2, bool convex);
  void AddPaintEdge(const Eigen::Vector3d& start, const Eigen::Vector3d& end);

  SceneMesh& mesh() { return mesh_; }
  std::vector<CreaseEdge>& crease_edges() { return crease_edges_; }
  std::vector<PaintEdge>& paint_edges() { return paint_edges_; }

 private:
  SceneMesh mesh_;
  std::vector<CreaseEdge> crease_edges_;
  std::vector<PaintEdge> paint_edges_;
};

}  // namespace colmap_lidar
