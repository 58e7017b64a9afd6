#include "src/mesh/synthetic_box_scene.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <unordered_map>

#include <Eigen/Geometry>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/mvs/workspace.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"

namespace colmap_lidar {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Face {
  Eigen::Vector3d origin;
  Eigen::Vector3d u;  // Edge vectors spanning the rectangle.
  Eigen::Vector3d v;
  Eigen::Vector3d normal;
  double Area() const { return u.cross(v).norm(); }
};

// Top and the four sides of the box, normals outwards.
std::vector<Face> BoxFaces(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d d = hi - lo;
  const Eigen::Vector3d ex(d.x(), 0, 0), ey(0, d.y(), 0), ez(0, 0, d.z());
  return {
      {Eigen::Vector3d(lo.x(), lo.y(), hi.z()), ex, ey, Eigen::Vector3d::UnitZ()},
      {lo, ey, ez, -Eigen::Vector3d::UnitX()},
      {Eigen::Vector3d(hi.x(), lo.y(), lo.z()), ey, ez, Eigen::Vector3d::UnitX()},
      {lo, ex, ez, -Eigen::Vector3d::UnitY()},
      {Eigen::Vector3d(lo.x(), hi.y(), lo.z()), ex, ez, Eigen::Vector3d::UnitY()},
  };
}

bool InFootprint(const SyntheticBoxSceneOptions& options,
                 const Eigen::Vector3d& point) {
  return point.x() > options.box_min.x() && point.x() < options.box_max.x() &&
         point.y() > options.box_min.y() && point.y() < options.box_max.y();
}

// Entry/exit parameters of the line from + t * dir through the box.
bool IntersectBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                  const Eigen::Vector3d& from, const Eigen::Vector3d& dir,
                  double* t_enter, double* t_exit) {
  double t0 = -1e300, t1 = 1e300;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(dir[k]) < 1e-300) {
      if (from[k] < lo[k] || from[k] > hi[k]) return false;
      continue;
    }
    double a = (lo[k] - from[k]) / dir[k];
    double b = (hi[k] - from[k]) / dir[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  *t_enter = t0;
  *t_exit = t1;
  return t0 <= t1;
}

}  // namespace

SyntheticBoxScene::SyntheticBoxScene(const SyntheticBoxSceneOptions& options)
    : options_(options) {
  Camera camera = Camera::FromModelName(
      "PINHOLE", options.image_width, options.image_height,
      {options.focal_length_px, options.focal_length_px,
       options.image_width / 2.0, options.image_height / 2.0});
  camera.camera_id = 1;
  model_.cameras[1] = camera;
  const Eigen::Vector3d look_at(
      0, 0, 0.5 * (options.box_min.z() + options.box_max.z()));
  for (int i = 0; i < options.num_cameras; ++i) {
    const double angle = 2 * kPi * i / options.num_cameras;
    const Eigen::Vector3d center(options.ring_radius_m * std::cos(angle),
                                 options.ring_radius_m * std::sin(angle),
                                 options.camera_height_m);
    const Eigen::Vector3d z = (look_at - center).normalized();
    const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector3d y = z.cross(x);
    Eigen::Matrix3d rotation;
    rotation.row(0) = x;
    rotation.row(1) = y;
    rotation.row(2) = z;
    Image image;
    image.image_id = i + 1;
    char name[32];
    std::snprintf(name, sizeof(name), "image_%03d.png", i);
    image.name = name;
    image.camera_id = 1;
    image.cam_from_world =
        Rigid3d(Eigen::Quaterniond(rotation), -(rotation * center));
    model_.images.push_back(image);
  }
}

bool SyntheticBoxScene::SegmentHitsBox(const Eigen::Vector3d& from,
                                       const Eigen::Vector3d& to) const {
  const Eigen::Vector3d shrink = Eigen::Vector3d::Constant(1e-7);
  double t_enter, t_exit;
  if (!IntersectBox(options_.box_min + shrink, options_.box_max - shrink, from,
                    to - from, &t_enter, &t_exit)) {
    return false;
  }
  return t_exit > 0 && t_enter < 1.0 - 1e-9;
}

std::vector<uint32_t> SyntheticBoxScene::VisibleCameras(
    const Eigen::Vector3d& point, const Eigen::Vector3d& normal) const {
  std::vector<uint32_t> cameras;
  const Camera& camera = model_.cameras.at(1);
  for (size_t i = 0; i < model_.images.size(); ++i) {
    const Image& image = model_.images[i];
    const Eigen::Vector3d center = image.ProjectionCenter();
    if (normal.dot(center - point) <= 0) continue;
    const Eigen::Vector3d point_in_cam = image.cam_from_world * point;
    if (point_in_cam.z() <= 0) continue;
    const Eigen::Vector2d pixel = camera.ImgFromCam(point_in_cam);
    if (pixel.x() < 0 || pixel.y() < 0 || pixel.x() >= camera.width ||
        pixel.y() >= camera.height) {
      continue;
    }
    if (SegmentHitsBox(center, point)) continue;
    cameras.push_back(static_cast<uint32_t>(i));
  }
  return cameras;
}

