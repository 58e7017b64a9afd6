#include "src/lidar/lidar_fusion.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include <Eigen/Eigenvalues>
#include <glog/logging.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {

// 21 bits per axis: +-2^20 voxels, i.e. +-52 km at 5 cm.
constexpr int64_t kAxisOffset = int64_t{1} << 20;
constexpr int64_t kAxisMask = (int64_t{1} << 21) - 1;

struct VoxelCoord {
  int64_t x, y, z;
};

uint64_t VoxelKey(const VoxelCoord& c) {
  return (static_cast<uint64_t>((c.x + kAxisOffset) & kAxisMask) << 42) |
         (static_cast<uint64_t>((c.y + kAxisOffset) & kAxisMask) << 21) |
         static_cast<uint64_t>((c.z + kAxisOffset) & kAxisMask);
}

VoxelCoord KeyToCoord(uint64_t key) {
  return {static_cast<int64_t>((key >> 42) & kAxisMask) - kAxisOffset,
          static_cast<int64_t>((key >> 21) & kAxisMask) - kAxisOffset,
          static_cast<int64_t>(key & kAxisMask) - kAxisOffset};
}

struct VoxelAccumulator {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  // Sum of unit vectors from the points to their scanner centre: the side
  // the normal must face.
  Eigen::Vector3f towards_scanners = Eigen::Vector3f::Zero();
  uint32_t count = 0;
  // (image_idx, points) per frame that hit the voxel.
  std::vector<std::pair<uint32_t, uint32_t>> frames;
};

// `keys` without the voxels that other scans see through (moving objects,
// src/lidar/free_space_filter.h); the order is kept.
std::vector<uint64_t> DropMovingVoxels(
    const std::vector<uint64_t>& keys,
    const std::unordered_map<uint64_t, VoxelAccumulator>& voxels,
    const std::vector<LidarFusionInput>& inputs,
    const LidarFusionOptions& options) {
  if (!options.free_space.enabled || inputs.size() < 2) {
    return keys;
  }
  // A voxel's frames are image indices; the filter wants input indices (a
  // frame given twice is two scans with one index).
  std::unordered_map<uint32_t, std::vector<uint32_t>> inputs_of_image;
  std::vector<FreeSpaceScan> scans(inputs.size());
  for (size_t i = 0; i < inputs.size(); ++i) {
    inputs_of_image[inputs[i].image_idx].push_back(static_cast<uint32_t>(i));
    scans[i].scan = inputs[i].scan;
    scans[i].world_from_lidar = inputs[i].world_from_lidar;
  }
  std::vector<Eigen::Vector3d> centroids(keys.size());
  std::vector<std::vector<uint32_t>> hit_frames(keys.size());
  for (size_t i = 0; i < keys.size(); ++i) {
    const VoxelAccumulator& voxel = voxels.at(keys[i]);
    centroids[i] = voxel.sum / voxel.count;
    for (const auto& frame : voxel.frames) {
      const std::vector<uint32_t>& indices = inputs_of_image.at(frame.first);
      hit_frames[i].insert(hit_frames[i].end(), indices.begin(), indices.end());
    }
  }
  const std::vector<bool> moving = FindMovingVoxels(
      centroids, hit_frames, scans, options.voxel_size_m, options.min_range_m,
      options.max_range_m, options.free_space);
  std::vector<uint64_t> kept;
  kept.reserve(keys.size());
  for (size_t i = 0; i < keys.size(); ++i) {
    if (!moving[i]) {
      kept.push_back(keys[i]);
    }
  }
  return kept;
}

}  // namespace

bool LidarFusionOptions::Check() const {
  if (!(voxel_size_m > 0)) {
    LOG(ERROR) << "LidarFusion.voxel_size_m must be > 0";
    return false;
  }
  if (!(min_range_m >= 0) || !(max_range_m > min_range_m)) {
    LOG(ERROR) << "LidarFusion.min_range_m / max_range_m: need "
                  "0 <= min_range_m < max_range_m";
    return false;
  }
  if (min_points_per_voxel < 1) {
    LOG(ERROR) << "LidarFusion.min_points_per_voxel must be >= 1";
    return false;
  }
  if (normal_radius_voxels < 1) {
    LOG(ERROR) << "LidarFusion.normal_radius_voxels must be >= 1";
    return false;
  }
  if (!(normal_min_eigenvalue_ratio >= 0 && normal_min_eigenvalue_ratio < 1)) {
    LOG(ERROR) << "LidarFusion.normal_min_eigenvalue_ratio must be in [0, 1)";
    return false;
  }
  if (normal_min_neighbors < 3) {
    LOG(ERROR) << "LidarFusion.normal_min_neighbors must be >= 3";
    return false;
  }
  if (max_num_visible_images < 1) {
    LOG(ERROR) << "LidarFusion.max_num_visible_images must be >= 1";
    return false;
  }
  return free_space.Check();
}

