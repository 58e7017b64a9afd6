#include "src/eval/nearest_neighbor.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <thread>

#include <Eigen/Geometry>
#include <embree3/rtcore.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Runs body(begin, end) on contiguous chunks of [0, count) in parallel.
void ParallelChunks(size_t count,
                    const std::function<void(size_t, size_t)>& body) {
  const size_t num_threads = std::max<size_t>(
      1, std::min<size_t>(std::thread::hardware_concurrency(),
                          count / 1024 + 1));
  if (num_threads == 1) {
    body(0, count);
    return;
  }
  std::vector<std::thread> threads;
  const size_t chunk = (count + num_threads - 1) / num_threads;
  for (size_t t = 0; t < num_threads; ++t) {
    const size_t begin = std::min(count, t * chunk);
    const size_t end = std::min(count, begin + chunk);
    threads.emplace_back(body, begin, end);
  }
  for (std::thread& thread : threads) {
    thread.join();
  }
}

Eigen::Vector3d Centroid(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& point : points) {
    sum += point;
  }
  return points.empty() ? sum : Eigen::Vector3d(sum / points.size());
}

}  // namespace

double PointSegmentDistance(const Eigen::Vector3d& point,
                            const Eigen::Vector3d& a,
                            const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double length_squared = ab.squaredNorm();
  double t = 0.0;
  if (length_squared > 0.0) {
    t = std::clamp((point - a).dot(ab) / length_squared, 0.0, 1.0);
  }
  return (a + t * ab - point).norm();
}

// Closest point by Voronoi regions of the triangle (Ericson, Real-Time
// Collision Detection, 5.1.5).
double PointTriangleDistance(const Eigen::Vector3d& p,
                             const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  if (ab.cross(ac).squaredNorm() <= 0.0) {
    // Degenerate: the closest of the three edges.
    return std::min({PointSegmentDistance(p, a, b),
                     PointSegmentDistance(p, b, c),
                     PointSegmentDistance(p, a, c)});
  }
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    return ap.norm();
  }
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) {
    return bp.norm();
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return (a + v * ab - p).norm();
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) {
    return cp.norm();
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return (a + w * ac - p).norm();
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return (b + w * (c - b) - p).norm();
  }
  const double denominator = 1.0 / (va + vb + vc);
  const double v = vb * denominator;
  const double w = vc * denominator;
  return (a + ab * v + ac * w - p).norm();
}

struct TriangleMeshIndex::Impl {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;
  Eigen::Vector3d origin;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Impl() {
    if (scene != nullptr) {
      rtcReleaseScene(scene);
    }
    if (device != nullptr) {
      rtcReleaseDevice(device);
    }
  }
};

namespace {

struct ClosestPointQuery {
  const TriangleMeshIndex* index;
  const std::vector<Eigen::Vector3d>* vertices;
  const std::vector<Eigen::Vector3i>* triangles;
  Eigen::Vector3d point;
  double distance = std::numeric_limits<double>::infinity();
};

// Embree calls this for every triangle whose bounds intersect the query
// sphere; shrinking the radius prunes the rest of the traversal.
bool ClosestPointCallback(RTCPointQueryFunctionArguments* args) {
  ClosestPointQuery* query = static_cast<ClosestPointQuery*>(args->userPtr);
  const Eigen::Vector3i& triangle = (*query->triangles)[args->primID];
  const std::vector<Eigen::Vector3d>& vertices = *query->vertices;
  const double distance =
      PointTriangleDistance(query->point, vertices[triangle[0]],
                            vertices[triangle[1]], vertices[triangle[2]]);
  if (distance < query->distance) {
    query->distance = distance;
    // Round the float radius up so that no triangle at the same distance
    // is pruned by rounding.
    const float radius = std::nextafter(static_cast<float>(distance),
                                        std::numeric_limits<float>::max());
    if (radius < args->query->radius) {
      args->query->radius = radius;
      return true;
    }
  }
  return false;
}

}  // namespace

TriangleMeshIndex::TriangleMeshIndex(
    const std::vector<Eigen::Vector3d>& vertices,
    const std::vector<Eigen::Vector3i>& triangles)
    : impl_(std::make_unique<Impl>()) {
  THROW_CHECK(!triangles.empty(), "TriangleMeshIndex: no triangles");
  for (const Eigen::Vector3i& triangle : triangles) {
    for (int k = 0; k < 3; ++k) {
      THROW_CHECK(triangle[k] >= 0 &&
                      static_cast<size_t>(triangle[k]) < vertices.size(),
                  "TriangleMeshIndex: vertex index "
                      << triangle[k] << " out of range (" << vertices.size()
                      << " vertices)");
    }
  }
  impl_->vertices = vertices;
  impl_->triangles = triangles;
  impl_->origin = Centroid(vertices);

  impl_->device = rtcNewDevice(nullptr);
  THROW_CHECK(impl_->device != nullptr,
              "TriangleMeshIndex: cannot create the Embree device");
  impl_->scene = rtcNewScene(impl_->device);
  RTCGeometry geometry =
      rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree reads 16 bytes from the last vertex: one float of padding.
  float* vertex_buffer = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
      3 * sizeof(float), vertices.size() + 1));
  for (size_t i = 0; i < vertices.size(); ++i) {
    const Eigen::Vector3f local = (vertices[i] - impl_->origin).cast<float>();
    vertex_buffer[3 * i + 0] = local.x();
    vertex_buffer[3 * i + 1] = local.y();
    vertex_buffer[3 * i + 2] = local.z();
  }
  unsigned int* index_buffer = static_cast<unsigned int*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0,
                              RTC_FORMAT_UINT3, 3 * sizeof(unsigned int),
                              triangles.size()));
  for (size_t i = 0; i < triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      index_buffer[3 * i + k] = static_cast<unsigned int>(triangles[i][k]);
    }
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
  THROW_CHECK(rtcGetDeviceError(impl_->device) == RTC_ERROR_NONE,
              "TriangleMeshIndex: Embree failed to build the BVH");
}