SyntheticPoints SyntheticBoxScene::SampleVisualPoints(int min_num_views) const {
  std::mt19937 rng(options_.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, options_.noise_m);
  SyntheticPoints points;
  auto add = [&](const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
    std::vector<uint32_t> cameras = VisibleCameras(point, normal);
    if (static_cast<int>(cameras.size()) < min_num_views) return;
    Eigen::Vector3d noisy = point;
    if (options_.noise_m > 0) {
      noisy += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    }
    points.positions.push_back(noisy);
    points.normals.push_back(normal);
    points.visibility.push_back(std::move(cameras));
  };
  for (const Face& face : BoxFaces(options_.box_min, options_.box_max)) {
    const int count = static_cast<int>(
        face.Area() / (options_.box_spacing_m * options_.box_spacing_m));
    for (int i = 0; i < count; ++i) {
      add(face.origin + uniform(rng) * face.u + uniform(rng) * face.v,
          face.normal);
    }
  }
  const double size = 2 * options_.ground_half_size_m;
  const int count = static_cast<int>(
      size * size / (options_.ground_spacing_m * options_.ground_spacing_m));
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d point((uniform(rng) - 0.5) * size,
                                (uniform(rng) - 0.5) * size, 0.0);
    if (InFootprint(options_, point)) continue;
    add(point, Eigen::Vector3d::UnitZ());
  }
  return points;
}

SyntheticPoints SyntheticBoxScene::SampleTrueSurface(double spacing_m,
                                                     int min_num_views) const {
  SyntheticPoints points;
  auto add = [&](const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
    std::vector<uint32_t> cameras = VisibleCameras(point, normal);
    if (static_cast<int>(cameras.size()) < min_num_views) return;
    points.positions.push_back(point);
    points.normals.push_back(normal);
    points.visibility.push_back(std::move(cameras));
  };
  for (const Face& face : BoxFaces(options_.box_min, options_.box_max)) {
    const int nu = std::max(1, static_cast<int>(face.u.norm() / spacing_m));
    const int nv = std::max(1, static_cast<int>(face.v.norm() / spacing_m));
    for (int i = 0; i < nu; ++i) {
      for (int j = 0; j < nv; ++j) {
        add(face.origin + (i + 0.5) / nu * face.u + (j + 0.5) / nv * face.v,
            face.normal);
      }
    }
  }
  const int n = static_cast<int>(2 * options_.ground_half_size_m / spacing_m);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector3d point(
          -options_.ground_half_size_m + (i + 0.5) * spacing_m,
          -options_.ground_half_size_m + (j + 0.5) * spacing_m, 0.0);
      if (InFootprint(options_, point)) continue;
      add(point, Eigen::Vector3d::UnitZ());
    }
  }
  return points;
}

double SyntheticBoxScene::DistanceToSurface(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d& lo = options_.box_min;
  const Eigen::Vector3d& hi = options_.box_max;
  double box_distance;
  const Eigen::Vector3d clamped = point.cwiseMax(lo).cwiseMin(hi);
  if (clamped != point) {
    box_distance = (point - clamped).norm();
  } else {
    box_distance = std::min({hi.z() - point.z(), point.x() - lo.x(),
                             hi.x() - point.x(), point.y() - lo.y(),
                             hi.y() - point.y()});
  }
  const double g = options_.ground_half_size_m;
  const Eigen::Vector3d on_ground(std::clamp(point.x(), -g, g),
                                  std::clamp(point.y(), -g, g), 0.0);
  return std::min(box_distance, (point - on_ground).norm());
}

Eigen::Vector3d SyntheticBoxScene::LidarOrigin(int frame,
                                               double lidar_drop_m) const {
  return model_.images.at(frame).ProjectionCenter() -
         lidar_drop_m * Eigen::Vector3d::UnitZ();
}

