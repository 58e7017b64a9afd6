#include "src/synth/synthesize.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <utility>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "colmap_ext/mvs/dense_maps.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "src/dataset/calibration.h"
#include "src/dataset/poses.h"
#include "src/lidar/scan_io.h"
#include "src/synth/lidar_simulator.h"
#include "src/synth/ray_tracer.h"
#include "src/synth/renderer.h"
#include "src/synth/scene_presets.h"
#include "src/synth/trajectory.h"

namespace colmap_lidar {
namespace {

std::string PriorNoiseComment(const SynthesisOptions& options) {
  std::ostringstream comment;
  comment << "Synthetic prior poses (world_from_cam, frame tx ty tz qx qy qz "
             "qw): the ground truth with\n"
          << "per-axis Gaussian noise of std "
          << options.prior_translation_sigma_m
          << " m on the camera centre and a rotation about a uniformly\n"
          << "random axis by a Gaussian angle of std "
          << options.prior_rotation_sigma_deg
          << " deg (R_prior = Exp(angle * axis) * R_gt), seed "
          << options.seed << ".";
  return comment.str();
}

std::string FormatOptions(const SynthesisOptions& o) {
  std::ostringstream out;
  out << std::setprecision(17);
  out << "preset = " << o.preset << "\n"
      << "num_frames = " << o.num_frames << "\n"
      << "length_factor = " << o.length_factor << "\n"
      << "seed = " << o.seed << "\n"
      << "image_width = " << o.image_width << "\n"
      << "image_height = " << o.image_height << "\n"
      << "horizontal_fov_deg = " << o.horizontal_fov_deg << "\n"
      << "camera_model = " << o.camera_model << "\n"
      << "camera_k1 = " << o.camera_k1 << "\n"
      << "camera_k2 = " << o.camera_k2 << "\n"
      << "camera_p1 = " << o.camera_p1 << "\n"
      << "camera_p2 = " << o.camera_p2 << "\n"
      << "supersampling = " << o.supersampling << "\n"
      << "image_noise_stddev = " << o.image_noise_stddev << "\n"
      << "sun_elevation_deg = " << o.sun_elevation_deg << "\n"
      << "sun_azimuth_deg = " << o.sun_azimuth_deg << "\n"
      << "lidar_model = " << o.lidar_model << "\n"
      << "lidar_rings = " << o.lidar_rings << "\n"
      << "lidar_columns = " << o.lidar_columns << "\n"
      << "lidar_vertical_fov_min_deg = " << o.lidar_vertical_fov_min_deg << "\n"
      << "lidar_vertical_fov_max_deg = " << o.lidar_vertical_fov_max_deg << "\n"
      << "lidar_range_noise_m = " << o.lidar_range_noise_m << "\n"
      << "lidar_dropout_probability = " << o.lidar_dropout_probability << "\n"
      << "lidar_grazing_dropout = " << o.lidar_grazing_dropout << "\n"
      << "lidar_min_range_m = " << o.lidar_min_range_m << "\n"
      << "lidar_max_range_m = " << o.lidar_max_range_m << "\n"
      << "prior_translation_sigma_m = " << o.prior_translation_sigma_m << "\n"
      << "prior_rotation_sigma_deg = " << o.prior_rotation_sigma_deg << "\n"
      << "survey_num_stations = " << o.survey_num_stations << "\n"
      << "survey_height_m = " << o.survey_height_m << "\n"
      << "survey_angular_step_deg = " << o.survey_angular_step_deg << "\n"
      << "survey_range_noise_m = " << o.survey_range_noise_m << "\n"
      << "survey_voxel_size_m = " << o.survey_voxel_size_m << "\n"
      << "survey_max_points = " << o.survey_max_points << "\n"
      << "write_depth_maps = " << o.write_depth_maps << "\n";
  return out.str();
}

// The LIDAR unit and its beam layout in words.
std::string LidarReadme(const SynthesisOptions& options) {
  const LidarGeometry geometry = SynthLidarGeometry(options);
  std::ostringstream out;
  out << "LIDAR " << geometry.model << ": "
      << geometry.ring_elevations_deg.size() << " rings, elevations from "
      << geometry.MinElevationDeg() << " to " << geometry.MaxElevationDeg()
      << " deg";
  if (geometry.model == "HDL-64E") {
    out << " in two uniform blocks of 32 ([-24.9, -8.87] and [-8.33, 2] "
           "deg)";
  } else {
    out << " (uniform)";
  }
  out << ", " << geometry.columns << " columns (azimuth 2 pi c / "
      << geometry.columns << " from +x towards +y).";
  return out.str();
}

std::string GroundTruthReadme(const SynthesisOptions& options,
                              const SynthScene& scene,
                              const std::vector<Eigen::Vector3d>& stations) {
  std::ostringstream out;
  out << "# Synthetic dataset `" << scene.name
      << "` (colmap-lidar synthesize)\n\n"
      << "World frame: metres, z up, ground plane z = 0. Camera frame: x "
         "right, y down, z forward.\n"
      << (scene.notes.empty() ? std::string() : scene.notes + "\n")
      << "Rig layout: docs/dataset-format.md (calibration.yaml, images/, "
         "lidar/, poses_*.txt, reference.ply).\n\n"
      << "## Files\n"
      << "- `poses_gt.txt`: exact camera poses (world_from_cam).\n"
      << "- `poses_prior.txt`: " << PriorNoiseComment(options) << "\n"
      << "- `lidar/<frame>.ply`: " << LidarReadme(options)
      << " Points in the LIDAR frame (x "
         "forward, y left, z up), x y z float32, intensity float32 in [0, 1] "
         "(albedo x |cos incidence|), ring uint16 (0 = lowest beam); range "
         "noise Gaussian, std "
      << options.lidar_range_noise_m
      << " m along the beam; a return is kept with probability (1 - "
      << options.lidar_dropout_probability << ") * (1 - "
      << options.lidar_grazing_dropout
      << " * (1 - |cos incidence|)). world_from_lidar = world_from_cam * "
         "cam_from_lidar (p_cam = cam_from_lidar * p_lidar).\n"
      << "- `reference.ply`: simulated survey from " << stations.size()
      << " tripod stations (world frame, x y z float32), range noise std "
      << options.survey_range_noise_m << " m, one point per "
      << options.survey_voxel_size_m
      << " m voxel; only surfaces seen from the stations.\n"
      << "- `ground_truth/scene.ply`: the scene mesh (vertex x y z float32, "
         "material uchar; faces). Materials: ";
  for (int m = 0; m < kNumMaterials; ++m) {
    out << (m > 0 ? ", " : "") << m << " = "
        << MaterialName(static_cast<Material>(m));
  }
  out << ".\n"
      << "- `ground_truth/crease_edges.txt`: 3D segments where two planar "
         "surfaces meet at an angle (building corners and roof lines, "
         "wall-ground lines, window/door recess lips and backs, sills, "
         "boxes, cylinder rims), on surfaces facing the courtyard/street; one "
         "per line `x1 y1 z1 x2 y2 z2 n1x n1y n1z n2x n2y n2z convex "
         "angle_deg` (outward normals of the two faces; convex 1 = outer "
         "corner).\n"
      << (scene.paint_edges.empty()
              ? std::string()
              : "- `ground_truth/paint_edges.txt`: borders of the painted "
                "road marks (lane lines, crossing bars), flat on the road: "
                "image edges that are NOT crease edges (no depth change); "
                "one per line `x1 y1 z1 x2 y2 z2`.\n")
      << "- `ground_truth/depth_maps/<frame>.bin`: COLMAP Mat (`W&H&1&` + "
         "float32), camera-frame z-depth of the ray through image point "
         "(col, row) WITHOUT +0.5 (COLMAP's MVS pixel convention), for the "
         "same (distorted) camera as the image: X_cam = depth * [x, y, 1] "
         "with (x, y) = CamFromImg(col, row) of calibration.yaml's camera "
         "(the model's undistortion of the point (col, row); for PINHOLE "
         "K^-1 [col, row, 1]); 0 where the ray hits nothing.\n"
      << "- Images: camera " << options.camera_model
      << " (calibration.yaml), rendered distorted: pixel (col, row) is the "
         "average of "
      << options.supersampling * options.supersampling
      << " rays through the undistortion (CamFromImg) of points on a "
         "regular grid inside [col, col+1] x [row, row+1] (SfM convention, "
         "centre at +0.5), Lambertian sun + sky shading with hard shadows, "
         "gamma 2.2, Gaussian noise std "
      << options.image_noise_stddev << " grey levels.\n\n"
      << "## Survey stations (world)\n";
  for (const Eigen::Vector3d& station : stations) {
    out << "- " << station.x() << " " << station.y() << " " << station.z()
        << "\n";
  }
  out << "\n## Options\n```\n" << FormatOptions(options) << "```\n";
  return out.str();
}

bool IsNonEmptyDir(const std::string& path) {
  return ExistsDir(path) && !std::filesystem::is_empty(path);
}

}  // namespace

Camera SynthCamera(const SynthesisOptions& options) {
  const double focal = 0.5 * options.image_width /
                       std::tan(0.5 * options.horizontal_fov_deg * M_PI / 180.0);
  const double cx = 0.5 * options.image_width;
  const double cy = 0.5 * options.image_height;
  std::vector<double> params;
  if (options.camera_model == "PINHOLE") {
    params = {focal, focal, cx, cy};
  } else if (options.camera_model == "SIMPLE_RADIAL") {
    params = {focal, cx, cy, options.camera_k1};
  } else if (options.camera_model == "RADIAL") {
    params = {focal, cx, cy, options.camera_k1, options.camera_k2};
  } else if (options.camera_model == "OPENCV") {
    params = {focal,
              focal,
              cx,
              cy,
              options.camera_k1,
              options.camera_k2,
              options.camera_p1,
              options.camera_p2};
  } else {
    THROW_CHECK(false, "Synthesis.camera_model must be PINHOLE, "
                       "SIMPLE_RADIAL, RADIAL or OPENCV, got '"
                           << options.camera_model << "'");
  }
  return Camera::FromModelName(options.camera_model, options.image_width,
                               options.image_height, params);
}

std::string SynthCameraProblem(const SynthesisOptions& options) {
  const std::string& model = options.camera_model;
  std::ostringstream problem;
  if (model != "PINHOLE" && model != "SIMPLE_RADIAL" && model != "RADIAL" &&
      model != "OPENCV") {
    problem << "Synthesis.camera_model must be PINHOLE, SIMPLE_RADIAL, "
               "RADIAL or OPENCV, got '"
            << model << "'";
    return problem.str();
  }
  const bool has_k1 = model != "PINHOLE";
  const bool has_k2 = model == "RADIAL" || model == "OPENCV";
  const bool has_p = model == "OPENCV";
  const std::pair<const char*, std::pair<double, bool>> coefficients[] = {
      {"camera_k1", {options.camera_k1, has_k1}},
      {"camera_k2", {options.camera_k2, has_k2}},
      {"camera_p1", {options.camera_p1, has_p}},
      {"camera_p2", {options.camera_p2, has_p}}};
  for (const auto& [name, value_and_used] : coefficients) {
    if (!std::isfinite(value_and_used.first)) {
      problem << "Synthesis." << name << " is not finite";
      return problem.str();
    }
    if (!value_and_used.second && value_and_used.first != 0.0) {
      problem << "Synthesis." << name << " = " << value_and_used.first
              << " but camera model " << model
              << " has no such coefficient (use a model that has it, or 0)";
      return problem.str();
    }
  }
  if (model == "PINHOLE" || options.image_width < 1 ||
      options.image_height < 1 || !(options.horizontal_fov_deg > 0.0) ||
      !(options.horizontal_fov_deg < 180.0)) {
    return "";  // Nothing to invert (other options checked elsewhere).
  }
  const Camera camera = SynthCamera(options);
  const Eigen::Vector2d centre(0.5 * options.image_width,
                               0.5 * options.image_height);
  // Rays from the principal point to points all around the border (every
  // ~16 pixels and the corners), sampled every ~4 pixels.
  const double w = static_cast<double>(camera.width);
  const double h = static_cast<double>(camera.height);
  std::vector<Eigen::Vector2d> border;
  const int steps_x = std::max(1, static_cast<int>(w / 16));
  const int steps_y = std::max(1, static_cast<int>(h / 16));
  for (int i = 0; i <= steps_x; ++i) {
    border.emplace_back(w * i / steps_x, 0.0);
    border.emplace_back(w * i / steps_x, h);
  }
  for (int i = 0; i <= steps_y; ++i) {
    border.emplace_back(0.0, h * i / steps_y);
    border.emplace_back(w, h * i / steps_y);
  }
  for (const Eigen::Vector2d& end : border) {
    const int samples =
        std::max(2, static_cast<int>((end - centre).norm() / 4.0));
    double previous_radius = -1.0;
    for (int k = 1; k <= samples; ++k) {
      const Eigen::Vector2d pixel = centre + (end - centre) * k / samples;
      const Eigen::Vector2d normalised = camera.CamFromImg(pixel);
      const Eigen::Vector2d back =
          camera.ImgFromCam(Eigen::Vector3d(normalised.x(), normalised.y(), 1));
      const double radius = normalised.norm();
      if (!normalised.allFinite() || (back - pixel).norm() > 1e-6 ||
          !(radius > previous_radius)) {
        problem << "Synthesis.camera_model " << model << " with k1 "
                << options.camera_k1 << ", k2 " << options.camera_k2
                << ", p1 " << options.camera_p1 << ", p2 "
                << options.camera_p2
                << ": the distortion is not invertible at pixel ("
                << pixel.x() << ", " << pixel.y() << ") of the "
                << camera.width << " x " << camera.height
                << " image (it folds over); use smaller coefficients or a "
                   "smaller horizontal_fov_deg";
        return problem.str();
      }
      previous_radius = radius;
    }
  }
  return "";
}

Rigid3d SynthCamFromLidar() {
  Eigen::Matrix3d cam_from_lidar_rotation;
  cam_from_lidar_rotation << 0, -1, 0,  //
      0, 0, -1,                         //
      1, 0, 0;
  // The LIDAR origin in the camera frame: 10 cm up (-y), 4 cm behind (-z).
  return Rigid3d(Eigen::Quaterniond(cam_from_lidar_rotation),
                 Eigen::Vector3d(0.0, -0.10, -0.04));
}

std::string SynthFrameName(int frame_index) {
  std::ostringstream name;
  name << std::setw(6) << std::setfill('0') << frame_index;
  return name.str();
}

void WriteCreaseEdges(const std::string& path,
                      const std::vector<CreaseEdge>& edges) {
  WriteFileAtomically(
      path,
      [&](std::ostream& out) {
        out << "# Crease edges (world frame, metres): x1 y1 z1 x2 y2 z2 n1x "
               "n1y n1z n2x n2y n2z convex angle_deg\n";
        out << "# n1, n2: outward unit normals of the two faces; convex 1 = "
               "outer corner, 0 = inner corner.\n";
        out << "# Number of edges: " << edges.size() << "\n";
        out << std::setprecision(9);
        for (const CreaseEdge& edge : edges) {
          out << edge.start.x() << " " << edge.start.y() << " "
              << edge.start.z() << " " << edge.end.x() << " " << edge.end.y()
              << " " << edge.end.z() << " " << edge.normal1.x() << " "
              << edge.normal1.y() << " " << edge.normal1.z() << " "
              << edge.normal2.x() << " " << edge.normal2.y() << " "
              << edge.normal2.z() << " " << (edge.convex ? 1 : 0) << " "
              << edge.AngleDeg() << "\n";
        }
      },
      /*binary=*/false);
}

std::vector<CreaseEdge> ReadCreaseEdges(const std::string& path) {
  std::istringstream in(ReadTextFile(path));
  std::vector<CreaseEdge> edges;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    CreaseEdge edge;
    int convex = 0;
    double angle = 0.0;
    fields >> edge.start.x() >> edge.start.y() >> edge.start.z() >>
        edge.end.x() >> edge.end.y() >> edge.end.z() >> edge.normal1.x() >>
        edge.normal1.y() >> edge.normal1.z() >> edge.normal2.x() >>
        edge.normal2.y() >> edge.normal2.z() >> convex >> angle;
    THROW_CHECK(!fields.fail(), "Malformed crease edge in " << path << " line "
                                                            << line_number);
    edge.convex = convex != 0;
    edges.push_back(edge);
  }
  return edges;
}

