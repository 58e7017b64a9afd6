#include "src/lidar/ring_estimation.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
// Backward azimuth steps up to this size are jitter (per-laser offsets,
// noise), larger ones mean the beam skipped more than half a turn.
constexpr double kMaxBacktrackDeg = 45.0;

double AzimuthDeg(const Eigen::Vector3f& point) {
  return std::atan2(static_cast<double>(point.y()),
                    static_cast<double>(point.x())) *
         kRadToDeg;
}

// a - b wrapped into (-180, 180].
double AngleDiffDeg(const double a, const double b) {
  double diff = std::fmod(a - b, 360.0);
  if (diff > 180.0) {
    diff -= 360.0;
  } else if (diff <= -180.0) {
    diff += 360.0;
  }
  return diff;
}

void CheckNumRings(const int num_rings) {
  THROW_CHECK(num_rings >= 1 && num_rings <= 65535,
              "num_rings must be in [1, 65535], got " << num_rings);
}

}  // namespace

double ElevationDeg(const Eigen::Vector3f& point_in_lidar) {
  const double horizontal = std::hypot(static_cast<double>(point_in_lidar.x()),
                                       static_cast<double>(point_in_lidar.y()));
  return std::atan2(static_cast<double>(point_in_lidar.z()), horizontal) *
         kRadToDeg;
}

std::vector<uint16_t> EstimateRingsFromElevation(
    const LidarScan& scan, const int num_rings, const double min_elevation_deg,
    const double max_elevation_deg) {
  CheckNumRings(num_rings);
  THROW_CHECK(min_elevation_deg < max_elevation_deg,
              "min_elevation_deg (" << min_elevation_deg
                                    << ") must be below max_elevation_deg ("
                                    << max_elevation_deg << ")");
  const double rings_per_deg =
      (num_rings - 1) / (max_elevation_deg - min_elevation_deg);
  std::vector<uint16_t> rings(scan.size());
  for (size_t i = 0; i < scan.size(); ++i) {
    const double ring = std::round(
        (ElevationDeg(scan.points[i]) - min_elevation_deg) * rings_per_deg);
    rings[i] = static_cast<uint16_t>(
        std::clamp(ring, 0.0, static_cast<double>(num_rings - 1)));
  }
  return rings;
}

std::vector<uint16_t> EstimateRingsFromScanOrder(const LidarScan& scan,
                                                 const int num_rings) {
  CheckNumRings(num_rings);
  const size_t num_points = scan.size();
  if (num_points < 2) {
    LOG(WARNING) << "Cannot estimate rings from the order of "
                 << num_points << " points";
    return {};
  }
  std::vector<double> steps(num_points, 0.0);
  double step_sum = 0.0;
  for (size_t i = 1; i < num_points; ++i) {
    steps[i] = AngleDiffDeg(AzimuthDeg(scan.points[i]),
                            AzimuthDeg(scan.points[i - 1]));
    step_sum += steps[i];
  }
  const double direction = (step_sum >= 0.0) ? 1.0 : -1.0;

  // Turn index of every point from the unwrapped azimuth. Small backward
  // steps are kept signed (so jitter does not drift the total) and the turn
  // index follows the running maximum (so jitter at a boundary does not go
  // back to the previous turn).
  std::vector<int> turns(num_points, 0);
  double unwrapped_deg = 0.0;
  double max_unwrapped_deg = 0.0;
  for (size_t i = 1; i < num_points; ++i) {
    double step = direction * steps[i];
    if (step < -kMaxBacktrackDeg) {
      step += 360.0;
    }
    unwrapped_deg += step;
    max_unwrapped_deg = std::max(max_unwrapped_deg, unwrapped_deg);
    turns[i] = static_cast<int>(max_unwrapped_deg / 360.0);
  }
  const int num_turns = turns.back() + 1;
  if (num_turns != num_rings) {
    LOG(WARNING) << "The point order has " << num_turns
                 << " azimuth turns, not " << num_rings
                 << " rings: not one ring after the other";
    return {};
  }

  // Median elevation per turn, then rank the turns by it.
  std::vector<std::vector<double>> elevations(num_turns);
  for (size_t i = 0; i < num_points; ++i) {
    elevations[turns[i]].push_back(ElevationDeg(scan.points[i]));
  }
  std::vector<double> medians(num_turns);
  for (int turn = 0; turn < num_turns; ++turn) {
    std::vector<double>& values = elevations[turn];
    auto middle = values.begin() + values.size() / 2;
    std::nth_element(values.begin(), middle, values.end());
    medians[turn] = *middle;
  }
  std::vector<int> order(num_turns);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&medians](int a, int b) {
    return medians[a] < medians[b];
  });
  std::vector<uint16_t> ring_of_turn(num_turns);
  for (int rank = 0; rank < num_turns; ++rank) {
    ring_of_turn[order[rank]] = static_cast<uint16_t>(rank);
  }
  std::vector<uint16_t> rings(num_points);
  for (size_t i = 0; i < num_points; ++i) {
    rings[i] = ring_of_turn[turns[i]];
  }
  return rings;
}

}  // namespace colmap_lidar