FusedLidarCloud FuseLidarScans(const std::vector<LidarFusionInput>& inputs,
                               const LidarFusionOptions& options) {
  THROW_CHECK(options.Check(), "invalid LidarFusion options");
  const double inv_voxel = 1.0 / options.voxel_size_m;
  std::unordered_map<uint64_t, VoxelAccumulator> voxels;
  for (const LidarFusionInput& input : inputs) {
    THROW_CHECK(input.scan != nullptr, "LidarFusionInput without a scan");
    const Eigen::Vector3d origin = input.world_from_lidar.translation;
    const Eigen::Matrix3d rotation =
        input.world_from_lidar.rotation.toRotationMatrix();
    for (const Eigen::Vector3f& point_in_lidar : input.scan->points) {
      const double range = point_in_lidar.cast<double>().norm();
      if (range < options.min_range_m || range > options.max_range_m) {
        continue;
      }
      const Eigen::Vector3d point_in_world =
          rotation * point_in_lidar.cast<double>() + origin;
      const VoxelCoord coord{
          static_cast<int64_t>(std::floor(point_in_world.x() * inv_voxel)),
          static_cast<int64_t>(std::floor(point_in_world.y() * inv_voxel)),
          static_cast<int64_t>(std::floor(point_in_world.z() * inv_voxel))};
      VoxelAccumulator& voxel = voxels[VoxelKey(coord)];
      voxel.sum += point_in_world;
      voxel.towards_scanners +=
          ((origin - point_in_world) / std::max(range, 1e-9)).cast<float>();
      ++voxel.count;
      if (voxel.frames.empty() || voxel.frames.back().first != input.image_idx) {
        voxel.frames.emplace_back(input.image_idx, 1);
      } else {
        ++voxel.frames.back().second;
      }
    }
  }

  std::vector<uint64_t> keys;
  keys.reserve(voxels.size());
  for (const auto& [key, voxel] : voxels) {
    if (voxel.count >= static_cast<uint32_t>(options.min_points_per_voxel)) {
      keys.push_back(key);
    }
  }
  std::sort(keys.begin(), keys.end());
  keys = DropMovingVoxels(keys, voxels, inputs, options);

  FusedLidarCloud cloud;
  cloud.points.resize(keys.size());
  cloud.normals.resize(keys.size(), Eigen::Vector3f::Zero());
  cloud.counts.resize(keys.size());
  cloud.visibility.resize(keys.size());
  std::unordered_map<uint64_t, uint32_t> key_to_index;
  key_to_index.reserve(keys.size());
  for (size_t i = 0; i < keys.size(); ++i) {
    VoxelAccumulator& voxel = voxels.at(keys[i]);
    key_to_index[keys[i]] = static_cast<uint32_t>(i);
    cloud.points[i] = (voxel.sum / voxel.count).cast<float>();
    cloud.counts[i] = voxel.count;
    // A frame may appear in several runs (scans given twice): merge them.
    std::sort(voxel.frames.begin(), voxel.frames.end());
    std::vector<std::pair<uint32_t, uint32_t>> merged;
    for (const auto& frame : voxel.frames) {
      if (!merged.empty() && merged.back().first == frame.first) {
        merged.back().second += frame.second;
      } else {
        merged.push_back(frame);
      }
    }
    std::stable_sort(merged.begin(), merged.end(),
                     [](const auto& a, const auto& b) {
                       return a.second > b.second;
                     });
    const size_t num_kept = std::min<size_t>(
        merged.size(), static_cast<size_t>(options.max_num_visible_images));
    for (size_t k = 0; k < num_kept; ++k) {
      cloud.visibility[i].push_back(merged[k].first);
    }
  }

  // Normals: PCA of the neighbouring voxel centroids.
  const int r = options.normal_radius_voxels;
  for (size_t i = 0; i < keys.size(); ++i) {
    const VoxelCoord c = KeyToCoord(keys[i]);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    int num = 0;
    for (int dx = -r; dx <= r; ++dx) {
      for (int dy = -r; dy <= r; ++dy) {
        for (int dz = -r; dz <= r; ++dz) {
          const auto it =
              key_to_index.find(VoxelKey({c.x + dx, c.y + dy, c.z + dz}));
          if (it == key_to_index.end()) {
            continue;
          }
          const Eigen::Vector3d p = cloud.points[it->second].cast<double>();
          mean += p;
          second += p * p.transpose();
          ++num;
        }
      }
    }
    if (num < options.normal_min_neighbors) {
      continue;
    }
    mean /= num;
    const Eigen::Matrix3d covariance = second / num - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
    // Eigenvalues in increasing order: a line of centroids has no plane.
    if (!(solver.eigenvalues()(1) >=
          options.normal_min_eigenvalue_ratio * solver.eigenvalues()(2))) {
      continue;
    }
    Eigen::Vector3f normal = solver.eigenvectors().col(0).cast<float>();
    if (normal.dot(voxels.at(keys[i]).towards_scanners) < 0) {
      normal = -normal;
    }
    cloud.normals[i] = normal.normalized();
  }
  return cloud;
}