void WritePaintEdges(const std::string& path,
                     const std::vector<PaintEdge>& edges) {
  WriteFileAtomically(
      path,
      [&](std::ostream& out) {
        out << "# Paint edges (world frame, metres): x1 y1 z1 x2 y2 z2\n";
        out << "# Borders of painted road marks: image edges on flat ground, "
               "not crease edges.\n";
        out << "# Number of edges: " << edges.size() << "\n";
        out << std::setprecision(9);
        for (const PaintEdge& edge : edges) {
          out << edge.start.x() << " " << edge.start.y() << " "
              << edge.start.z() << " " << edge.end.x() << " " << edge.end.y()
              << " " << edge.end.z() << "\n";
        }
      },
      /*binary=*/false);
}

std::vector<PaintEdge> ReadPaintEdges(const std::string& path) {
  std::istringstream in(ReadTextFile(path));
  std::vector<PaintEdge> edges;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    PaintEdge edge;
    fields >> edge.start.x() >> edge.start.y() >> edge.start.z() >>
        edge.end.x() >> edge.end.y() >> edge.end.z();
    THROW_CHECK(!fields.fail(), "Malformed paint edge in " << path << " line "
                                                           << line_number);
    edges.push_back(edge);
  }
  return edges;
}

void WriteSceneMesh(const std::string& path, const SceneMesh& mesh) {
  PlyData ply;
  std::vector<double> xs, ys, zs, materials;
  const std::vector<Material> vertex_materials = mesh.VertexMaterials();
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    xs.push_back(mesh.vertices[i].x());
    ys.push_back(mesh.vertices[i].y());
    zs.push_back(mesh.vertices[i].z());
    materials.push_back(static_cast<double>(vertex_materials[i]));
  }
  ply.AddColumn("x", PlyScalarType::kFloat32, std::move(xs));
  ply.AddColumn("y", PlyScalarType::kFloat32, std::move(ys));
  ply.AddColumn("z", PlyScalarType::kFloat32, std::move(zs));
  ply.AddColumn("material", PlyScalarType::kUInt8, std::move(materials));
  for (const Eigen::Vector3i& triangle : mesh.triangles) {
    ply.faces.push_back({static_cast<uint32_t>(triangle(0)),
                         static_cast<uint32_t>(triangle(1)),
                         static_cast<uint32_t>(triangle(2))});
  }
  WritePly(path, ply);
}

