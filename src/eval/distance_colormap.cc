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
  const size_t n = points.size();
  std::vector<double> x(n), y(n), z(n), red(n), green(n), blue(n);
  for (size_t i = 0; i < n; ++i) {
    x[i] = points[i].x();
    y[i] = points[i].y();
    z[i] = points[i].z();
    Vector3ub color(kExcludedGrey, kExcludedGrey, kExcludedGrey);
    if (included.empty() || included[i]) {
      color = DistanceColor(distances[i], color_threshold);
    }
    red[i] = color[0];
    green[i] = color[1];
    blue[i] = color[2];
  }
  PlyData data;
  data.AddColumn("x", PlyScalarType::kFloat64, std::move(x));
  data.AddColumn("y", PlyScalarType::kFloat64, std::move(y));
  data.AddColumn("z", PlyScalarType::kFloat64, std::move(z));
  data.AddColumn("red", PlyScalarType::kUInt8, std::move(red));
  data.AddColumn("green", PlyScalarType::kUInt8, std::move(green));
  data.AddColumn("blue", PlyScalarType::kUInt8, std::move(blue));
  data.AddColumn("distance", PlyScalarType::kFloat64, distances);
  WritePly(path, data, PlyFormat::kBinaryLittleEndian);
}

}  // namespace colmap_lidar
