#include "src/sfm/lidar_point_planes.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "src/lidar/gicp_helpers.h"
#include "src/lidar/scan_io.h"
#include "src/lidar/sensor_estimation.h"

namespace colmap_lidar {
namespace {

// Numerical floor of a plane's sigma, metres: a noise-free synthetic scan
// would otherwise give residuals divided by ~0.
constexpr double kMinPlaneSigmaM = 0.002;
// Scans the range noise is measured on (evenly spread over the sequence):
// the estimate needs a few thousand planar points, not every scan.
constexpr size_t kMaxNoiseScans = 8;

}  // namespace

bool LidarPointPlaneOptions::Check() const {
  // Named as lidar_mapper's options (LidarMapper.point_plane_<field>).
#define PLANES_CHECK(condition, name)                                      \
  if (!(condition)) {                                                      \
    LOG(ERROR) << "LidarMapper.point_plane_" #name " is invalid: " << name \
               << " (must satisfy " #condition ")";                        \
    return false;                                                          \
  }
  PLANES_CHECK(min_radius_m > 0.0, min_radius_m);
  PLANES_CHECK(max_radius_range_fraction > 0.0, max_radius_range_fraction);
  PLANES_CHECK(min_neighbors >= 3, min_neighbors);
  PLANES_CHECK(min_spread_fraction > 0.0 && min_spread_fraction < 1.0,
               min_spread_fraction);
  PLANES_CHECK(max_rms_sigmas > 0.0, max_rms_sigmas);
  PLANES_CHECK(max_distance_sigmas > 0.0, max_distance_sigmas);
  PLANES_CHECK(max_range_m > 0.0, max_range_m);
  PLANES_CHECK(num_threads == -1 || num_threads >= 1, num_threads);
#undef PLANES_CHECK
  return true;
}

std::string LidarPointPlaneSummary::ToString() const {
  std::ostringstream stream;
  stream << num_planes << " LIDAR planes for " << num_observations
         << " point observations (" << num_scans << " scans, range noise "
         << range_sigma_m << " m, median plane sigma " << median_plane_sigma_m
         << " m)";
  return stream.str();
}

struct LidarPlaneScans::Scan {
  pcl::PointCloud<pcl::PointXYZ>::Ptr points_in_cam;
  pcl::search::KdTree<pcl::PointXYZ> tree;
};

LidarPlaneScans::LidarPlaneScans(std::vector<LidarPlaneScanInput> scans) {
  Build(std::move(scans));
}

LidarPlaneScans::LidarPlaneScans(const Database& database,
                                 const Reconstruction& model) {
  std::vector<LidarPlaneScanInput> scans;
  for (const Image& image : model.images) {
    const std::optional<LidarScanRecord> record =
        database.ReadLidarScan(image.image_id);
    if (!record) {
      continue;
    }
    LidarPlaneScanInput input;
    input.image_id = image.image_id;
    input.scan =
        ReadLidarScan(LidarScanFilePath(database.path(), record->path));
    input.cam_from_lidar = record->cam_from_lidar;
    scans.push_back(std::move(input));
  }
  Build(std::move(scans));
}

void LidarPlaneScans::Build(std::vector<LidarPlaneScanInput> scans) {
  // The noise is measured on scans spread evenly over the sequence.
  std::sort(scans.begin(), scans.end(),
            [](const LidarPlaneScanInput& a, const LidarPlaneScanInput& b) {
              return a.image_id < b.image_id;
            });
  const size_t noise_stride =
      std::max<size_t>(1, (scans.size() + kMaxNoiseScans - 1) / kMaxNoiseScans);
  std::vector<LidarScan> noise_scans;
  for (size_t k = 0; k < scans.size(); ++k) {
    LidarPlaneScanInput& input = scans[k];
    auto entry = std::make_unique<Scan>();
    entry->points_in_cam.reset(new pcl::PointCloud<pcl::PointXYZ>);
    entry->points_in_cam->reserve(input.scan.size());
    const Eigen::Matrix3f rotation =
        input.cam_from_lidar.rotation.toRotationMatrix().cast<float>();
    const Eigen::Vector3f translation =
        input.cam_from_lidar.translation.cast<float>();
    for (const Eigen::Vector3f& point : input.scan.points) {
      const Eigen::Vector3f in_cam = rotation * point + translation;
      entry->points_in_cam->push_back(
          pcl::PointXYZ(in_cam.x(), in_cam.y(), in_cam.z()));
    }
    if (entry->points_in_cam->empty()) {
      continue;
    }
    entry->tree.setInputCloud(entry->points_in_cam);
    scans_[input.image_id] = std::move(entry);
    if (k % noise_stride == 0) {
      noise_scans.push_back(std::move(input.scan));
    }
  }
  const RangeNoiseEstimate noise =
      EstimateRangeNoise(noise_scans, RangeNoiseOptions());
  range_sigma_m_ = std::max(noise.sigma_m, kMinPlaneSigmaM);
  if (noise.num_voxels == 0 && !scans_.empty()) {
    LOG(WARNING) << "LIDAR planes of points: no planar voxel to measure the "
                    "range noise on; assuming "
                 << range_sigma_m_ << " m";
  }
}

LidarPlaneScans::~LidarPlaneScans() = default;

int LidarPlaneScans::NumScans() const {
  return static_cast<int>(scans_.size());
}

std::vector<PointPlaneObservation> LidarPlaneScans::Associate(
    const Reconstruction& model, int min_track_length,
    const LidarPointPlaneOptions& options,
    LidarPointPlaneSummary* summary) const {
  THROW_CHECK(options.Check(), "LIDAR planes of points: invalid options");
  LidarPointPlaneSummary local_summary;
  local_summary.num_scans = NumScans();
  local_summary.range_sigma_m = range_sigma_m_;

  // One query per observation whose image has a scan.
  std::vector<PointPlaneObservation> queries;
  std::vector<Eigen::Vector3d> queries_in_cam;
  std::vector<const Scan*> query_scans;
  for (const auto& [point3D_id, point3D] : model.points3D) {
    if (static_cast<int>(point3D.track.size()) < min_track_length) {
      continue;
    }
    for (const TrackElement& element : point3D.track) {
      const auto scan_it = scans_.find(element.image_id);
      const Image* image = model.FindImage(element.image_id);
      if (scan_it == scans_.end() || image == nullptr) {
        continue;
      }
      PointPlaneObservation query;
      query.image_id = element.image_id;
      query.point3D_id = point3D_id;
      queries.push_back(query);
      queries_in_cam.push_back(image->cam_from_world * point3D.xyz);
      query_scans.push_back(scan_it->second.get());
    }
  }
  local_summary.num_observations = static_cast<int>(queries.size());

  const double sigma = range_sigma_m_;
  const double first_radius = std::max(options.min_radius_m, 5.0 * sigma);
  std::vector<char> found(queries.size(), 0);
  ParallelFor(
      queries.size(), options.num_threads, [&](size_t begin, size_t end) {
        std::vector<int> indices;
        std::vector<float> squared_distances;
        for (size_t q = begin; q < end; ++q) {
          const Eigen::Vector3d& point = queries_in_cam[q];
          const double range = point.norm();
          if (!std::isfinite(range) || range > options.max_range_m ||
              point.z() <= 0.0) {
            continue;
          }
          const Scan& scan = *query_scans[q];
          const double max_radius = options.max_radius_range_fraction * range;
          const pcl::PointXYZ center(static_cast<float>(point.x()),
                                     static_cast<float>(point.y()),
                                     static_cast<float>(point.z()));
          // Doubling, the last step clamped to max_radius (which is searched).
          for (double radius = std::min(first_radius, max_radius);;
               radius = std::min(2.0 * radius, max_radius)) {
            const bool last = radius >= max_radius;
            scan.tree.radiusSearch(center, radius, indices, squared_distances);
            if (static_cast<int>(indices.size()) < options.min_neighbors) {
              if (last) {
                break;
              }
              continue;
            }
            Eigen::Vector3d mean = Eigen::Vector3d::Zero();
            for (const int index : indices) {
              mean += scan.points_in_cam->points[index]
                          .getVector3fMap()
                          .cast<double>();
            }
            mean /= static_cast<double>(indices.size());
            Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
            for (const int index : indices) {
              const Eigen::Vector3d offset = scan.points_in_cam->points[index]
                                                 .getVector3fMap()
                                                 .cast<double>() -
                                             mean;
              covariance += offset * offset.transpose();
            }
            covariance /= static_cast<double>(indices.size());
            const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(
                covariance);
            const Eigen::Vector3d eigenvalues =
                solver.eigenvalues().cwiseMax(0.0);
            const double min_spread = options.min_spread_fraction * radius;
            if (std::sqrt(eigenvalues[1]) < min_spread) {
              if (last) {
                break;
              }
              continue;  // One ring (a line) so far: widen.
            }
            const double rms = std::sqrt(eigenvalues[0]);
            if (rms > options.max_rms_sigmas * sigma) {
              break;  // Not flat: a crease, clutter.
            }
            const Eigen::Vector3d normal = solver.eigenvectors().col(0);
            const double plane_sigma = std::max(rms, sigma);
            const Eigen::Vector3d offset = point - mean;
            const double distance = normal.dot(offset);
            const double in_plane = (offset - distance * normal).norm();
            if (std::abs(distance) >
                    options.max_distance_sigmas * plane_sigma ||
                in_plane > 0.5 * radius) {
              break;
            }
            PointPlaneObservation& plane = queries[q];
            plane.normal_in_cam = normal;
            plane.offset_m = normal.dot(mean);
            plane.sigma_m = plane_sigma;
            found[q] = 1;
            break;
          }
        }
      });

  std::vector<PointPlaneObservation> planes;
  std::vector<double> sigmas;
  for (size_t q = 0; q < queries.size(); ++q) {
    if (found[q]) {
      planes.push_back(queries[q]);
      sigmas.push_back(queries[q].sigma_m);
    }
  }
  local_summary.num_planes = static_cast<int>(planes.size());
  if (!sigmas.empty()) {
    std::nth_element(sigmas.begin(), sigmas.begin() + sigmas.size() / 2,
                     sigmas.end());
    local_summary.median_plane_sigma_m = sigmas[sigmas.size() / 2];
  }
  if (summary != nullptr) {
    *summary = local_summary;
  }
  return planes;
}

}  // namespace colmap_lidar
