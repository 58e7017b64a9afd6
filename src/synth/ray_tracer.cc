#include "src/synth/ray_tracer.h"

#include <algorithm>
#include <cmath>

#include <embree3/rtcore.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

float ToFloatFar(double t) {
  return std::isinf(t) ? std::numeric_limits<float>::infinity()
                       : static_cast<float>(t);
}

void InitRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
             double t_near, double t_far, RTCRay* ray) {
  ray->org_x = static_cast<float>(origin.x());
  ray->org_y = static_cast<float>(origin.y());
  ray->org_z = static_cast<float>(origin.z());
  ray->dir_x = static_cast<float>(direction.x());
  ray->dir_y = static_cast<float>(direction.y());
  ray->dir_z = static_cast<float>(direction.z());
  ray->tnear = static_cast<float>(t_near);
  ray->tfar = ToFloatFar(t_far);
  ray->time = 0.0f;
  ray->mask = 0xFFFFFFFFu;
  ray->id = 0;
  ray->flags = 0;
}

// Distance from a point to a triangle (exact, double precision).
double PointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c);

}  // namespace

RayTracer::RayTracer(const SceneMesh& mesh) : mesh_(mesh) {
  THROW_CHECK(!mesh.triangles.empty(), "Cannot ray trace an empty mesh");
  device_ = rtcNewDevice(nullptr);
  THROW_CHECK(device_ != nullptr,
              "Embree: cannot create a device (error "
                  << static_cast<int>(rtcGetDeviceError(nullptr)) << ")");
  scene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  float* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
      3 * sizeof(float), mesh.vertices.size()));
  unsigned* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
      3 * sizeof(unsigned), mesh.triangles.size()));
  THROW_CHECK(vertices != nullptr && indices != nullptr,
              "Embree: cannot allocate the geometry buffers (error "
                  << static_cast<int>(rtcGetDeviceError(device_)) << ")");
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = mesh.vertices[i](k);
  }
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      indices[3 * i + k] = static_cast<unsigned>(mesh.triangles[i](k));
    }
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene_);
  const RTCError error = rtcGetDeviceError(device_);
  THROW_CHECK(error == RTC_ERROR_NONE,
              "Embree: scene build failed (error " << static_cast<int>(error)
                                                    << ")");
}

RayTracer::~RayTracer() {
  if (scene_ != nullptr) rtcReleaseScene(scene_);
  if (device_ != nullptr) rtcReleaseDevice(device_);
}

RayHit RayTracer::Intersect(const Eigen::Vector3d& origin,
                            const Eigen::Vector3d& direction, double t_near,
                            double t_far) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit ray_hit;
  InitRay(origin, direction, t_near, t_far, &ray_hit.ray);
  ray_hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  ray_hit.hit.primID = RTC_INVALID_GEOMETRY_ID;
  ray_hit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &ray_hit);
  RayHit hit;
  if (ray_hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.triangle = ray_hit.hit.primID;
  // Re-intersect the found triangle in double precision: Embree's float t
  // is off by ~1e-6 relative, which would show as depth noise.
  const Eigen::Vector3i& tri = mesh_.triangles[hit.triangle];
  const Eigen::Vector3d a = mesh_.vertices[tri(0)].cast<double>();
  const Eigen::Vector3d normal = mesh_.normals[hit.triangle].cast<double>();
  const double denominator = normal.dot(direction);
  if (std::abs(denominator) > 1e-12) {
    hit.distance = normal.dot(a - origin) / denominator;
  } else {
    hit.distance = ray_hit.ray.tfar;
  }
  return hit;
}

bool RayTracer::Occluded(const Eigen::Vector3d& origin,
                         const Eigen::Vector3d& direction, double t_near,
                         double t_far) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray;
  InitRay(origin, direction, t_near, t_far, &ray);
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0.0f;
}

namespace {

double PointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  // Closest point on the triangle by Voronoi regions (Ericson, Real-Time
  // Collision Detection, 5.1.5), written from the region conditions.
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    return (p - (a + d1 / (d1 - d3) * ab)).norm();
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    return (p - (a + d2 / (d2 - d6) * ac)).norm();
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  }
  const double denominator = 1.0 / (va + vb + vc);
  const double v = vb * denominator;
  const double w = vc * denominator;
  return (p - (a + ab * v + ac * w)).norm();
}

}  // namespace

double RayTracer::DistanceToSurface(const Eigen::Vector3d& point) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3i& tri : mesh_.triangles) {
    best = std::min(best, PointTriangleDistance(
                              point, mesh_.vertices[tri(0)].cast<double>(),
                              mesh_.vertices[tri(1)].cast<double>(),
                              mesh_.vertices[tri(2)].cast<double>()));
  }
  return best;
}

}  // namespace colmap_lidar
