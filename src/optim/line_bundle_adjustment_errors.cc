// Error measures of line_bundle_adjustment.h: a LIDAR edge's and a line
// track's residual under the reconstruction's current poses.
#include "src/optim/line_bundle_adjustment.h"

#include <cmath>
#include <memory>

#include <ceres/ceres.h>

#include "src/optim/cost_functions.h"
#include "src/optim/line_geometry.h"

namespace colmap_lidar {
namespace {

// Whether a line residual block can be built for this observation.
const Image* ObservedImage(const Reconstruction& reconstruction,
                           const LineObservation& observation) {
  return reconstruction.FindImage(observation.image_id);
}

}  // namespace

double ComputeRelativePoseEdgeError(const Reconstruction& reconstruction,
                                    const RelativePoseEdge& edge) {
  const Image* image1 = reconstruction.FindImage(edge.image_id1);
  const Image* image2 = reconstruction.FindImage(edge.image_id2);
  if (image1 == nullptr || image2 == nullptr) {
    return -1.0;
  }
  const std::unique_ptr<ceres::CostFunction> cost(
      RelativeLidarPoseCostFunctor::Create(edge.lidar1_from_lidar2,
                                           edge.cam1_from_lidar,
                                           edge.cam2_from_lidar,
                                           edge.sqrt_information));
  const double* parameters[4] = {
      image1->cam_from_world.rotation.coeffs().data(),
      image1->cam_from_world.translation.data(),
      image2->cam_from_world.rotation.coeffs().data(),
      image2->cam_from_world.translation.data()};
  Eigen::Matrix<double, 6, 1> residuals;
  if (!cost->Evaluate(parameters, residuals.data(), nullptr)) {
    return -1.0;
  }
  return residuals.norm();
}

double ComputeLineReprojectionError(const Reconstruction& reconstruction,
                                    const LineTrack& track) {
  if (!IsLineInitialized(track)) {
    return -1.0;
  }
  double sum = 0.0;
  int count = 0;
  for (const LineObservation& observation : track.observations) {
    const Image* image = ObservedImage(reconstruction, observation);
    if (image == nullptr) {
      continue;
    }
    const auto camera_it = reconstruction.cameras.find(image->camera_id);
    if (camera_it == reconstruction.cameras.end()) {
      continue;
    }
    const Camera& camera = camera_it->second;
    const Eigen::Vector3d image_line = ProjectPluckerToImageLine(
        camera, TransformPlucker(image->cam_from_world, track.plucker_in_world));
    for (const Eigen::Vector2d& pixel : {observation.start2D, observation.end2D}) {
      sum += std::abs(
          ImageLinePointDistance(image_line, UndistortPixel(camera, pixel)));
      ++count;
    }
  }
  return count > 0 ? sum / count : -1.0;
}

}  // namespace colmap_lidar