SyntheticBoxScene::LidarVoxels SyntheticBoxScene::SimulateLidar(
    int num_frames, double angular_step_deg, double voxel_size_m,
    double range_noise_m) const {
  std::mt19937 rng(options_.seed + 7);
  std::normal_distribution<double> noise(0.0, range_noise_m);
  struct Accumulator {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    uint32_t count = 0;
    std::set<uint32_t> frames;
  };
  std::map<std::array<int64_t, 3>, Accumulator> voxels;
  const double g = options_.ground_half_size_m;
  for (int frame = 0; frame < num_frames; ++frame) {
    const Eigen::Vector3d origin = LidarOrigin(frame);
    for (double elevation = -60; elevation <= 10; elevation += angular_step_deg) {
      for (double azimuth = 0; azimuth < 360; azimuth += angular_step_deg) {
        const double e = elevation * kPi / 180, a = azimuth * kPi / 180;
        const Eigen::Vector3d dir(std::cos(e) * std::cos(a),
                                  std::cos(e) * std::sin(a), std::sin(e));
        double t = 1e300;
        double t_enter, t_exit;
        if (IntersectBox(options_.box_min, options_.box_max, origin, dir,
                         &t_enter, &t_exit) &&
            t_enter > 0) {
          t = t_enter;
        }
        if (dir.z() < 0) {
          const double t_ground = -origin.z() / dir.z();
          const Eigen::Vector3d hit = origin + t_ground * dir;
          if (t_ground < t && std::abs(hit.x()) <= g && std::abs(hit.y()) <= g) {
            t = t_ground;
          }
        }
        if (t == 1e300) continue;
        const Eigen::Vector3d point =
            origin + (t + (range_noise_m > 0 ? noise(rng) : 0.0)) * dir;
        const std::array<int64_t, 3> key = {
            static_cast<int64_t>(std::floor(point.x() / voxel_size_m)),
            static_cast<int64_t>(std::floor(point.y() / voxel_size_m)),
            static_cast<int64_t>(std::floor(point.z() / voxel_size_m))};
        Accumulator& voxel = voxels[key];
        voxel.sum += point;
        ++voxel.count;
        voxel.frames.insert(frame);
      }
    }
  }
  LidarVoxels result;
  for (const auto& [key, voxel] : voxels) {
    result.positions.push_back(voxel.sum / voxel.count);
    result.counts.push_back(voxel.count);
    result.frames.emplace_back(voxel.frames.begin(), voxel.frames.end());
  }
  return result;
}

std::vector<Line3D> SyntheticBoxScene::BoxEdgeLines() const {
  const Eigen::Vector3d& lo = options_.box_min;
  const Eigen::Vector3d& hi = options_.box_max;
  std::vector<Line3D> lines;
  // Each edge: two corners and the normals of its two surfaces.
  auto add = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                 const Eigen::Vector3d& n1, const Eigen::Vector3d& n2) {
    const Eigen::Vector3d middle = 0.5 * (a + b);
    std::set<uint32_t> cameras;
    for (const Eigen::Vector3d& normal : {n1, n2}) {
      for (const uint32_t camera : VisibleCameras(middle, normal)) {
        cameras.insert(camera);
      }
    }
    if (cameras.size() < 2) return;
    Line3D line;
    line.start_in_world = a;
    line.end_in_world = b;
    for (const uint32_t camera : cameras) {
      line.track.push_back({model_.images[camera].image_id, 0});
    }
    lines.push_back(line);
  };
  const Eigen::Vector3d ux = Eigen::Vector3d::UnitX(), uy = Eigen::Vector3d::UnitY(),
                        uz = Eigen::Vector3d::UnitZ();
  for (const double z : {lo.z(), hi.z()}) {
    const Eigen::Vector3d other = z == hi.z() ? uz : uz;  // Top or ground.
    add({lo.x(), lo.y(), z}, {hi.x(), lo.y(), z}, -uy, other);
    add({lo.x(), hi.y(), z}, {hi.x(), hi.y(), z}, uy, other);
    add({lo.x(), lo.y(), z}, {lo.x(), hi.y(), z}, -ux, other);
    add({hi.x(), lo.y(), z}, {hi.x(), hi.y(), z}, ux, other);
  }
  for (const double x : {lo.x(), hi.x()}) {
    for (const double y : {lo.y(), hi.y()}) {
      add({x, y, lo.z()}, {x, y, hi.z()}, x == lo.x() ? -ux : ux,
          y == lo.y() ? -uy : uy);
    }
  }
  return lines;
}

