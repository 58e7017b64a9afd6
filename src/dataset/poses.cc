#include "src/dataset/poses.h"

#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {

std::vector<FramePose> ReadPoses(const std::string& path) {
  CheckFileExists(path, "Poses");
  std::istringstream content(ReadTextFile(path));
  std::vector<FramePose> poses;
  std::set<std::string> seen;
  std::string line;
  int line_number = 0;
  while (std::getline(content, line)) {
    ++line_number;
    line = StringTrim(line);
    if (line.empty() || line[0] == '#') {
      continue;
    }
    std::istringstream fields_stream(line);
    std::vector<std::string> fields;
    std::string field;
    while (fields_stream >> field) {
      fields.push_back(field);
    }
    const std::string where = path + ":" + std::to_string(line_number);
    THROW_CHECK(fields.size() == 8,
                where << ": expected 8 columns (frame tx ty tz qx qy qz qw), "
                         "got "
                      << fields.size());
    double values[7];
    for (int i = 0; i < 7; ++i) {
      values[i] = ParseDouble(fields[i + 1], where);
      THROW_CHECK(std::isfinite(values[i]),
                  where << ": non-finite value '" << fields[i + 1] << "'");
    }
    Eigen::Quaterniond rotation(values[6], values[3], values[4], values[5]);
    const double norm = rotation.norm();
    THROW_CHECK(std::abs(norm - 1.0) < 1e-3,
                where << ": quaternion is not unit (norm " << norm << ")");
    THROW_CHECK(seen.insert(fields[0]).second,
                where << ": frame '" << fields[0] << "' appears twice");
    FramePose pose;
    pose.frame = fields[0];
    pose.world_from_cam = Rigid3d(rotation.normalized(),
                                  Eigen::Vector3d(values[0], values[1], values[2]));
    poses.push_back(pose);
  }
  return poses;
}

void WritePoses(const std::string& path, const std::vector<FramePose>& poses,
                const std::string& comment) {
  WriteFileAtomically(
      path,
      [&](std::ostream& out) {
        if (!comment.empty()) {
          std::istringstream comment_lines(comment);
          std::string line;
          while (std::getline(comment_lines, line)) {
            out << "# " << line << "\n";
          }
        }
        out << "# frame tx ty tz qx qy qz qw  (world_from_cam)\n";
        out << std::setprecision(17);
        for (const FramePose& pose : poses) {
          const Eigen::Vector3d& t = pose.world_from_cam.translation;
          const Eigen::Quaterniond q = pose.world_from_cam.rotation.normalized();
          out << pose.frame << " " << t.x() << " " << t.y() << " " << t.z()
              << " " << q.x() << " " << q.y() << " " << q.z() << " " << q.w()
              << "\n";
        }
      },
      /*binary=*/false);
}

}  // namespace colmap_lidar
