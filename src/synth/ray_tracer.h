// Ray casting against a SceneMesh with Embree 3. One instance is built
// per scene and queried concurrently from many threads (Embree's
// rtcIntersect1 / rtcOccluded1 are thread-safe on a committed scene).
#pragma once

#include <cstdint>
#include <limits>

#include <Eigen/Core>

#include "src/synth/scene_mesh.h"

// Forward declarations of Embree's opaque handles (embree3/rtcore.h), so
// users of this header do not need Embree's headers.
typedef struct RTCDeviceTy* RTCDevice;
typedef struct RTCSceneTy* RTCScene;

namespace colmap_lidar {

struct RayHit {
  // Ray parameter of the hit: origin + distance * direction. For a unit
  // direction it is the Euclidean distance in metres.
  double distance = std::numeric_limits<double>::infinity();
  // Triangle index in the mesh, or -1 when the ray hits nothing.
  int64_t triangle = -1;
  bool Valid() const { return triangle >= 0; }
};

class RayTracer {
 public:
  // Builds the acceleration structure; the mesh must outlive the tracer.
  // Throws colmap_lidar::Error with Embree's error code on failure.
  explicit RayTracer(const SceneMesh& mesh);
  ~RayTracer();
  RayTracer(const RayTracer&) = delete;
  RayTracer& operator=(const RayTracer&) = delete;

  // The closest hit with t in [t_near, t_far]; the direction need not be
  // unit length (t is in units of its length).
  RayHit Intersect(const Eigen::Vector3d& origin,
                   const Eigen::Vector3d& direction, double t_near = 0.0,
                   double t_far = std::numeric_limits<double>::infinity()) const;
  // True when anything lies on the ray with t in [t_near, t_far].
  bool Occluded(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                double t_near = 0.0,
                double t_far = std::numeric_limits<double>::infinity()) const;

  // Unsigned distance from `point` to the closest surface (brute force over
  // all triangles; for tests and evaluation of a few thousand points).
  double DistanceToSurface(const Eigen::Vector3d& point) const;

  const SceneMesh& mesh() const { return mesh_; }

 private:
  const SceneMesh& mesh_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace colmap_lidar
