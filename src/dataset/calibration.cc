#include "src/dataset/calibration.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

// Reads node as a finite double; throws naming the file and the key.
double ReadFiniteDouble(const YAML::Node& node, const std::string& path,
                        const std::string& key) {
  double value = 0;
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    THROW_ERROR(path << ": '" << key << "' must be a number");
  }
  THROW_CHECK(std::isfinite(value),
              path << ": '" << key << "' is not finite (" << value << ")");
  return value;
}

// Reads node as an integer in [min_value, max_value]; throws naming the file
// and the key. The range is checked on the double, so the conversion to int
// is always defined (a fuzzer found 1.7e16 rings).
int ReadBoundedInt(const YAML::Node& node, const std::string& path,
                   const std::string& key, int min_value, int max_value) {
  const double value = ReadFiniteDouble(node, path, key);
  THROW_CHECK(value == std::floor(value) && value >= min_value &&
                  value <= max_value,
              path << ": '" << key << "' must be an integer in [" << min_value
                   << ", " << max_value << "] (" << value << ")");
  return static_cast<int>(value);
}

YAML::Node RequireKey(const YAML::Node& parent, const std::string& key,
                      const std::string& path, const std::string& full_key) {
  THROW_CHECK(parent.IsMap(), path << ": expected a mapping above '"
                                   << full_key << "'");
  const YAML::Node node = parent[key];
  THROW_CHECK(node.IsDefined() && !node.IsNull(),
              path << ": missing key '" << full_key << "'");
  return node;
}

Rigid3d ReadRigidTransform(const YAML::Node& node, const std::string& path,
                           const std::string& key) {
  THROW_CHECK(node.IsSequence() && (node.size() == 4 || node.size() == 3),
              path << ": '" << key
                   << "' must be a list of 3 or 4 rows of 4 numbers");
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
  for (size_t r = 0; r < node.size(); ++r) {
    THROW_CHECK(node[r].IsSequence() && node[r].size() == 4,
                path << ": row " << r << " of '" << key
                     << "' must have 4 numbers");
    for (size_t c = 0; c < 4; ++c) {
      std::ostringstream element_key;
      element_key << key << "[" << r << "][" << c << "]";
      matrix(r, c) = ReadFiniteDouble(node[r][c], path, element_key.str());
    }
  }
  THROW_CHECK(matrix.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1)),
              path << ": the last row of '" << key << "' must be 0 0 0 1");
  const Eigen::Matrix3d rotation = matrix.topLeftCorner<3, 3>();
  const double orthogonality_error =
      (rotation * rotation.transpose() - Eigen::Matrix3d::Identity())
          .cwiseAbs()
          .maxCoeff();
  THROW_CHECK(orthogonality_error < 1e-4 && rotation.determinant() > 0,
              path << ": '" << key
                   << "' is not a rigid transform (rotation block is not a "
                      "proper rotation, max |R R^T - I| = "
                   << orthogonality_error << ")");
  return Rigid3d::FromMatrix(matrix.topRows<3>());
}

}  // namespace

