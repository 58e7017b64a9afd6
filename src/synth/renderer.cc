#include "src/synth/renderer.h"

#include <algorithm>
#include <cmath>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/parallel.h"
#include "src/synth/random.h"
#include "src/synth/textures.h"

namespace colmap_lidar {
namespace {

const Eigen::Vector3d kSunColour(1.15, 1.08, 0.98);
const Eigen::Vector3d kSkyAmbient(0.30, 0.33, 0.38);

Eigen::Vector3d SkyColour(const Eigen::Vector3d& direction) {
  const double elevation =
      std::clamp(direction.z() / direction.norm(), 0.0, 1.0);
  const Eigen::Vector3d horizon(0.85, 0.88, 0.92);
  const Eigen::Vector3d zenith(0.35, 0.50, 0.80);
  return horizon + (zenith - horizon) * std::sqrt(elevation);
}

// Linear radiance seen along the ray.
Eigen::Vector3d Shade(const RayTracer& tracer, const Eigen::Vector3d& origin,
                      const Eigen::Vector3d& direction,
                      const Eigen::Vector3d& sun) {
  const RayHit hit = tracer.Intersect(origin, direction);
  if (!hit.Valid()) return SkyColour(direction);
  const SceneMesh& mesh = tracer.mesh();
  const Eigen::Vector3d point = origin + hit.distance * direction;
  const Eigen::Vector3d face_normal =
      mesh.normals[hit.triangle].cast<double>();
  const Eigen::Vector3d albedo =
      MaterialAlbedo(mesh.materials[hit.triangle],
                     SurfaceCoordinates(point, face_normal),
                     mesh.texture_seeds[hit.triangle]);
  // Two-sided surfaces: shade the side the ray comes from.
  const Eigen::Vector3d normal =
      face_normal.dot(direction) > 0.0 ? Eigen::Vector3d(-face_normal)
                                       : face_normal;
  double direct = normal.dot(sun);
  if (direct > 0.0 && tracer.Occluded(point + 1e-4 * normal, sun, 0.0)) {
    direct = 0.0;
  }
  const double sky_visibility = 0.75 + 0.25 * normal.z();
  Eigen::Vector3d radiance =
      albedo.cwiseProduct(kSunColour * std::max(0.0, direct) +
                          kSkyAmbient * sky_visibility);
  if (mesh.materials[hit.triangle] == Material::kGlass) {
    // Panes reflect some sky.
    radiance += 0.06 * SkyColour(direction - 2.0 * direction.dot(normal) *
                                                 normal);
  }
  return radiance;
}

double EncodeGamma(double linear) {
  return std::pow(std::clamp(linear, 0.0, 1.0), 1.0 / 2.2);
}

}  // namespace

Eigen::Vector3d SunDirection(const SynthesisOptions& options) {
  const double elevation = options.sun_elevation_deg * M_PI / 180.0;
  const double azimuth = options.sun_azimuth_deg * M_PI / 180.0;
  return Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
                         std::cos(elevation) * std::sin(azimuth),
                         std::sin(elevation));
}

RenderedFrame RenderFrame(const RayTracer& tracer, const Camera& camera,
                          const Rigid3d& world_from_cam,
                          const SynthesisOptions& options, int frame_index,
                          bool render_depth) {
  camera.Check();
  const int width = static_cast<int>(camera.width);
  const int height = static_cast<int>(camera.height);
  const CameraModelId model_id = camera.model_id;
  const double* params = camera.params.data();
  // The ray through image point (x, y) in the camera frame, with z = 1: the
  // model's undistortion (for PINHOLE exactly ((x - cx) / fx, (y - cy) / fy,
  // 1), the arithmetic the renderer always used).
  const auto ray_in_cam = [model_id, params](double x, double y) {
    double u, v, w;
    CameraModelCamFromImg(model_id, params, x, y, &u, &v, &w);
    return Eigen::Vector3d(u / w, v / w, 1.0);
  };
  const Eigen::Matrix3d rotation = world_from_cam.rotation.toRotationMatrix();
  const Eigen::Vector3d origin = world_from_cam.translation;
  const Eigen::Vector3d sun = SunDirection(options);
  const int s = options.supersampling;
  const CounterRng noise(options.seed,
                         StreamId(RandomStream::kImageNoise, frame_index));

  RenderedFrame frame;
  frame.image = cv::Mat(height, width, CV_8UC3);
  if (render_depth) frame.depth = cv::Mat(height, width, CV_32FC1);
  ParallelFor(0, height, options.num_threads, [&](int row) {
    cv::Vec3b* image_row = frame.image.ptr<cv::Vec3b>(row);
    float* depth_row = render_depth ? frame.depth.ptr<float>(row) : nullptr;
    for (int col = 0; col < width; ++col) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int j = 0; j < s; ++j) {
        for (int i = 0; i < s; ++i) {
          const double u = col + (i + 0.5) / s;
          const double v = row + (j + 0.5) / s;
          const Eigen::Vector3d direction = rotation * ray_in_cam(u, v);
          sum += Shade(tracer, origin, direction.normalized(), sun);
        }
      }
      const Eigen::Vector3d linear = sum / (s * s);
      const uint64_t pixel = static_cast<uint64_t>(row) * width + col;
      for (int c = 0; c < 3; ++c) {
        const double value =
            255.0 * EncodeGamma(linear(c)) +
            options.image_noise_stddev * noise.Normal(3 * pixel + c);
        // OpenCV stores BGR: channel 2 - c.
        image_row[col][2 - c] =
            static_cast<uint8_t>(std::clamp(std::lround(value), 0L, 255L));
      }
      if (render_depth) {
        // MVS convention: the ray through (col, row) itself. With a camera
        // direction of z = 1 the ray parameter is the z-depth.
        const Eigen::Vector3d direction = rotation * ray_in_cam(col, row);
        const RayHit hit = tracer.Intersect(origin, direction);
        depth_row[col] = hit.Valid() ? static_cast<float>(hit.distance) : 0.0f;
      }
    }
  });
  return frame;
}

}  // namespace colmap_lidar
