#include "src/optim/line_track.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "colmap_ext/util/logging.h"
#include "src/optim/line_geometry.h"

namespace colmap_lidar {

bool IsLineInitialized(const LineTrack& track) {
  const double norm = track.plucker_in_world.head<3>().norm();
  return std::isfinite(norm) && norm > 0.0 &&
         track.plucker_in_world.tail<3>().allFinite();
}

bool InitializeLineFromLidar(const Reconstruction& reconstruction,
                             LineTrack* track) {
  std::vector<Eigen::Vector3d> endpoints_in_world;
  for (const LineObservation& observation : track->observations) {
    if (!observation.has_lidar) {
      continue;
    }
    const Image* image = reconstruction.FindImage(observation.image_id);
    if (image == nullptr) {
      return false;
    }
    const Rigid3d world_from_cam = image->cam_from_world.Inverse();
    endpoints_in_world.push_back(world_from_cam * observation.start_in_cam);
    endpoints_in_world.push_back(world_from_cam * observation.end_in_cam);
  }
  if (endpoints_in_world.empty()) {
    return false;
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& point : endpoints_in_world) {
    centroid += point;
  }
  centroid /= static_cast<double>(endpoints_in_world.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& point : endpoints_in_world) {
    covariance += (point - centroid) * (point - centroid).transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  // Eigenvalues increase; the largest is the squared spread along the line.
  constexpr double kMinSpreadM = 1e-3;
  if (solver.eigenvalues()[2] < kMinSpreadM * kMinSpreadM) {
    return false;
  }
  track->plucker_in_world = NormalizePlucker(
      PluckerFromPointAndDirection(centroid, solver.eigenvectors().col(2)));
  return true;
}

bool InitializeLineFromViews(const Reconstruction& reconstruction,
                             LineTrack* track, double min_angle_deg) {
  std::vector<Eigen::Vector4d> planes;
  for (const LineObservation& observation : track->observations) {
    const Image* image = reconstruction.FindImage(observation.image_id);
    if (image == nullptr) {
      return false;
    }
    const auto camera_it = reconstruction.cameras.find(image->camera_id);
    if (camera_it == reconstruction.cameras.end()) {
      return false;
    }
    planes.push_back(ViewingPlaneInWorld(camera_it->second,
                                         image->cam_from_world,
                                         observation.start2D, observation.end2D));
  }
  // The pair of viewing planes with the largest angle between normals.
  double best_sin = 0.0;
  Vector6d best_line = Vector6d::Zero();
  for (size_t i = 0; i < planes.size(); ++i) {
    for (size_t j = i + 1; j < planes.size(); ++j) {
      const Vector6d line = IntersectPlanes(planes[i], planes[j]);
      const double sin_angle = line.head<3>().norm();
      if (sin_angle > best_sin) {
        best_sin = sin_angle;
        best_line = line;
      }
    }
  }
  const double min_angle_rad = min_angle_deg * M_PI / 180.0;
  if (!(best_sin > std::sin(min_angle_rad))) {
    return false;
  }
  track->plucker_in_world = NormalizePlucker(best_line);
  return true;
}

bool ComputeLineSegment(const Reconstruction& reconstruction,
                        LineTrack* track) {
  if (!IsLineInitialized(*track)) {
    return false;
  }
  const Vector6d& line = track->plucker_in_world;
  double min_coordinate = std::numeric_limits<double>::infinity();
  double max_coordinate = -std::numeric_limits<double>::infinity();
  const auto extend = [&](double coordinate) {
    min_coordinate = std::min(min_coordinate, coordinate);
    max_coordinate = std::max(max_coordinate, coordinate);
  };
  for (const LineObservation& observation : track->observations) {
    const Image* image = reconstruction.FindImage(observation.image_id);
    if (image == nullptr) {
      continue;
    }
    const Rigid3d world_from_cam = image->cam_from_world.Inverse();
    if (observation.has_lidar) {
      extend(PluckerLineCoordinate(line, world_from_cam * observation.start_in_cam));
      extend(PluckerLineCoordinate(line, world_from_cam * observation.end_in_cam));
    }
    const auto camera_it = reconstruction.cameras.find(image->camera_id);
    if (camera_it == reconstruction.cameras.end()) {
      continue;
    }
    for (const Eigen::Vector2d& pixel : {observation.start2D, observation.end2D}) {
      const Eigen::Vector3d ray_in_world =
          world_from_cam.rotation *
          camera_it->second.CamFromImg(pixel).homogeneous();
      double coordinate;
      if (ClosestLineCoordinateToRay(line, world_from_cam.translation,
                                     ray_in_world, &coordinate)) {
        extend(coordinate);
      }
    }
  }
  if (!(min_coordinate <= max_coordinate)) {
    return false;
  }
  track->start_in_world = PluckerPointAt(line, min_coordinate);
  track->end_in_world = PluckerPointAt(line, max_coordinate);
  return true;
}

Line3D LineTrackToLine3D(const LineTrack& track) {
  Line3D line3D;
  line3D.start_in_world = track.start_in_world;
  line3D.end_in_world = track.end_in_world;
  line3D.error = track.error;
  line3D.track.reserve(track.observations.size());
  for (const LineObservation& observation : track.observations) {
    LineTrackElement element;
    element.image_id = observation.image_id;
    element.line2D_idx = observation.line2D_idx;
    line3D.track.push_back(element);
  }
  return line3D;
}

void SetReconstructionLines(const std::vector<LineTrack>& tracks,
                            Reconstruction* reconstruction) {
  std::map<line3D_t, Line3D> lines3D;
  for (const LineTrack& track : tracks) {
    THROW_CHECK(track.line3D_id != kInvalidLine3DId,
                "Line track with an invalid line3D_id");
    THROW_CHECK(lines3D.emplace(track.line3D_id, LineTrackToLine3D(track)).second,
                "Duplicate line3D_id " << track.line3D_id);
  }
  reconstruction->lines3D = std::move(lines3D);
}

}  // namespace colmap_lidar