void WriteFusedLidarCloud(const std::string& ply_path,
                          const FusedLidarCloud& cloud) {
  const size_t n = cloud.size();
  std::vector<double> columns[7];
  for (auto& column : columns) {
    column.resize(n);
  }
  std::vector<double> counts(n);
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      columns[k][i] = cloud.points[i][k];
      columns[3 + k][i] = cloud.normals[i][k];
    }
    counts[i] = cloud.counts[i];
  }
  PlyData data;
  const char* names[6] = {"x", "y", "z", "nx", "ny", "nz"};
  for (int k = 0; k < 6; ++k) {
    data.AddColumn(names[k], PlyScalarType::kFloat32, std::move(columns[k]));
  }
  data.AddColumn("count", PlyScalarType::kUInt32, std::move(counts));
  WritePly(ply_path, data);
  FusedVisibility visibility = cloud.visibility;
  visibility.resize(n);
  WriteFusedVis(ply_path + ".vis", visibility);
}

FusedLidarCloud ReadFusedLidarCloud(const std::string& ply_path) {
  const PlyData data = ReadPly(ply_path);
  const size_t n = data.NumVertices();
  auto column = [&](const char* name) -> const PlyColumn& {
    const PlyColumn* c = data.FindColumn(name);
    THROW_CHECK(c != nullptr, "PLY " << ply_path << " has no column " << name);
    return *c;
  };
  const PlyColumn* cols[7] = {&column("x"),  &column("y"),  &column("z"),
                              &column("nx"), &column("ny"), &column("nz"),
                              &column("count")};
  FusedLidarCloud cloud;
  cloud.points.resize(n);
  cloud.normals.resize(n);
  cloud.counts.resize(n);
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      cloud.points[i][k] = static_cast<float>(cols[k]->values[i]);
      cloud.normals[i][k] = static_cast<float>(cols[3 + k]->values[i]);
    }
    cloud.counts[i] = static_cast<uint32_t>(cols[6]->values[i]);
  }
  if (ExistsFile(ply_path + ".vis")) {
    cloud.visibility = ReadFusedVis(ply_path + ".vis", n);
  }
  return cloud;
}

namespace {

// lidar_origins.txt is whitespace-separated: a name must be one token.
bool IsStorableOriginName(const std::string& image_name) {
  return !image_name.empty() &&
         image_name.find_first_of(" \t\n\r") == std::string::npos;
}

}  // namespace

void WriteLidarOrigins(const std::string& path,
                       const std::vector<LidarOrigin>& origins) {
  WriteFileAtomically(
      path,
      [&](std::ostream& stream) {
        stream.precision(17);
        for (const LidarOrigin& origin : origins) {
          THROW_CHECK(IsStorableOriginName(origin.image_name),
                      "image name '" << origin.image_name
                                     << "' cannot be stored in " << path);
          stream << origin.image_name << " " << origin.position_in_world.x()
                 << " " << origin.position_in_world.y() << " "
                 << origin.position_in_world.z() << "\n";
        }
      },
      /*binary=*/false);
}

