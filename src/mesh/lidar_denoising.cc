#include "src/mesh/lidar_denoising.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/parallel.h"
#include "src/mesh/local_plane.h"
#include "src/mesh/radius_grid.h"

namespace colmap_lidar {

bool LidarDenoisingOptions::Check() const {
  if (!(radius_m >= 0)) {
    LOG(ERROR) << "LIDAR denoising radius must be >= 0";
    return false;
  }
  if (!(max_plane_std_m > 0)) {
    LOG(ERROR) << "LIDAR denoising max_plane_std_m must be > 0";
    return false;
  }
  if (!(plane_std_factor >= 0) || !std::isfinite(plane_std_factor)) {
    LOG(ERROR) << "LIDAR denoising plane_std_factor must be >= 0";
    return false;
  }
  if (min_neighbors < 3) {
    LOG(ERROR) << "LIDAR denoising min_neighbors must be >= 3";
    return false;
  }
  return true;
}

LidarDenoisingSummary DenoiseLidarVoxels(const LidarDenoisingOptions& options,
                                         const std::vector<uint32_t>& counts,
                                         int num_threads,
                                         std::vector<Eigen::Vector3d>* positions) {
  THROW_CHECK(options.Check(), "Invalid LIDAR denoising options");
  THROW_CHECK(counts.size() == positions->size(),
              "LIDAR denoising: counts and positions differ in length");
  LidarDenoisingSummary summary;
  if (options.radius_m == 0 || positions->empty()) return summary;
  const std::vector<Eigen::Vector3d>& input = *positions;
  const RadiusGrid grid(input, options.radius_m);
  // Pass 1: the plane of every neighbourhood with enough voxels (normal,
  // offset of the plane from the voxel along it, variance across it).
  struct LocalPlane {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    double offset = 0;
    double variance = -1;  // < 0: too few neighbours.
  };
  std::vector<LocalPlane> planes(input.size());
  constexpr int kBlock = 4096;
  const int num_blocks =
      static_cast<int>((input.size() + kBlock - 1) / kBlock);
  ParallelFor(0, num_blocks, num_threads, [&](int block) {
    const size_t end = std::min(input.size(), (block + 1) * size_t{kBlock});
    for (size_t i = block * size_t{kBlock}; i < end; ++i) {
      // Count-weighted first and second moments of the neighbourhood.
      const NeighbourhoodMoments moments = ComputeNeighbourhoodMoments(
          input, grid, input[i], options.radius_m, &counts);
      if (moments.num_neighbors < options.min_neighbors) continue;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(
          moments.covariance);
      // input[i] is the origin of the offsets: the plane passes through
      // `mean`.
      planes[i].normal = solver.eigenvectors().col(0);
      planes[i].offset = planes[i].normal.dot(moments.mean);
      planes[i].variance = std::max(0.0, solver.eigenvalues()(0));
    }
  });

  // The threshold from the median deviation (the noise floor).
  std::vector<double> deviations;
  deviations.reserve(input.size());
  for (const LocalPlane& plane : planes) {
    if (plane.variance >= 0) deviations.push_back(std::sqrt(plane.variance));
  }
  if (!deviations.empty()) {
    auto middle = deviations.begin() + deviations.size() / 2;
    std::nth_element(deviations.begin(), middle, deviations.end());
    summary.median_plane_std_m = *middle;
  }
  summary.plane_std_threshold_m =
      std::max(options.max_plane_std_m,
               options.plane_std_factor * summary.median_plane_std_m);
  const double max_variance =
      summary.plane_std_threshold_m * summary.plane_std_threshold_m;

  // Pass 2: projection of the voxels whose neighbourhood is planar.
  std::vector<Eigen::Vector3d> output(input);
  std::vector<uint8_t> projected(input.size(), 0);
  for (size_t i = 0; i < input.size(); ++i) {
    const LocalPlane& plane = planes[i];
    if (!(plane.variance >= 0 && plane.variance < max_variance)) continue;
    output[i] = input[i] + plane.normal * plane.offset;
    projected[i] = 1;
  }
  double displacement_sum = 0;
  for (size_t i = 0; i < input.size(); ++i) {
    if (!projected[i]) continue;
    ++summary.num_projected;
    displacement_sum += (output[i] - input[i]).norm();
  }
  if (summary.num_projected > 0) {
    summary.mean_displacement_m = displacement_sum / summary.num_projected;
  }
  *positions = std::move(output);
  LOG(INFO) << "LIDAR denoising: " << summary.num_projected << " of "
            << input.size() << " voxels projected onto their local plane (r "
            << options.radius_m << " m, planar below "
            << summary.plane_std_threshold_m << " m = max("
            << options.max_plane_std_m << ", " << options.plane_std_factor
            << " x median " << summary.median_plane_std_m
            << " m)), mean displacement " << summary.mean_displacement_m
            << " m";
  return summary;
}

}  // namespace colmap_lidar