RigCalibration ReadCalibration(const std::string& path) {
  CheckFileExists(path, "Calibration");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    THROW_ERROR(path << ": malformed YAML: " << e.what());
  }
  THROW_CHECK(root.IsMap(), path << ": expected a YAML mapping at the top");

  RigCalibration calib;
  const YAML::Node camera = RequireKey(root, "camera", path, "camera");
  std::string model_name;
  try {
    model_name = RequireKey(camera, "model", path, "camera.model").as<std::string>();
  } catch (const YAML::Exception&) {
    THROW_ERROR(path << ": 'camera.model' must be a string");
  }
  const double width = ReadFiniteDouble(
      RequireKey(camera, "width", path, "camera.width"), path, "camera.width");
  const double height =
      ReadFiniteDouble(RequireKey(camera, "height", path, "camera.height"),
                       path, "camera.height");
  // The upper bound keeps the conversion to an integer defined (a width of
  // 1e30 would overflow it) and is far above any real camera.
  constexpr double kMaxImageSize = 1 << 20;
  THROW_CHECK(width >= 1 && height >= 1 && width == std::floor(width) &&
                  height == std::floor(height) && width <= kMaxImageSize &&
                  height <= kMaxImageSize,
              path << ": camera.width and camera.height must be positive "
                      "integers up to "
                   << kMaxImageSize);
  const YAML::Node params_node =
      RequireKey(camera, "params", path, "camera.params");
  THROW_CHECK(params_node.IsSequence(),
              path << ": 'camera.params' must be a list of numbers");
  std::vector<double> params;
  for (size_t i = 0; i < params_node.size(); ++i) {
    params.push_back(ReadFiniteDouble(
        params_node[i], path, "camera.params[" + std::to_string(i) + "]"));
  }
  try {
    calib.camera = Camera::FromModelName(model_name,
                                         static_cast<uint64_t>(width),
                                         static_cast<uint64_t>(height), params);
  } catch (const Error& e) {
    THROW_ERROR(path << ": camera: " << e.what());
  }
  calib.camera.has_prior_focal_length = true;

  calib.cam_from_lidar = ReadRigidTransform(
      RequireKey(root, "cam_from_lidar", path, "cam_from_lidar"), path,
      "cam_from_lidar");

  const YAML::Node lidar = root["lidar"];
  if (lidar.IsDefined() && !lidar.IsNull()) {
    THROW_CHECK(lidar.IsMap(), path << ": 'lidar' must be a mapping");
    LidarDescription description;
    if (lidar["rings"]) {
      // 0 means "unknown"; real units have at most 128 rings, the bound
      // leaves room for denser ones.
      constexpr int kMaxRings = 4096;
      description.rings =
          ReadBoundedInt(lidar["rings"], path, "lidar.rings", 0, kMaxRings);
    }
    if (lidar["vertical_fov_deg"]) {
      const YAML::Node fov = lidar["vertical_fov_deg"];
      THROW_CHECK(fov.IsSequence() && fov.size() == 2,
                  path << ": 'lidar.vertical_fov_deg' must be [min, max]");
      description.vertical_fov_min_deg =
          ReadFiniteDouble(fov[0], path, "lidar.vertical_fov_deg[0]");
      description.vertical_fov_max_deg =
          ReadFiniteDouble(fov[1], path, "lidar.vertical_fov_deg[1]");
      THROW_CHECK(description.vertical_fov_min_deg <
                      description.vertical_fov_max_deg,
                  path << ": 'lidar.vertical_fov_deg' must be [min, max] "
                          "with min < max");
    }
    if (lidar["range_noise_m"]) {
      description.range_noise_m =
          ReadFiniteDouble(lidar["range_noise_m"], path, "lidar.range_noise_m");
      THROW_CHECK(description.range_noise_m >= 0,
                  path << ": 'lidar.range_noise_m' must not be negative");
    }
    calib.lidar = description;
  }
  return calib;
}

void WriteCalibration(const std::string& path, const RigCalibration& calib) {
  calib.camera.Check();
  WriteFileAtomically(
      path,
      [&](std::ostream& out) {
        out << std::setprecision(17);
        out << "camera:\n";
        out << "  model: " << calib.camera.ModelName() << "\n";
        out << "  width: " << calib.camera.width << "\n";
        out << "  height: " << calib.camera.height << "\n";
        out << "  params: [";
        for (size_t i = 0; i < calib.camera.params.size(); ++i) {
          out << (i > 0 ? ", " : "") << calib.camera.params[i];
        }
        out << "]\n";
        out << "cam_from_lidar:  # 4x4 row-major, p_cam = T * p_lidar\n";
        const Eigen::Matrix3x4d matrix = calib.cam_from_lidar.ToMatrix();
        for (int r = 0; r < 3; ++r) {
          out << "  - [" << matrix(r, 0) << ", " << matrix(r, 1) << ", "
              << matrix(r, 2) << ", " << matrix(r, 3) << "]\n";
        }
        out << "  - [0, 0, 0, 1]\n";
        if (calib.lidar) {
          out << "lidar:\n";
          out << "  rings: " << calib.lidar->rings << "\n";
          out << "  vertical_fov_deg: [" << calib.lidar->vertical_fov_min_deg
              << ", " << calib.lidar->vertical_fov_max_deg << "]\n";
          out << "  range_noise_m: " << calib.lidar->range_noise_m << "\n";
        }
      },
      /*binary=*/false);
}

}  // namespace colmap_lidar
