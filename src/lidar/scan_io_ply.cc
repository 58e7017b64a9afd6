// PLY scans of scan_io.h, through colmap_ext/util/ply.h.
#include "src/lidar/scan_io.h"

#include <string>
#include <vector>

#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/string.h"
#include "src/lidar/scan_io_internal.h"

namespace colmap_lidar {
namespace {

// Names of the return-strength channel, in order of preference.
const char* const kIntensityNames[] = {"intensity", "reflectance",
                                       "scalar_intensity"};

}  // namespace

namespace scan_io_internal {

LidarScan ReadPlyScan(const std::string& path) {
  const PlyData data = ReadPly(path);
  const PlyColumn* columns[3] = {data.FindColumn("x"), data.FindColumn("y"),
                                 data.FindColumn("z")};
  for (int axis = 0; axis < 3; ++axis) {
    THROW_CHECK(columns[axis] != nullptr,
                "PLY file " << path << " has no vertex property '"
                            << "xyz"[axis] << "'");
  }
  const PlyColumn* intensity = nullptr;
  for (const char* name : kIntensityNames) {
    if (intensity == nullptr) {
      intensity = data.FindColumn(name);
    }
  }
  const PlyColumn* ring = data.FindColumn("ring");

  const size_t num_points = data.NumVertices();
  LidarScan scan;
  scan.points.resize(num_points);
  for (size_t i = 0; i < num_points; ++i) {
    scan.points[i] = Eigen::Vector3f(static_cast<float>(columns[0]->values[i]),
                                     static_cast<float>(columns[1]->values[i]),
                                     static_cast<float>(columns[2]->values[i]));
  }
  if (intensity != nullptr) {
    scan.intensities.assign(intensity->values.begin(),
                            intensity->values.end());
  }
  if (ring != nullptr) {
    scan.rings.resize(num_points);
    for (size_t i = 0; i < num_points; ++i) {
      scan.rings[i] = ToRing(ring->values[i], i, path);
    }
  }
  return scan;
}

size_t CountPlyScanPoints(const std::string& path) {
  for (const auto& words : ReadHeaderLines(path, "end_header")) {
    if (words.size() == 3 && words[0] == "element" && words[1] == "vertex") {
      return static_cast<size_t>(
          ParseInt(words[2], "vertex count of " + path));
    }
  }
  THROW_ERROR("PLY file " << path << " has no vertex element");
}

}  // namespace scan_io_internal

void WriteLidarScanPly(const std::string& path, const LidarScan& scan,
                       const bool binary) {
  THROW_CHECK(!scan.HasIntensities() || scan.intensities.size() == scan.size(),
              "Cannot write " << path << ": intensity count differs from "
                              << "point count");
  THROW_CHECK(!scan.HasRings() || scan.rings.size() == scan.size(),
              "Cannot write " << path << ": ring count differs from point "
                              << "count");
  PlyData data;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> values(scan.size());
    for (size_t i = 0; i < scan.size(); ++i) {
      values[i] = scan.points[i][axis];
    }
    data.AddColumn(std::string(1, "xyz"[axis]), PlyScalarType::kFloat32,
                   std::move(values));
  }
  if (scan.HasIntensities()) {
    data.AddColumn("intensity", PlyScalarType::kFloat32,
                   std::vector<double>(scan.intensities.begin(),
                                       scan.intensities.end()));
  }
  if (scan.HasRings()) {
    data.AddColumn("ring", PlyScalarType::kUInt16,
                   std::vector<double>(scan.rings.begin(), scan.rings.end()));
  }
  WritePly(path, data,
           binary ? PlyFormat::kBinaryLittleEndian : PlyFormat::kAscii);
}

}  // namespace colmap_lidar