SynthesisSummary SynthesizeDataset(const SynthesisOptions& options,
                                   const std::string& output_path) {
  const auto start_time = std::chrono::steady_clock::now();
  THROW_CHECK(options.Check(), "Invalid Synthesis options (see the log)");
  THROW_CHECK(!output_path.empty(), "Empty output path");
  THROW_CHECK(options.overwrite || !IsNonEmptyDir(output_path),
              "Output folder " << output_path
                               << " exists and is not empty; pass "
                                  "--Synthesis.overwrite 1 to replace it");
  THROW_CHECK(!ExistsFile(output_path) || ExistsDir(output_path),
              "Output path " << output_path << " is a file");

  const SynthScene scene = BuildScene(options.preset, options.length_factor);
  const RayTracer tracer(scene.mesh);
  LOG(INFO) << "Scene " << scene.name << ": " << scene.mesh.NumTriangles()
            << " triangles, " << scene.crease_edges.size() << " crease edges"
            << (scene.paint_edges.empty()
                    ? std::string()
                    : ", " + std::to_string(scene.paint_edges.size()) +
                          " paint edges");

  const Camera camera = SynthCamera(options);
  const Rigid3d cam_from_lidar = SynthCamFromLidar();
  const std::vector<Rigid3d> gt_poses =
      GenerateTrajectory(scene.path, options.num_frames, options.seed,
                         options.path_fraction);
  const std::vector<Rigid3d> prior_poses =
      PerturbPoses(gt_poses, options.prior_translation_sigma_m,
                   options.prior_rotation_sigma_deg, options.seed);

  StagedDirectory staged(output_path);
  const std::string root = staged.path();
  const std::string image_dir = JoinPaths(root, "images");
  const std::string lidar_dir = JoinPaths(root, "lidar");
  const std::string truth_dir = JoinPaths(root, "ground_truth");
  const std::string depth_dir = JoinPaths(truth_dir, "depth_maps");
  for (const std::string& dir : {image_dir, lidar_dir, truth_dir}) {
    CreateDirIfNotExists(dir);
  }
  if (options.write_depth_maps) CreateDirIfNotExists(depth_dir);

  SynthesisSummary summary;
  summary.num_frames = options.num_frames;
  summary.num_triangles = scene.mesh.NumTriangles();
  summary.num_crease_edges = scene.crease_edges.size();
  summary.num_paint_edges = scene.paint_edges.size();
  std::vector<FramePose> gt_frames;
  std::vector<FramePose> prior_frames;
  for (int i = 0; i < options.num_frames; ++i) {
    const std::string frame = SynthFrameName(i);
    const RenderedFrame rendered = RenderFrame(
        tracer, camera, gt_poses[i], options, i, options.write_depth_maps);
    const std::string image_path = JoinPaths(image_dir, frame + ".png");
    THROW_CHECK(cv::imwrite(image_path, rendered.image),
                "Cannot write " << image_path);
    if (options.write_depth_maps) {
      DepthMap depth_map(camera.width, camera.height);
      for (int row = 0; row < rendered.depth.rows; ++row) {
        for (int col = 0; col < rendered.depth.cols; ++col) {
          depth_map.Set(row, col, rendered.depth.at<float>(row, col));
        }
      }
      depth_map.Write(JoinPaths(depth_dir, frame + ".bin"));
    }
    // p_world = world_from_cam * cam_from_lidar * p_lidar.
    const Rigid3d world_from_lidar = gt_poses[i] * cam_from_lidar;
    const LidarScan scan =
        SimulateLidarScan(tracer, world_from_lidar, options, i);
    summary.num_lidar_points += scan.size();
    WriteLidarScanPly(JoinPaths(lidar_dir, frame + ".ply"), scan);
    gt_frames.push_back({frame, gt_poses[i]});
    prior_frames.push_back({frame, prior_poses[i]});
    LOG(INFO) << "Frame " << frame << ": image, " << scan.size()
              << " LIDAR points";
  }

  RigCalibration calibration;
  calibration.camera = camera;
  calibration.cam_from_lidar = cam_from_lidar;
  // calibration.yaml carries the ring count and the vertical extent; the
  // per-ring elevations (non-uniform for HDL-64E) are in the scans' ring
  // channel and in ground_truth/README.md.
  const LidarGeometry lidar_geometry = SynthLidarGeometry(options);
  LidarDescription lidar;
  lidar.rings = static_cast<int>(lidar_geometry.ring_elevations_deg.size());
  lidar.vertical_fov_min_deg = lidar_geometry.MinElevationDeg();
  lidar.vertical_fov_max_deg = lidar_geometry.MaxElevationDeg();
  lidar.range_noise_m = options.lidar_range_noise_m;
  calibration.lidar = lidar;
  WriteCalibration(JoinPaths(root, "calibration.yaml"), calibration);
  WritePoses(JoinPaths(root, "poses_gt.txt"), gt_frames,
             "Synthetic ground-truth poses (world_from_cam), preset " +
                 scene.name + ".");
  WritePoses(JoinPaths(root, "poses_prior.txt"), prior_frames,
             PriorNoiseComment(options));

  std::vector<Eigen::Vector3d> stations;
  for (int s = 0; s < options.survey_num_stations; ++s) {
    const Eigen::Vector2d& xy =
        scene.survey_stations[s % scene.survey_stations.size()];
    // Stations beyond the preset's list are shifted by 1 m per round.
    const double shift =
        static_cast<double>(s / scene.survey_stations.size());
    stations.emplace_back(xy.x() + shift, xy.y(), options.survey_height_m);
  }
  if (!stations.empty()) {
    const std::vector<Eigen::Vector3f> reference =
        SimulateSurvey(tracer, stations, options);
    summary.num_reference_points = reference.size();
    PlyData ply;
    for (int k = 0; k < 3; ++k) {
      std::vector<double> values(reference.size());
      for (size_t i = 0; i < reference.size(); ++i) values[i] = reference[i](k);
      ply.AddColumn(k == 0 ? "x" : (k == 1 ? "y" : "z"),
                    PlyScalarType::kFloat32, std::move(values));
    }
    WritePly(JoinPaths(root, "reference.ply"), ply);
  }

  WriteSceneMesh(JoinPaths(truth_dir, "scene.ply"), scene.mesh);
  WriteCreaseEdges(JoinPaths(truth_dir, "crease_edges.txt"),
                   scene.crease_edges);
  if (!scene.paint_edges.empty()) {
    WritePaintEdges(JoinPaths(truth_dir, "paint_edges.txt"),
                    scene.paint_edges);
  }
  const std::string readme = GroundTruthReadme(options, scene, stations);
  WriteFileAtomically(
      JoinPaths(truth_dir, "README.md"),
      [&](std::ostream& out) { out << readme; }, /*binary=*/false);

  staged.Commit();
  summary.seconds = std::chrono::duration<double>(
                        std::chrono::steady_clock::now() - start_time)
                        .count();
  LOG(INFO) << "Synthesised " << summary.num_frames << " frames, "
            << summary.num_lidar_points << " LIDAR points, "
            << summary.num_reference_points << " reference points in "
            << summary.seconds << " s into " << output_path;
  return summary;
}

}  // namespace colmap_lidar