std::vector<LidarOrigin> ReadLidarOriginList(const std::string& path) {
  std::istringstream stream(ReadTextFile(path));
  std::vector<LidarOrigin> origins;
  std::string line;
  int line_number = 0;
  while (std::getline(stream, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#') {
      continue;
    }
    std::istringstream fields(line);
    LidarOrigin origin;
    THROW_CHECK(static_cast<bool>(fields >> origin.image_name >>
                                  origin.position_in_world.x() >>
                                  origin.position_in_world.y() >>
                                  origin.position_in_world.z()),
                "malformed line " << line_number << " in " << path);
    origins.push_back(origin);
  }
  return origins;
}

LidarFuserSummary RunLidarFuser(const std::string& database_path,
                                const std::string& input_path,
                                const std::string& output_path,
                                const LidarFusionOptions& options) {
  THROW_CHECK(options.Check(), "invalid LidarFusion options");
  // Opening a Database creates a missing file: refuse first, so that a
  // wrong path is an error and not an empty fusion.
  CheckFileExists(database_path, "LIDAR fusion database");
  const Reconstruction model = ReadReconstruction(input_path);
  const std::string dense_sparse = JoinPaths(output_path, "sparse");
  const Reconstruction order_model =
      ExistsModel(dense_sparse) ? ReadReconstruction(dense_sparse) : model;
  if (!ExistsModel(dense_sparse)) {
    LOG(WARNING) << "No dense workspace model in " << dense_sparse
                 << "; .vis indices follow the image order of "
                 << input_path;
  }
  const Database database(database_path);

  LidarFuserSummary summary;
  std::vector<LidarScan> scans;
  std::vector<LidarFusionInput> inputs;
  std::vector<LidarOrigin> origins;
  scans.reserve(order_model.images.size());
  for (size_t idx = 0; idx < order_model.images.size(); ++idx) {
    const std::string& name = order_model.images[idx].name;
    const Image* image = model.FindImageByName(name);
    if (image == nullptr) {
      LOG(WARNING) << "Image " << name << " is not in " << input_path
                   << "; skipped";
      continue;
    }
    ++summary.num_frames;
    // Checked before anything is written, so that a failure leaves no
    // cloud without its origins.
    THROW_CHECK(IsStorableOriginName(name),
                "image name '" << name << "' cannot be stored in "
                               << JoinPaths(output_path, "lidar_origins.txt")
                               << " (it holds whitespace)");
    const std::optional<DatabaseImage> db_image =
        database.ReadImageWithName(name);
    std::optional<LidarScanRecord> record;
    if (db_image) {
      record = database.ReadLidarScan(db_image->image_id);
    }
    if (!record) {
      LOG(WARNING) << "Image " << name << " has no LIDAR scan in "
                   << database_path;
      ++summary.num_frames_without_scan;
      continue;
    }
    scans.push_back(
        ReadLidarScan(LidarScanFilePath(database_path, record->path)));
    summary.num_raw_points += scans.back().size();
    LidarFusionInput input;
    input.image_idx = static_cast<uint32_t>(idx);
    input.world_from_lidar =
        image->cam_from_world.Inverse() * record->cam_from_lidar;
    inputs.push_back(input);
    origins.push_back({name, input.world_from_lidar.translation});
  }
  for (size_t i = 0; i < inputs.size(); ++i) {
    inputs[i].scan = &scans[i];
  }
  const FusedLidarCloud cloud = FuseLidarScans(inputs, options);
  summary.num_voxels = cloud.size();
  CreateDirIfNotExists(output_path);
  WriteFusedLidarCloud(JoinPaths(output_path, "lidar_fused.ply"), cloud);
  WriteLidarOrigins(JoinPaths(output_path, "lidar_origins.txt"), origins);
  LOG(INFO) << "Fused " << summary.num_raw_points << " LIDAR points of "
            << inputs.size() << " frames into " << summary.num_voxels
            << " voxels";
  return summary;
}

}  // namespace colmap_lidar
