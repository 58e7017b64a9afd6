// Synthetic scenes of textured planes, rendered by ray casting, for the
// PatchMatch tests and benchmark: exact ground-truth depth, images with a
// smooth random texture (value noise, seeded), LIDAR-like point samples.
// Rendering follows the MVS pixel convention: pixel (row, col) is the ray
// K^-1 [col, row, 1].
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "colmap_ext/scene/rigid3.h"
#include "src/mvs/mvs_view.h"
#include "src/mvs/plane_map.h"

namespace colmap_lidar {

struct TexturedPlane {
  // Points origin + u * u_axis + v * v_axis (axes orthonormal) with u, v in
  // the extent and outside the optional hole.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d u_axis = Eigen::Vector3d::UnitX();
  Eigen::Vector3d v_axis = Eigen::Vector3d::UnitY();
  double u_min = -1e9, u_max = 1e9, v_min = -1e9, v_max = 1e9;
  bool has_hole = false;
  double hole_u_min = 0, hole_u_max = 0, hole_v_min = 0, hole_v_max = 0;
  uint32_t texture_seed = 0;
  // Texture cell size, metres.
  double texture_cell_m = 0.06;
};

class PlaneScene {
 public:
  std::vector<TexturedPlane> planes;

  // Nearest hit along origin + t * direction (t > 0). Returns false on a
  // miss.
  bool Intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                 double* t, Eigen::Vector3d* normal, float* intensity) const;

  // Renders a view (2x2 supersampled); `gt_depth` (optional) receives the
  // z-depth per pixel (0 = no surface).
  MvsView Render(const std::string& name, const Eigen::Matrix3d& K,
                 const Rigid3d& cam_from_world, int width, int height,
                 std::vector<float>* gt_depth = nullptr) const;

  // LIDAR-like samples from `origin`: rays through a grid of directions
  // (num_rows x num_cols) around `forward` within the half angles (radians).
  // Normals face the scanner.
  void Scan(const Eigen::Vector3d& origin, const Eigen::Vector3d& forward,
            int num_rows, int num_cols, double half_angle_horizontal,
            double half_angle_vertical, std::vector<Eigen::Vector3f>* points,
            std::vector<Eigen::Vector3f>* normals) const;
};

// A textured wall at z = 4 and a slanted textured plane in front of it
// (world = the middle camera's frame, cameras look along +z).
PlaneScene MakeTestPlaneScene();
// fx = fy = 0.625 width, principal point at the centre.
Eigen::Matrix3d TestCalibration(int width, int height);
// `num` cameras (cam_from_world) looking along +z from a small cross of
// positions around the origin (baseline ~0.2 m), the first at the origin.
std::vector<Rigid3d> TestCameraPoses(int num);

// Share of pixels with ground truth (> 0) whose depth is within `tolerance`
// metres of it (invalid estimates count as failures).
double ShareWithinTolerance(const std::vector<float>& depth,
                            const std::vector<float>& gt_depth,
                            double tolerance);

// A wall seen at grazing incidence: the plane x = 6 + 0.1 z of the frame of
// an untextured (flat grey) 320 x 240 view at the origin (TestCalibration,
// f = 200 px), 10 m away at column 300 and 30 m at 220.
struct GrazingWall {
  Eigen::Matrix3d K;
  MvsView view;
  Eigen::Vector3f normal;  // Unit, camera frame.
  // The wall's z-depth along `ray` (z = 1).
  double Depth(const Eigen::Vector3d& ray) const {
    return 6.0 / (ray.x() - 0.1);
  }
};
GrazingWall MakeGrazingWall();

// A fixed stream of uniform numbers in [0, 1) (a linear congruential
// generator: the same on every platform, unlike
// std::uniform_real_distribution).
class UniformStream {
 public:
  explicit UniformStream(uint64_t seed) : state_(seed) {}
  double Next() {
    state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state_ >> 11) / 9007199254740992.0;
  }

 private:
  uint64_t state_;
};

// The exact plane map of a level ground `height` metres below a camera that
// looks along it (camera rotation identity: y down, z forward): per pixel
// centre the ground's z-depth and its normal facing the camera (0, -1, 0);
// depth 0 at and above the horizon and beyond `max_depth` metres.
PlaneMap GroundPlaneMap(const MvsView& view, float height, float max_depth);

// Two cameras `ground_height` metres above a level ground, both looking
// along it (rotation identity, flat grey images, TestCalibration): the
// reference at the world origin, the source at `src_center` (world = the
// reference's frame); `src_map` is the source's exact GroundPlaneMap up to
// 30 m.
struct GroundViewPair {
  GroundViewPair(int width, int height, float ground_height,
                 const Eigen::Vector3d& src_center);
  MvsView ref;
  MvsView src;
  PlaneMap src_map;
};

}  // namespace colmap_lidar
