#include "src/eval/distance_colormap.h"

#include <algorithm>
#include <cmath>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"

namespace colmap_lidar {

Vector3ub DistanceColor(double distance, double color_threshold) {
  THROW_CHECK(color_threshold > 0.0,
              "DistanceColor: the colour threshold must be positive, got "
                  << color_threshold);
  // Key colours at 0, 1/3, 2/3 and 1 of the threshold.
  static const double kKeys[4][3] = {
      {0, 0, 255}, {0, 255, 0}, {255, 255, 0}, {255, 0, 0}};
  double s = std::isfinite(distance) ? distance / color_threshold : 1.0;
  s = std::clamp(s, 0.0, 1.0) * 3.0;
  const int segment = std::min(2, static_cast<int>(s));
  const double w = s - segment;
  Vector3ub color;
  for (int c = 0; c < 3; ++c) {
    const double value =
        (1.0 - w) * kKeys[segment][c] + w * kKeys[segment + 1][c];
    color[c] = static_cast<uint8_t>(std::lround(value));
  }
  return color;
}

void WriteDistanceColoredPly(const std::string& path,
                             const std::vector<Eigen::Vector3d>& points,
                             const std::vector<double>& distances,
                             const std::vector<bool>& included,
                             double color_threshold) {
  THROW_CHECK(distances.size() == points.size() &&
                  (included.empty() || included.size() == points.size()),
              "WriteDistanceColoredPly " << path << ": " << points.size()
                                         << " points, " << distances.size()
                                         << " distances, " << included.size()
                                         << " flags");
  // Streamed: a 200-frame mesh has 14 M samples, 0.5 GB of records.
  const std::vector<PlyProperty> properties = {
      {"x", PlyScalarType::kFloat64},      {"y", PlyScalarType::kFloat64},
      {"z", PlyScalarType::kFloat64},      {"red", PlyScalarType::kUInt8},
      {"green", PlyScalarType::kUInt8},    {"blue", PlyScalarType::kUInt8},
      {"distance", PlyScalarType::kFloat64}};
  WritePlyVertices(path, properties, points.size(),
                   [&](size_t i, double* values) {
                     Vector3ub color(kExcludedGrey, kExcludedGrey,
                                     kExcludedGrey);
                     if (included.empty() || included[i]) {
                       color = DistanceColor(distances[i], color_threshold);
                     }
                     values[0] = points[i].x();
                     values[1] = points[i].y();
                     values[2] = points[i].z();
                     values[3] = color[0];
                     values[4] = color[1];
                     values[5] = color[2];
                     values[6] = distances[i];
                   });
}

}  // namespace colmap_lidar
