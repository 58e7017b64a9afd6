#include "src/synth/lidar_simulator.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <unordered_set>

#include <glog/logging.h>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/parallel.h"
#include "src/synth/random.h"
#include "src/synth/textures.h"

namespace colmap_lidar {
namespace {

double DegToRad(double deg) { return deg * M_PI / 180.0; }

constexpr double kSurveyMinElevationDeg = -60.0;
constexpr double kSurveyMaxElevationDeg = 90.0;
constexpr double kSurveyMaxRange = 60.0;
constexpr double kSurveyMinRange = 0.5;

// Packs a voxel index (each coordinate within +-2^20) into 63 bits.
uint64_t VoxelKey(const Eigen::Vector3d& point, double voxel_size) {
  uint64_t key = 0;
  for (int k = 0; k < 3; ++k) {
    const int64_t index =
        static_cast<int64_t>(std::floor(point(k) / voxel_size)) + (1 << 20);
    key = (key << 21) | (static_cast<uint64_t>(index) & 0x1FFFFF);
  }
  return key;
}

}  // namespace

std::string LidarModelNames() {
  return "VLP-16, HDL-32E, OS1-64, HDL-64E, OS1-128, custom";
}

bool IsKnownLidarModel(const std::string& model) {
  return model == "VLP-16" || model == "HDL-32E" || model == "OS1-64" ||
         model == "HDL-64E" || model == "OS1-128" || model == "custom";
}

LidarGeometry SynthLidarGeometry(const SynthesisOptions& options) {
  LidarGeometry geometry;
  geometry.model = options.lidar_model;
  const auto add_uniform = [&geometry](int rings, double min_deg,
                                       double max_deg) {
    // Same expression as the original uniform layout (bit-identical
    // elevations for custom / OS1-64).
    for (int ring = 0; ring < rings; ++ring) {
      geometry.ring_elevations_deg.push_back(
          rings > 1 ? min_deg + (max_deg - min_deg) * ring / (rings - 1)
                    : 0.5 * (min_deg + max_deg));
    }
  };
  const std::string& model = options.lidar_model;
  if (model == "VLP-16") {
    add_uniform(16, -15.0, 15.0);
    geometry.columns = 1800;
  } else if (model == "HDL-32E") {
    add_uniform(32, -30.67, 10.67);
    geometry.columns = 2172;
  } else if (model == "OS1-64") {
    add_uniform(64, -16.6, 16.6);
    geometry.columns = 1024;
  } else if (model == "HDL-64E") {
    add_uniform(32, -24.9, -8.87);  // Lower block.
    add_uniform(32, -8.33, 2.0);    // Upper block.
    geometry.columns = 2048;
  } else if (model == "OS1-128") {
    add_uniform(128, -22.5, 22.5);
    geometry.columns = 1024;
  } else if (model == "custom") {
    add_uniform(options.lidar_rings, options.lidar_vertical_fov_min_deg,
                options.lidar_vertical_fov_max_deg);
    geometry.columns = options.lidar_columns;
  } else {
    THROW_CHECK(false, "Synthesis.lidar_model must be one of "
                           << LidarModelNames() << ", got '" << model << "'");
  }
  THROW_CHECK(!geometry.ring_elevations_deg.empty() && geometry.columns >= 1,
              "Synthesis.lidar_model " << model
                                       << ": no rings or columns");
  return geometry;
}

Eigen::Vector3d LidarBeamDirection(const LidarGeometry& geometry, int ring,
                                   int column) {
  const double elevation = DegToRad(geometry.ring_elevations_deg[ring]);
  const double azimuth = 2.0 * M_PI * column / geometry.columns;
  return Eigen::Vector3d(std::cos(elevation) * std::cos(azimuth),
                         std::cos(elevation) * std::sin(azimuth),
                         std::sin(elevation));
}

LidarScan SimulateLidarScan(const RayTracer& tracer,
                            const Rigid3d& world_from_lidar,
                            const SynthesisOptions& options, int frame_index) {
  const SceneMesh& mesh = tracer.mesh();
  const CounterRng noise(options.seed,
                         StreamId(RandomStream::kLidarNoise, frame_index));
  const CounterRng dropout(options.seed,
                           StreamId(RandomStream::kLidarDropout, frame_index));
  const Eigen::Matrix3d rotation = world_from_lidar.rotation.toRotationMatrix();
  const Eigen::Vector3d origin = world_from_lidar.translation;
  const LidarGeometry geometry = SynthLidarGeometry(options);
  const int rings = static_cast<int>(geometry.ring_elevations_deg.size());
  const int columns = geometry.columns;
  const bool simulate_dropout = options.lidar_dropout_probability > 0.0 ||
                                options.lidar_grazing_dropout > 0.0;
  // Per beam: range (<= 0: no return) and intensity.
  std::vector<float> ranges(static_cast<size_t>(rings) * columns, 0.0f);
  std::vector<float> intensities(ranges.size(), 0.0f);
  std::vector<Eigen::Vector3f> points(ranges.size());
  ParallelFor(0, columns, options.num_threads, [&](int column) {
    for (int ring = 0; ring < rings; ++ring) {
      const size_t beam = static_cast<size_t>(column) * rings + ring;
      const Eigen::Vector3d direction_in_lidar =
          LidarBeamDirection(geometry, ring, column);
      const Eigen::Vector3d direction = rotation * direction_in_lidar;
      const RayHit hit = tracer.Intersect(origin, direction,
                                          options.lidar_min_range_m,
                                          options.lidar_max_range_m);
      if (!hit.Valid()) continue;
      const double range =
          hit.distance + options.lidar_range_noise_m * noise.Normal(beam);
      if (range <= 0.0) continue;
      const Eigen::Vector3d point_in_world = origin + hit.distance * direction;
      const Eigen::Vector3d normal = mesh.normals[hit.triangle].cast<double>();
      const double cosine = std::abs(normal.dot(direction));
      if (simulate_dropout) {
        const double keep_probability =
            (1.0 - options.lidar_dropout_probability) *
            (1.0 - options.lidar_grazing_dropout * (1.0 - cosine));
        if (dropout.Uniform(beam) >= keep_probability) continue;
      }
      const Eigen::Vector3d albedo = MaterialAlbedo(
          mesh.materials[hit.triangle],
          SurfaceCoordinates(point_in_world, normal),
          mesh.texture_seeds[hit.triangle]);
      ranges[beam] = static_cast<float>(range);
      intensities[beam] =
          static_cast<float>(std::clamp(albedo.mean() * cosine, 0.0, 1.0));
      points[beam] = (range * direction_in_lidar).cast<float>();
    }
  });
  LidarScan scan;
  for (int column = 0; column < columns; ++column) {
    for (int ring = 0; ring < rings; ++ring) {
      const size_t beam = static_cast<size_t>(column) * rings + ring;
      if (ranges[beam] <= 0.0f) continue;
      scan.points.push_back(points[beam]);
      scan.intensities.push_back(intensities[beam]);
      scan.rings.push_back(static_cast<uint16_t>(ring));
    }
  }
  return scan;
}

std::vector<Eigen::Vector3f> SimulateSurvey(
    const RayTracer& tracer, const std::vector<Eigen::Vector3d>& stations,
    const SynthesisOptions& options) {
  const double step = DegToRad(options.survey_angular_step_deg);
  const int num_azimuths = static_cast<int>(std::round(2.0 * M_PI / step));
  const int num_elevations = static_cast<int>(std::floor(
      DegToRad(kSurveyMaxElevationDeg - kSurveyMinElevationDeg) / step));
  std::vector<Eigen::Vector3f> result;
  std::unordered_set<uint64_t> occupied;
  for (size_t s = 0; s < stations.size(); ++s) {
    const Eigen::Vector3d& station = stations[s];
    const CounterRng noise(options.seed,
                           StreamId(RandomStream::kSurveyNoise, s));
    std::vector<std::vector<Eigen::Vector3f>> rows(num_elevations);
    ParallelFor(0, num_elevations, options.num_threads, [&](int e) {
      const double elevation = DegToRad(kSurveyMinElevationDeg) + e * step;
      // Fewer azimuth steps towards the zenith keep the spacing uniform.
      const int row_azimuths = std::max(
          1, static_cast<int>(std::round(num_azimuths * std::cos(elevation))));
      std::vector<Eigen::Vector3f>& row = rows[e];
      for (int a = 0; a < row_azimuths; ++a) {
        const double azimuth = 2.0 * M_PI * a / row_azimuths;
        const Eigen::Vector3d direction(std::cos(elevation) * std::cos(azimuth),
                                        std::cos(elevation) * std::sin(azimuth),
                                        std::sin(elevation));
        const RayHit hit = tracer.Intersect(station, direction,
                                            kSurveyMinRange, kSurveyMaxRange);
        if (!hit.Valid()) continue;
        const uint64_t index = static_cast<uint64_t>(e) * num_azimuths + a;
        const double range =
            hit.distance + options.survey_range_noise_m * noise.Normal(index);
        row.push_back((station + range * direction).cast<float>());
      }
    });
    size_t num_hits = 0;
    for (const auto& row : rows) {
      num_hits += row.size();
      for (const Eigen::Vector3f& point : row) {
        if (occupied.insert(VoxelKey(point.cast<double>(),
                                     options.survey_voxel_size_m))
                .second) {
          result.push_back(point);
        }
      }
    }
    LOG(INFO) << "Survey station " << s << " at (" << station.transpose()
              << "): " << num_hits << " returns, " << result.size()
              << " reference points so far";
  }
  if (result.size() > static_cast<size_t>(options.survey_max_points)) {
    std::vector<size_t> order(result.size());
    std::iota(order.begin(), order.end(), 0);
    std::mt19937_64 generator(
        HashCombine(options.seed, StreamId(RandomStream::kSurveySubsample)));
    std::shuffle(order.begin(), order.end(), generator);
    order.resize(options.survey_max_points);
    std::sort(order.begin(), order.end());
    std::vector<Eigen::Vector3f> subsampled;
    subsampled.reserve(order.size());
    for (size_t index : order) subsampled.push_back(result[index]);
    result = std::move(subsampled);
  }
  return result;
}

}  // namespace colmap_lidar
