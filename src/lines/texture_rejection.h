// Texture-only line rejection (section III-B: "we discard lines
// corresponding to flat surfaces (i.e. only corresponding to changes in
// texture)"). The LIDAR points around a lifted 3D segment are split into the
// two sides of its viewing plane (the plane through the camera centre and
// the segment); a plane is fitted to each side. The segment is a geometric
// edge when the two normals differ by at least min_normal_change_deg, or
// when one side has a surface and the other has (almost) no points within
// the radius (an occluding contour). It is a texture line when both sides
// lie on one plane.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace colmap_lidar {

struct TextureRejectionOptions {
  // Discard texture-only lines.
  bool enabled = true;
  // Points within this distance of the segment are its neighbours, metres.
  double radius = 0.3;
  // Points nearer than this to the line belong to neither side, metres.
  double exclusion_distance = 0.02;
  // A side needs this many points for a plane fit.
  int min_side_points = 6;
  // Angle between the side normals of an edge, degrees.
  double min_normal_change_deg = 15.0;

  bool Check() const;
};

enum class LineSurfaceType {
  kCrease,        // the normal turns across the line
  kOcclusion,     // a surface on one side only
  kTexture,       // one plane on both sides
  kUnknown,       // too few points on both sides to tell
};

// start/end and the points are in the camera frame (camera centre at the
// origin). `points` may contain any points; those farther than the radius
// from the segment are ignored.
LineSurfaceType ClassifyLineSurface(const Eigen::Vector3d& start,
                                    const Eigen::Vector3d& end,
                                    const std::vector<Eigen::Vector3d>& points,
                                    const TextureRejectionOptions& options);

}  // namespace colmap_lidar
