#include "src/mesh/meshing_input.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/mvs/workspace.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/parallel.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/process_group.h"
#include "colmap_ext/util/string.h"
#include "src/mesh/radius_grid.h"

namespace colmap_lidar {

size_t MeshingInput::NumRays() const {
  size_t num_rays = 0;
  for (const auto& sensors_of_point : visibility) {
    num_rays += sensors_of_point.size();
  }
  return num_rays;
}

size_t MeshingInput::NumPoints(MeshingPointSource source) const {
  size_t count = 0;
  for (const MeshingPointSource point_source : sources) {
    count += point_source == source ? 1 : 0;
  }
  return count;
}

void MeshingInput::AddPoint(const Eigen::Vector3d& position,
                            MeshingPointSource source, float ray_weight,
                            std::vector<uint32_t> sensor_indices) {
  for (const uint32_t sensor_idx : sensor_indices) {
    THROW_CHECK(sensor_idx < sensors.size(),
                "Sensor index " << sensor_idx << " of point "
                                << positions.size() << " is not below "
                                << sensors.size());
  }
  positions.push_back(position);
  sources.push_back(source);
  ray_weights.push_back(ray_weight);
  visibility.push_back(std::move(sensor_indices));
}

void MeshingInput::Check() const {
  THROW_CHECK(sources.size() == positions.size() &&
                  ray_weights.size() == positions.size() &&
                  visibility.size() == positions.size(),
              "MeshingInput arrays differ in length");
  CheckFusedVisIndices(visibility, sensors.size(), "MeshingInput");
}

LidarCountMapping LidarCountMappingFromString(const std::string& name) {
  const std::string lower = StringToLower(name);
  if (lower == "none") return LidarCountMapping::kNone;
  if (lower == "linear") return LidarCountMapping::kLinear;
  if (lower == "log") return LidarCountMapping::kLog;
  THROW_ERROR("Unknown LIDAR count mapping '" << name
                                              << "' (none | linear | log)");
}

bool MeshingInputOptions::Check() const {
  if (!(visual_weight >= 0)) {
    LOG(ERROR) << "MeshingInput.visual_weight must be >= 0";
    return false;
  }
  if (!(visibility_sigma > 0)) {
    LOG(ERROR) << "MeshingInput.visibility_sigma must be > 0";
    return false;
  }
  if (!(lidar_weight >= 0)) {
    LOG(ERROR) << "MeshingInput.lidar_weight must be >= 0";
    return false;
  }
  try {
    LidarCountMappingFromString(lidar_count_mapping);
  } catch (const Error& error) {
    LOG(ERROR) << "MeshingInput.lidar_count_mapping: " << error.what();
    return false;
  }
  if (max_lidar_rays_per_point < 0) {
    LOG(ERROR) << "MeshingInput.max_lidar_rays_per_point must be >= 0";
    return false;
  }
  if (!(line_weight >= 0)) {
    LOG(ERROR) << "MeshingInput.line_weight must be >= 0";
    return false;
  }
  if (!(line_sample_step_m >= 0) || !std::isfinite(line_sample_step_m)) {
    LOG(ERROR) << "MeshingInput.line_sample_step_m must be >= 0 (0: the "
                  "points' spacing)";
    return false;
  }
  if (!lidar_denoising.Check()) return false;
  if (validate_lines && !line_validation.Check()) return false;
  return true;
}

std::string LidarFusedPlyPath(const std::string& workspace_path) {
  return JoinPaths(workspace_path, "lidar_fused.ply");
}
std::string LidarFusedVisPath(const std::string& workspace_path) {
  return JoinPaths(workspace_path, "lidar_fused.ply.vis");
}
std::string LidarOriginsPath(const std::string& workspace_path) {
  return JoinPaths(workspace_path, "lidar_origins.txt");
}

std::vector<std::pair<std::string, Eigen::Vector3d>> ReadLidarOrigins(
    const std::string& path) {
  CheckFileExists(path, "LIDAR origins");
  std::istringstream stream(ReadTextFile(path));
  std::vector<std::pair<std::string, Eigen::Vector3d>> origins;
  std::map<std::string, int> line_of_name;
  std::string line;
  int line_number = 0;
  while (std::getline(stream, line)) {
    ++line_number;
    line = StringTrim(line);
    if (line.empty() || line[0] == '#') continue;
    // The last three fields are the coordinates; the rest is the name.
    std::vector<std::string> fields = StringSplit(line, " \t");
    std::vector<std::string> tokens;
    for (const std::string& field : fields) {
      if (!field.empty()) tokens.push_back(field);
    }
    THROW_CHECK(tokens.size() >= 4, path << ":" << line_number
                                         << ": expected IMAGE_NAME X Y Z");
    Eigen::Vector3d origin;
    for (int k = 0; k < 3; ++k) {
      origin[k] = ParseDouble(tokens[tokens.size() - 3 + k],
                              path + ":" + std::to_string(line_number));
    }
    // The name is what precedes the last three fields (it may hold spaces).
    std::string name = line;
    for (int k = 0; k < 3; ++k) {
      name = StringTrim(name.substr(0, name.find_last_of(" \t")));
    }
    const auto [it, inserted] = line_of_name.emplace(name, line_number);
    THROW_CHECK(inserted, path << ":" << line_number << ": image '" << name
                               << "' already on line " << it->second);
    origins.emplace_back(name, origin);
  }
  return origins;
}

void WriteLidarOrigins(
    const std::string& path,
    const std::vector<std::pair<std::string, Eigen::Vector3d>> & origins) {
  WriteFileAtomically(
      path,
      [&](std::ostream& stream) {
        stream << "# IMAGE_NAME X Y Z (LIDAR centre in the world frame)\n";
        stream << std::setprecision(17);
        for (const auto& [name, origin] : origins) {
          stream << name << " " << origin.x() << " " << origin.y() << " "
                 << origin.z() << "\n";
        }
      },
      /*binary=*/false);
}

void AddCameraSensors(const Reconstruction& model, MeshingInput* input) {
  THROW_CHECK(input->sensors.empty(),
              "AddCameraSensors must be called on an empty input");
  for (const Image& image : model.images) {
    const auto camera_it = model.cameras.find(image.camera_id);
    THROW_CHECK(camera_it != model.cameras.end(),
                "Image " << image.name << " has no camera");
    MeshingSensor sensor;
    sensor.position_in_world = image.ProjectionCenter();
    sensor.is_camera = true;
    sensor.proj_matrix =
        camera_it->second.CalibrationMatrix() * image.cam_from_world.ToMatrix();
    sensor.image_width = static_cast<int>(camera_it->second.width);
    sensor.image_height = static_cast<int>(camera_it->second.height);
    input->sensors.push_back(sensor);
  }
}

namespace {

// COLMAP's visibility probability of a point seen in n images,
// 1 - exp(-n^2 / (2 visibility_sigma^2)): how much a ray of it is trusted.
double VisibilityProbability(const MeshingInputOptions& options, size_t n) {
  const double sigma = options.visibility_sigma;
  return 1.0 - std::exp(-0.5 * static_cast<double>(n * n) / (sigma * sigma));
}

}  // namespace

void AddVisualPoints(const MeshingInputOptions& options,
                     const std::vector<Eigen::Vector3d>& positions,
                     const FusedVisibility& visibility, MeshingInput* input) {
  THROW_CHECK(positions.size() == visibility.size(),
              "Visual points and visibility differ in length");
  size_t num_unseen = 0;
  for (size_t i = 0; i < positions.size(); ++i) {
    if (visibility[i].empty()) {
      ++num_unseen;
      continue;
    }
    const double weight = options.visual_weight *
                          VisibilityProbability(options, visibility[i].size());
    input->AddPoint(positions[i], MeshingPointSource::kVisual,
                    static_cast<float>(weight), visibility[i]);
  }
  if (num_unseen > 0) {
    LOG(WARNING) << num_unseen << " visual points without visibility skipped";
  }
}

void AddLidarPoints(const MeshingInputOptions& options,
                    const std::vector<Eigen::Vector3d>& positions,
                    const std::vector<uint32_t>& counts,
                    const FusedVisibility& frames,
                    const std::vector<Eigen::Vector3d>& origins,
                    const std::vector<bool>& has_origin,
                    const std::string& path_for_errors, MeshingInput* input) {
  THROW_CHECK(positions.size() == counts.size() &&
                  positions.size() == frames.size(),
              "LIDAR points, counts and visibility differ in length");
  THROW_CHECK(origins.size() == has_origin.size(),
              "LIDAR origins and flags differ in length");
  const LidarCountMapping mapping =
      LidarCountMappingFromString(options.lidar_count_mapping);
  // One sensor per frame that has an origin, created on first use.
  std::vector<int> sensor_of_frame(origins.size(), -1);
  for (size_t i = 0; i < positions.size(); ++i) {
    if (frames[i].empty()) continue;
    std::vector<uint32_t> sensor_indices;
    sensor_indices.reserve(frames[i].size());
    for (const uint32_t frame : frames[i]) {
      THROW_CHECK(frame < origins.size(),
                  path_for_errors << ": point " << i << " refers to image "
                                  << frame << " of " << origins.size());
      THROW_CHECK(has_origin[frame], path_for_errors
                                         << ": point " << i
                                         << " is seen by image position "
                                         << frame
                                         << ", which has no LIDAR origin");
      if (sensor_of_frame[frame] < 0) {
        sensor_of_frame[frame] = static_cast<int>(input->sensors.size());
        MeshingSensor sensor;
        sensor.position_in_world = origins[frame];
        input->sensors.push_back(sensor);
      }
      sensor_indices.push_back(sensor_of_frame[frame]);
    }
    const size_t max_rays =
        static_cast<size_t>(options.max_lidar_rays_per_point);
    if (max_rays > 0 && sensor_indices.size() > max_rays) {
      const Eigen::Vector3d& position = positions[i];
      const auto distance = [&](uint32_t sensor) {
        return (input->sensors[sensor].position_in_world - position)
            .squaredNorm();
      };
      std::partial_sort(sensor_indices.begin(),
                        sensor_indices.begin() + max_rays,
                        sensor_indices.end(),
                        [&](uint32_t a, uint32_t b) {
                          return distance(a) < distance(b);
                        });
      sensor_indices.resize(max_rays);
    }
    const double count = std::max<uint32_t>(counts[i], 1);
    double total_weight = options.lidar_weight;
    switch (mapping) {
      case LidarCountMapping::kNone:
        break;
      case LidarCountMapping::kLinear:
        total_weight *= count;
        break;
      case LidarCountMapping::kLog:
        total_weight *= 1.0 + std::log(count);
        break;
    }
    const float ray_weight =
        static_cast<float>(total_weight / sensor_indices.size());
    input->AddPoint(positions[i], MeshingPointSource::kLidar, ray_weight,
                    std::move(sensor_indices));
  }
}

namespace {

// Validates every segment of `segments` against `points` (the visual and
// LIDAR points of the input) on the threads; one INFO line of the outcome.
// Returns the validator's point spacing s, metres (0 when nothing was
// validated), and its plane band in *plane_band_m.
double ValidateLines(const MeshingInputOptions& options,
                     const std::vector<Eigen::Vector3d>& points,
                     int num_threads,
                     std::map<line3D_t, ValidatedLine>* segments,
                     double* plane_band_m) {
  *plane_band_m = 0;
  if (segments->empty()) return 0;
  if (points.size() <=
      static_cast<size_t>(options.line_validation.spacing_neighbor)) {
    LOG(WARNING) << "Line validation: too few surface points; every line "
                    "is left out";
    for (auto& [line3D_id, segment] : *segments) {
      segment.status = LineValidationStatus::kFewPoints;
    }
    return 0;
  }
  const LineValidator validator(options.line_validation, points);
  std::vector<std::pair<line3D_t, ValidatedLine*>> items;
  for (auto& [line3D_id, segment] : *segments) {
    items.emplace_back(line3D_id, &segment);
  }
  ParallelFor(0, static_cast<int>(items.size()), num_threads, [&](int i) {
    ValidatedLine& segment = *items[i].second;
    segment = validator.Validate(segment.start, segment.end, items[i].first);
  });
  std::array<size_t, kNumLineValidationStatuses> counts{};
  std::vector<double> offsets;
  size_t num_with_side_face = 0;
  for (const auto& [line3D_id, segment] : *segments) {
    ++counts[static_cast<int>(segment.status)];
    if (segment.status == LineValidationStatus::kCrease) {
      offsets.push_back(segment.offset_m);
      num_with_side_face += segment.with_side_face;
    }
  }
  std::ostringstream dropped;
  for (int status = 1; status < kNumLineValidationStatuses; ++status) {
    dropped << (status > 1 ? ", " : "")
            << LineValidationStatusName(
                   static_cast<LineValidationStatus>(status))
            << " " << counts[status];
  }
  double median_offset = 0;
  if (!offsets.empty()) {
    std::nth_element(offsets.begin(), offsets.begin() + offsets.size() / 2,
                     offsets.end());
    median_offset = offsets[offsets.size() / 2];
  }
  LOG(INFO) << "Line validation (point spacing " << validator.spacing()
            << " m, noise " << validator.noise() << " m, plane band +-"
            << validator.plane_tolerance() << " m): " << counts[0] << " of "
            << segments->size() << " 3D lines on a crease of the points ("
            << num_with_side_face
            << " with a step's side face: not sampled, only snapped to), "
               "moved onto it by "
            << median_offset << " m (median); left out: " << dropped.str();
  *plane_band_m = validator.plane_tolerance();
  return validator.spacing();
}

}  // namespace

size_t AddLineSamples(
    const MeshingInputOptions& options, const Reconstruction& dense_model,
    const Reconstruction& lines_model,
    const std::map<line3D_t, std::vector<LineObservedInterval>>* observations,
    MeshingInput* input) {
  size_t num_lines_used = 0;
  size_t num_samples = 0;
  size_t num_unobserved = 0;
  // The segments to sample: as estimated, or validated against the points
  // gathered so far (line_validation.h) and moved onto their crease.
  std::map<line3D_t, ValidatedLine> segments;
  for (const auto& [line3D_id, line3D] : lines_model.lines3D) {
    ValidatedLine& segment = segments[line3D_id];
    segment.status = LineValidationStatus::kCrease;
    segment.start = line3D.start_in_world;
    segment.end = line3D.end_in_world;
  }
  double spacing = 0;
  double plane_band_m = 0;
  if (options.validate_lines) {
    spacing = ValidateLines(options, input->positions, options.num_threads,
                            &segments, &plane_band_m);
  }
  // The step along the segments: as given, or the points' spacing (measured
  // here when the validation did not); with too few points to measure it,
  // only the end points.
  double step_m = options.line_sample_step_m;
  if (step_m == 0) {
    if (spacing == 0 && !segments.empty() &&
        input->positions.size() >
            static_cast<size_t>(options.line_validation.spacing_neighbor)) {
      spacing =
          LineValidator(options.line_validation, input->positions).spacing();
    }
    step_m = spacing > 0 ? spacing : std::numeric_limits<double>::infinity();
    if (!segments.empty()) {
      LOG(INFO) << "Line samples every " << step_m
                << " m (the surface points' spacing)";
    }
  }
  // The surface points the gaps are measured against (indexed before the
  // line samples are added, so those are not among them).
  std::unique_ptr<RadiusGrid> surface_grid;
  if (options.validate_lines && options.line_samples_only_in_gaps &&
      plane_band_m > 0) {
    surface_grid = std::make_unique<RadiusGrid>(input->positions, plane_band_m);
  }
  size_t num_covered = 0;
  for (const auto& [line3D_id, line3D] : lines_model.lines3D) {
    const ValidatedLine& segment = segments.at(line3D_id);
    if (segment.status != LineValidationStatus::kCrease) continue;
    // (sensor index, observed interval) of each image of the track.
    struct Observer {
      uint32_t sensor_idx;
      double t_begin;
      double t_end;
    };
    std::vector<Observer> observers;
    if (observations == nullptr) {
      for (const LineTrackElement& element : line3D.track) {
        const int image_idx = dense_model.ImageIndex(element.image_id);
        if (image_idx >= 0) {
          observers.push_back({static_cast<uint32_t>(image_idx),
                               -std::numeric_limits<double>::infinity(),
                               std::numeric_limits<double>::infinity()});
        }
      }
    } else if (const auto it = observations->find(line3D_id);
               it != observations->end()) {
      for (const LineObservedInterval& observation : it->second) {
        const int image_idx = dense_model.ImageIndex(observation.image_id);
        if (image_idx >= 0) {
          observers.push_back({static_cast<uint32_t>(image_idx),
                               observation.t_begin, observation.t_end});
        }
      }
    }
    if (observers.empty()) continue;
    const Eigen::Vector3d& start = segment.start;
    const Eigen::Vector3d& end = segment.end;
    const int num_steps =
        std::max(1, static_cast<int>(std::ceil((end - start).norm() / step_m)));
    // The per-view endpoints are as noisy as the LIDAR edge points they
    // came from: an image sees a sample one step beyond its interval too.
    const double tolerance = 1.0 / num_steps;
    // A crease with a step's side face is less certain (line_validation.h):
    // its samples would be hard vertices of the Delaunay meshing on it, and
    // on the benchmark matrix they cost precision near the creases
    // (matrix.md); the snapping, which moves a vertex only where the points
    // around it agree, uses it.
    const bool sample = !segment.with_side_face;
    size_t num_observed_samples = 0;
    for (int k = 0; k <= num_steps; ++k) {
      const double t = static_cast<double>(k) / num_steps;
      std::vector<uint32_t> sensor_indices;
      for (const Observer& observer : observers) {
        if (t >= observer.t_begin - tolerance &&
            t <= observer.t_end + tolerance) {
          sensor_indices.push_back(observer.sensor_idx);
        }
      }
      std::sort(sensor_indices.begin(), sensor_indices.end());
      sensor_indices.erase(
          std::unique(sensor_indices.begin(), sensor_indices.end()),
          sensor_indices.end());
      if (sensor_indices.empty()) {
        ++num_unobserved;
        continue;
      }
      ++num_observed_samples;
      if (!sample) continue;
      if (surface_grid != nullptr) {
        const Eigen::Vector3d position = start + t * (end - start);
        bool covered = false;
        surface_grid->ForEachNear(position, [&](uint32_t i) {
          if ((input->positions[i] - position).squaredNorm() <
              plane_band_m * plane_band_m) {
            covered = true;
          }
        });
        if (covered) {
          ++num_covered;
          continue;
        }
      }
      // Trusted like a visual point seen in as many images: the sample is
      // as well placed as the line (a few cm), no better than a fused
      // depth; a full-weight ray of each sample outweighed the dense points
      // near the crease and cost precision there (matrix.md).
      const double weight =
          options.line_weight *
          VisibilityProbability(options, sensor_indices.size());
      input->AddPoint(start + t * (end - start), MeshingPointSource::kLine,
                      static_cast<float>(weight), std::move(sensor_indices));
      ++num_samples;
    }
    ++num_lines_used;
    // A validated segment seen where it would be sampled knows the two
    // faces of its crease: the mesher snaps the mesh onto them.
    if (options.validate_lines && num_observed_samples > 0) {
      MeshCrease crease;
      crease.start = segment.start;
      crease.end = segment.end;
      crease.face_directions = segment.face_directions;
      crease.plane_band_m = plane_band_m;
      input->creases.push_back(crease);
      input->crease_spacing_m = spacing;
    }
  }
  size_t num_kept = 0;
  for (const auto& [line3D_id, segment] : segments) {
    num_kept += segment.status == LineValidationStatus::kCrease;
  }
  if (num_lines_used < num_kept) {
    LOG(WARNING) << num_kept - num_lines_used
                 << " 3D lines are seen by no image of the dense model";
  }
  if (num_covered > 0) {
    LOG(INFO) << num_covered
              << " line samples lie within the plane band of a surface point "
                 "and are not used";
  }
  if (num_unobserved > 0) {
    LOG(INFO) << num_unobserved
              << " line samples lie outside every observed part of their "
                 "line and are not used";
  }
  return num_samples;
}

MeshingInput ReadMeshingInput(const MeshingInputOptions& options,
                              const std::string& workspace_path,
                              const std::string& lines_model_path,
                              const std::string& database_path) {
  THROW_CHECK(options.Check(), "Invalid meshing input options");
  CheckDirExists(workspace_path, "Dense workspace");
  const DenseWorkspace workspace(workspace_path);
  const Reconstruction model = workspace.ReadModel();
  MeshingInput input;
  AddCameraSensors(model, &input);

  if (options.use_visual) {
    const std::string ply_path = workspace.FusedPlyPath();
    const std::string vis_path = workspace.FusedVisPath();
    CheckFileExists(ply_path, "Fused point cloud");
    CheckFileExists(vis_path, "Fused point visibility");
    const std::vector<PlyPoint> points = ReadPlyPoints(ply_path);
    const FusedVisibility visibility = ReadFusedVis(vis_path, points.size());
    CheckFusedVisIndices(visibility, model.images.size(), vis_path);
    std::vector<Eigen::Vector3d> positions;
    positions.reserve(points.size());
    for (const PlyPoint& point : points) {
      positions.push_back(point.xyz.cast<double>());
    }
    AddVisualPoints(options, positions, visibility, &input);
    LOG(INFO) << "Visual points: " << points.size() << " from " << ply_path;
  }

  const std::string lidar_ply_path = LidarFusedPlyPath(workspace_path);
  if (options.use_lidar && ExistsFile(lidar_ply_path)) {
    const std::string vis_path = LidarFusedVisPath(workspace_path);
    const std::string origins_path = LidarOriginsPath(workspace_path);
    CheckFileExists(vis_path, "LIDAR voxel visibility");
    CheckFileExists(origins_path, "LIDAR origins");
    const PlyData ply = ReadPly(lidar_ply_path);
    std::vector<Eigen::Vector3d> positions = ply.Positions(lidar_ply_path);
    std::vector<uint32_t> counts(positions.size(), 1);
    if (const PlyColumn* column = ply.FindColumn("count")) {
      for (size_t i = 0; i < counts.size(); ++i) {
        THROW_CHECK(column->values[i] >= 0,
                    lidar_ply_path << ": negative count at vertex " << i);
        counts[i] = static_cast<uint32_t>(column->values[i]);
      }
    } else {
      LOG(WARNING) << lidar_ply_path << " has no 'count'; using 1 per voxel";
    }
    DenoiseLidarVoxels(options.lidar_denoising, counts, options.num_threads,
                       &positions);
    const FusedVisibility frames = ReadFusedVis(vis_path, positions.size());
    CheckFusedVisIndices(frames, model.images.size(), vis_path);
    std::vector<Eigen::Vector3d> origins(model.images.size(),
                                         Eigen::Vector3d::Zero());
    std::vector<bool> has_origin(model.images.size(), false);
    for (const auto& [name, origin] : ReadLidarOrigins(origins_path)) {
      // (No lambda here: C++17 cannot capture a structured binding, and
      // clang refuses to.)
      const Image* image = model.FindImageByName(name);
      const int image_idx =
          image == nullptr ? -1 : model.ImageIndex(image->image_id);
      if (image_idx < 0) {
        LOG(WARNING) << origins_path << ": image " << name
                     << " is not in the workspace model";
        continue;
      }
      origins[image_idx] = origin;
      has_origin[image_idx] = true;
    }
    AddLidarPoints(options, positions, counts, frames, origins, has_origin,
                   vis_path + " / " + origins_path, &input);
    LOG(INFO) << "LIDAR voxels: " << positions.size() << " from "
              << lidar_ply_path;
  } else if (options.use_lidar) {
    LOG(INFO) << "No " << lidar_ply_path << "; meshing without LIDAR";
  }

  if (!lines_model_path.empty()) {
    CheckDirExists(lines_model_path, "Lines model");
    const Reconstruction lines_model = ReadReconstruction(lines_model_path);
    THROW_CHECK(!lines_model.lines3D.empty(),
                "No lines3D.bin/.txt with lines in " << lines_model_path);
    std::map<line3D_t, std::vector<LineObservedInterval>> observations;
    if (!database_path.empty()) {
      // Under mpirun rank 0 alone opens the database (SQLite's write-ahead
      // log needs memory shared by the processes that open it, which ranks
      // on different machines do not share; process_group.h) and sends the
      // observations to the others.
      const ProcessGroup& group = ProcessGroup::World();
      std::exception_ptr error;
      if (group.IsRoot()) {
        try {
          CheckFileExists(database_path, "Database");
          const Database database(database_path);
          observations = ReadLineObservations(lines_model, database);
        } catch (...) {
          error = std::current_exception();
        }
      }
      group.CheckAllOk(error, "reading the line observations");
      if (group.Distributed()) {
        std::string bytes = group.IsRoot()
                                ? SerializeLineObservations(observations)
                                : std::string();
        group.Broadcast(&bytes);
        if (!group.IsRoot()) observations = DeserializeLineObservations(bytes);
      }
    } else {
      LOG(WARNING) << "No database of the line segments: every image of a "
                      "line's track is taken to see the whole line";
    }
    const size_t num_samples = AddLineSamples(
        options, model, lines_model,
        database_path.empty() ? nullptr : &observations, &input);
    LOG(INFO) << "Line samples: " << num_samples << " from "
              << lines_model.lines3D.size() << " 3D lines in "
              << lines_model_path;
  }

  THROW_CHECK(input.NumPoints() > 0,
              "No input points for meshing in " << workspace_path);
  input.Check();
  return input;
}

}  // namespace colmap_lidar
