#include "src/lines/line_export.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <iomanip>

#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

struct WorldSegment {
  Eigen::Vector3d start;
  Eigen::Vector3d end;
  std::array<int, 3> rgb;
};

std::array<int, 3> ImageColor(const size_t image_idx) {
  // Golden-angle hues, full saturation.
  const double hue = std::fmod(image_idx * 137.508, 360.0) / 60.0;
  const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
  std::array<double, 3> rgb = {0, 0, 0};
  switch (static_cast<int>(hue)) {
    case 0: rgb = {1, x, 0}; break;
    case 1: rgb = {x, 1, 0}; break;
    case 2: rgb = {0, 1, x}; break;
    case 3: rgb = {0, x, 1}; break;
    case 4: rgb = {x, 0, 1}; break;
    default: rgb = {1, 0, x}; break;
  }
  return {static_cast<int>(255 * rgb[0]), static_cast<int>(255 * rgb[1]),
          static_cast<int>(255 * rgb[2])};
}

}  // namespace

LineExportSummary ExportWorldLineSegments(const Database& database,
                                          const Reconstruction& model,
                                          const std::string& output_path) {
  std::string extension = std::filesystem::path(output_path).extension();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  THROW_CHECK(extension == ".ply" || extension == ".obj",
              "line_exporter: --output_path must end in .ply or .obj: "
                  << output_path);
  LineExportSummary summary;
  std::vector<WorldSegment> segments;
  for (const image_t image_id : ReadImageIdsWithLineSegments(database)) {
    const std::optional<DatabaseImage> db_image = database.ReadImage(image_id);
    const Image* image =
        db_image ? model.FindImageByName(db_image->name) : nullptr;
    if (image == nullptr) {
      ++summary.num_images_missing;
      continue;
    }
    const Rigid3d world_from_cam = image->cam_from_world.Inverse();
    const std::array<int, 3> rgb = ImageColor(summary.num_images);
    ++summary.num_images;
    for (const LineSegmentRecord& record :
         ReadLineSegments(database, image_id)) {
      segments.push_back({world_from_cam * record.start3D_in_cam,
                          world_from_cam * record.end3D_in_cam, rgb});
    }
  }
  summary.num_segments = static_cast<int>(segments.size());
  if (summary.num_images_missing > 0) {
    LOG(WARNING) << summary.num_images_missing
                 << " images with line segments are not in the model; "
                    "their segments are not exported";
  }

  WriteFileAtomically(
      output_path,
      [&](std::ostream& out) {
        out << std::setprecision(9);
        if (extension == ".ply") {
          out << "ply\nformat ascii 1.0\n"
              << "comment colmap-lidar 3D line segments, world frame\n"
              << "element vertex " << 2 * segments.size() << "\n"
              << "property float x\nproperty float y\nproperty float z\n"
              << "property uchar red\nproperty uchar green\n"
              << "property uchar blue\n"
              << "element edge " << segments.size() << "\n"
              << "property int vertex1\nproperty int vertex2\n"
              << "end_header\n";
          for (const WorldSegment& segment : segments) {
            for (const Eigen::Vector3d& point : {segment.start, segment.end}) {
              out << point.x() << " " << point.y() << " " << point.z() << " "
                  << segment.rgb[0] << " " << segment.rgb[1] << " "
                  << segment.rgb[2] << "\n";
            }
          }
          for (size_t i = 0; i < segments.size(); ++i) {
            out << 2 * i << " " << 2 * i + 1 << "\n";
          }
        } else {
          out << "# colmap-lidar 3D line segments, world frame\n";
          for (const WorldSegment& segment : segments) {
            for (const Eigen::Vector3d& point : {segment.start, segment.end}) {
              out << "v " << point.x() << " " << point.y() << " " << point.z()
                  << " " << segment.rgb[0] / 255.0 << " "
                  << segment.rgb[1] / 255.0 << " " << segment.rgb[2] / 255.0
                  << "\n";
            }
          }
          for (size_t i = 0; i < segments.size(); ++i) {
            out << "l " << 2 * i + 1 << " " << 2 * i + 2 << "\n";
          }
        }
      },
      /*binary=*/false);
  return summary;
}

}  // namespace colmap_lidar