TriangleMeshIndex::~TriangleMeshIndex() = default;

std::vector<double> TriangleMeshIndex::NearestDistances(
    const std::vector<Eigen::Vector3d>& queries) const {
  std::vector<double> distances(queries.size());
  ParallelChunks(queries.size(), [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      ClosestPointQuery closest;
      closest.index = this;
      closest.vertices = &impl_->vertices;
      closest.triangles = &impl_->triangles;
      closest.point = queries[i];
      const Eigen::Vector3f local = (queries[i] - impl_->origin).cast<float>();
      RTCPointQuery query;
      query.x = local.x();
      query.y = local.y();
      query.z = local.z();
      query.time = 0.0f;
      query.radius = std::numeric_limits<float>::infinity();
      RTCPointQueryContext context;
      rtcInitPointQueryContext(&context);
      rtcPointQuery(impl_->scene, &query, &context, &ClosestPointCallback,
                    &closest);
      distances[i] = closest.distance;
    }
  });
  return distances;
}

// Points are kept in an Embree BVH; the point query
// visits the points whose bounds meet the shrinking query sphere. Unlike a
// kd-tree (FLANN took milliseconds per query for queries metres away from
// surface-like clouds), BVH traversal stays fast for far queries.
struct PointCloudIndex::Impl {
  Eigen::Vector3d origin;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Impl() {
    if (scene != nullptr) {
      rtcReleaseScene(scene);
    }
    if (device != nullptr) {
      rtcReleaseDevice(device);
    }
  }
};

namespace {

struct NearestPointQuery {
  const std::vector<Eigen::Vector3d>* points;
  Eigen::Vector3d point;
  double distance = std::numeric_limits<double>::infinity();
};

bool NearestPointCallback(RTCPointQueryFunctionArguments* args) {
  NearestPointQuery* query = static_cast<NearestPointQuery*>(args->userPtr);
  const double distance = ((*query->points)[args->primID] - query->point).norm();
  if (distance < query->distance) {
    query->distance = distance;
    const float radius = std::nextafter(static_cast<float>(distance),
                                        std::numeric_limits<float>::max());
    if (radius < args->query->radius) {
      args->query->radius = radius;
      return true;
    }
  }
  return false;
}

}  // namespace

PointCloudIndex::PointCloudIndex(const std::vector<Eigen::Vector3d>& points)
    : points_(points), impl_(std::make_unique<Impl>()) {
  THROW_CHECK(!points.empty(), "PointCloudIndex: no points to index");
  impl_->origin = Centroid(points);
  impl_->device = rtcNewDevice(nullptr);
  THROW_CHECK(impl_->device != nullptr,
              "PointCloudIndex: cannot create the Embree device");
  impl_->scene = rtcNewScene(impl_->device);
  // Each point is a degenerate triangle (i, i, i): Embree's point queries
  // call back for triangles, and a point's bounds are the point itself.
  RTCGeometry geometry =
      rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree reads 16 bytes from the last vertex: one float of padding.
  float* vertex_buffer = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
      3 * sizeof(float), points.size() + 1));
  unsigned int* index_buffer = static_cast<unsigned int*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0,
                              RTC_FORMAT_UINT3, 3 * sizeof(unsigned int),
                              points.size()));
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f local = (points[i] - impl_->origin).cast<float>();
    vertex_buffer[3 * i + 0] = local.x();
    vertex_buffer[3 * i + 1] = local.y();
    vertex_buffer[3 * i + 2] = local.z();
    for (int k = 0; k < 3; ++k) {
      index_buffer[3 * i + k] = static_cast<unsigned int>(i);
    }
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
  THROW_CHECK(rtcGetDeviceError(impl_->device) == RTC_ERROR_NONE,
              "PointCloudIndex: Embree failed to build the BVH");
}

PointCloudIndex::~PointCloudIndex() = default;

std::vector<double> PointCloudIndex::NearestDistances(
    const std::vector<Eigen::Vector3d>& queries) const {
  std::vector<double> distances(queries.size());
  ParallelChunks(queries.size(), [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      NearestPointQuery nearest;
      nearest.points = &points_;
      nearest.point = queries[i];
      const Eigen::Vector3f local = (queries[i] - impl_->origin).cast<float>();
      RTCPointQuery query;
      query.x = local.x();
      query.y = local.y();
      query.z = local.z();
      query.time = 0.0f;
      query.radius = std::numeric_limits<float>::infinity();
      RTCPointQueryContext context;
      rtcInitPointQueryContext(&context);
      rtcPointQuery(impl_->scene, &query, &context, &NearestPointCallback,
                    &nearest);
      distances[i] = nearest.distance;
    }
  });
  return distances;
}

}  // namespace colmap_lidar