void SyntheticBoxScene::WriteWorkspace(const std::string& workspace_path,
                                       const SyntheticPoints& points,
                                       const LidarVoxels* lidar) const {
  CreateDirIfNotExists(workspace_path);
  const DenseWorkspace workspace(workspace_path);
  CreateDirIfNotExists(workspace.SparseDir());
  WriteReconstruction(workspace.SparseDir(), model_, ModelFormat::kText);
  std::vector<PlyPoint> ply_points(points.positions.size());
  for (size_t i = 0; i < ply_points.size(); ++i) {
    ply_points[i].xyz = points.positions[i].cast<float>();
    ply_points[i].normal = points.normals[i].cast<float>();
    ply_points[i].rgb = {128, 128, 128};
  }
  WriteColmapPlyPoints(workspace.FusedPlyPath(), ply_points);
  WriteFusedVis(workspace.FusedVisPath(), points.visibility);
  if (lidar == nullptr) return;
  PlyData data;
  std::vector<double> columns[7];
  for (size_t i = 0; i < lidar->positions.size(); ++i) {
    for (int k = 0; k < 3; ++k) columns[k].push_back(lidar->positions[i][k]);
    columns[3].push_back(0);
    columns[4].push_back(0);
    columns[5].push_back(1);
    columns[6].push_back(lidar->counts[i]);
  }
  const char* names[6] = {"x", "y", "z", "nx", "ny", "nz"};
  for (int k = 0; k < 6; ++k) {
    data.AddColumn(names[k], PlyScalarType::kFloat32, columns[k]);
  }
  data.AddColumn("count", PlyScalarType::kUInt32, columns[6]);
  WritePly(LidarFusedPlyPath(workspace_path), data);
  WriteFusedVis(LidarFusedVisPath(workspace_path), lidar->frames);
  std::set<uint32_t> frames;
  for (const auto& voxel_frames : lidar->frames) {
    frames.insert(voxel_frames.begin(), voxel_frames.end());
  }
  std::vector<std::pair<std::string, Eigen::Vector3d>> origins;
  for (const uint32_t frame : frames) {
    origins.emplace_back(model_.images.at(frame).name, LidarOrigin(frame));
  }
  WriteLidarOrigins(LidarOriginsPath(workspace_path), origins);
}

struct MeshDistance::Impl {
  using K = CGAL::Simple_cartesian<double>;
  using Triangle = K::Triangle_3;
  using Primitive =
      CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
  std::vector<Triangle> triangles;
  Tree tree;
};

MeshDistance::MeshDistance(const TriangleMesh& mesh) : impl_(new Impl) {
  THROW_CHECK(!mesh.faces.empty(), "MeshDistance of an empty mesh");
  for (const auto& face : mesh.faces) {
    const auto& a = mesh.vertices[face[0]];
    const auto& b = mesh.vertices[face[1]];
    const auto& c = mesh.vertices[face[2]];
    impl_->triangles.emplace_back(Impl::K::Point_3(a.x(), a.y(), a.z()),
                                  Impl::K::Point_3(b.x(), b.y(), b.z()),
                                  Impl::K::Point_3(c.x(), c.y(), c.z()));
  }
  impl_->tree.insert(impl_->triangles.begin(), impl_->triangles.end());
  impl_->tree.accelerate_distance_queries();
}

MeshDistance::~MeshDistance() = default;

double MeshDistance::Distance(const Eigen::Vector3d& point) const {
  return std::sqrt(impl_->tree.squared_distance(
      Impl::K::Point_3(point.x(), point.y(), point.z())));
}

double Percentile(std::vector<double> values, double percent) {
  if (values.empty()) return 0;
  const size_t idx = std::min(values.size() - 1,
                              static_cast<size_t>(percent / 100 * values.size()));
  std::nth_element(values.begin(), values.begin() + idx, values.end());
  return values[idx];
}

std::vector<double> FaceDistancesToSurface(const SyntheticBoxScene& scene,
                                           const TriangleMesh& mesh) {
  std::vector<double> distances;
  for (const auto& face : mesh.faces) {
    const Eigen::Vector3d& a = mesh.vertices[face[0]];
    const Eigen::Vector3d& b = mesh.vertices[face[1]];
    const Eigen::Vector3d& c = mesh.vertices[face[2]];
    for (const Eigen::Vector3d& point :
         {Eigen::Vector3d((a + b + c) / 3), Eigen::Vector3d((a + b) / 2),
          Eigen::Vector3d((b + c) / 2), Eigen::Vector3d((a + c) / 2)}) {
      distances.push_back(scene.DistanceToSurface(point));
    }
  }
  return distances;
}

double SurfaceCoverage(const SyntheticBoxScene& scene, const TriangleMesh& mesh,
                       double threshold, double spacing) {
  const SyntheticPoints truth = scene.SampleTrueSurface(spacing, 2);
  const MeshDistance distance(mesh);
  size_t num_covered = 0;
  for (const Eigen::Vector3d& point : truth.positions) {
    num_covered += distance.Distance(point) <= threshold ? 1 : 0;
  }
  return static_cast<double>(num_covered) / truth.positions.size();
}

MeshingInput MakeVisualMeshingInput(const SyntheticBoxScene& scene,
                                    const SyntheticPoints& points) {
  MeshingInput input;
  AddCameraSensors(scene.Model(), &input);
  AddVisualPoints(MeshingInputOptions(), points.positions, points.visibility,
                  &input);
  return input;
}

}  // namespace colmap_lidar
