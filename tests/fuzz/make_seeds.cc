// Writes the seed corpora of the fuzz targets from real files: the KITTI raw
// sample (calibration files, Velodyne scans) and a synthesized rig recording
// (calibration.yaml, poses, PLY scans, the reference cloud, ground-truth depth
// maps). Large files are shrunk by re-encoding a few of their records with
// our writers, so that every seed stays a well-formed file of a few KB.
//
// Usage: make_seeds <corpus_root> <kitti_date_dir> <synthesized_dataset_dir>
// Writes <corpus_root>/<target>/<seed> for each target of tests/fuzz.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>

#include "colmap_ext/model/model_io.h"
#include "colmap_ext/mvs/dense_maps.h"
#include "colmap_ext/mvs/fused_vis.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/ply.h"
#include "src/dataset/calibration.h"
#include "src/dataset/poses.h"
#include "src/lidar/scan_io.h"
#include "tests/fuzz/fuzz_db_input.h"

namespace fs = std::filesystem;
using namespace colmap_lidar;

namespace {

std::string g_root;

std::string SeedPath(const std::string& target, const std::string& name) {
  const fs::path dir = fs::path(g_root) / target;
  fs::create_directories(dir);
  return (dir / name).string();
}

void WriteSeed(const std::string& target, const std::string& name,
               const std::string& content) {
  std::ofstream file(SeedPath(target, name), std::ios::binary);
  file << content;
}

std::string FirstFile(const std::string& dir, const std::string& extension) {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == extension) {
      files.push_back(entry.path().string());
    }
  }
  THROW_CHECK(!files.empty(), "No " << extension << " file in " << dir);
  std::sort(files.begin(), files.end());
  return files.front();
}

// Every `step`-th point, at most `max_points`, keeping the channels.
LidarScan Subsample(const LidarScan& scan, size_t max_points) {
  LidarScan small;
  const size_t step = std::max<size_t>(1, scan.size() / max_points);
  for (size_t i = 0; i < scan.size() && small.size() < max_points; i += step) {
    small.points.push_back(scan.points[i]);
    if (scan.HasIntensities()) small.intensities.push_back(scan.intensities[i]);
    if (scan.HasRings()) small.rings.push_back(scan.rings[i]);
  }
  return small;
}

std::string ReadBytes(const std::string& path, size_t max_bytes) {
  std::string content = ReadTextFile(path);
  if (content.size() > max_bytes) content.resize(max_bytes);
  return content;
}

// First lines of a text file.
std::string HeadLines(const std::string& path, int num_lines) {
  std::istringstream content(ReadTextFile(path));
  std::string line;
  std::string head;
  for (int i = 0; i < num_lines && std::getline(content, line); ++i) {
    head += line + "\n";
  }
  return head;
}

void ScanSeeds(const std::string& kitti_dir, const std::string& synth_dir) {
  // KITTI Velodyne: real records, 64 points (1 KB).
  const std::string kitti_scan =
      FirstFile(kitti_dir + "/velodyne_points/data", ".bin");
  WriteSeed("kitti_bin", "kitti_64_points.bin", ReadBytes(kitti_scan, 64 * 16));
  WriteSeed("kitti_bin", "kitti_1_point.bin", ReadBytes(kitti_scan, 16));
  const LidarScan kitti = Subsample(ReadLidarScan(kitti_scan), 48);

  // Synthesized scan with rings and intensities.
  const LidarScan synth =
      Subsample(ReadLidarScan(FirstFile(synth_dir + "/lidar", ".ply")), 48);

  WriteLidarScanPly(SeedPath("ply", "synth_scan_binary.ply"), synth, true);
  WriteLidarScanPly(SeedPath("ply", "synth_scan_ascii.ply"), synth, false);
  WriteLidarScanPly(SeedPath("ply", "kitti_scan_ascii.ply"), kitti, false);
  for (const auto& [name, format] :
       {std::pair<const char*, PcdFormat>{"ascii", PcdFormat::kAscii},
        {"binary", PcdFormat::kBinary},
        {"binary_compressed", PcdFormat::kBinaryCompressed}}) {
    WriteLidarScanPcd(SeedPath("pcd", std::string("synth_") + name + ".pcd"),
                      synth, format);
    WriteLidarScanPcd(SeedPath("pcd", std::string("kitti_") + name + ".pcd"),
                      kitti, format);
  }

  // The reference cloud: a few vertices with all their columns, plus a small
  // mesh with faces and a COLMAP fused.ply record layout.
  PlyData reference = ReadPly(synth_dir + "/reference.ply");
  for (PlyColumn& column : reference.vertex_columns) {
    column.values.resize(std::min<size_t>(column.values.size(), 24));
  }
  reference.faces.clear();
  WritePly(SeedPath("ply", "reference_binary.ply"), reference);
  WritePly(SeedPath("ply", "reference_ascii.ply"), reference, PlyFormat::kAscii);
  PlyData mesh;
  const std::vector<Eigen::Vector3d> positions = reference.Positions();
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> values;
    for (size_t i = 0; i < 4 && i < positions.size(); ++i) {
      values.push_back(positions[i](axis));
    }
    mesh.AddColumn(std::string(1, "xyz"[axis]), PlyScalarType::kFloat32, values);
  }
  mesh.faces = {{0, 1, 2}, {0, 2, 3}};
  WritePly(SeedPath("ply", "mesh_binary.ply"), mesh);
  WritePly(SeedPath("ply", "mesh_ascii.ply"), mesh, PlyFormat::kAscii);
  std::vector<PlyPoint> fused(6);
  for (size_t i = 0; i < fused.size(); ++i) {
    fused[i].xyz = kitti.points[i];
    fused[i].normal = Eigen::Vector3f(0, 0, 1);
    fused[i].rgb = {static_cast<uint8_t>(10 * i), 128, 255};
  }
  WriteColmapPlyPoints(SeedPath("ply", "fused.ply"), fused);
}

void DatasetSeeds(const std::string& kitti_dir, const std::string& synth_dir) {
  WriteSeed("calibration", "synth_calibration.yaml",
            ReadTextFile(synth_dir + "/calibration.yaml"));
  // The same rig with a distorted camera and a LIDAR description.
  RigCalibration calibration = ReadCalibration(synth_dir + "/calibration.yaml");
  const Camera& pinhole = calibration.camera;
  calibration.camera = Camera::FromModelName(
      "OPENCV", pinhole.width, pinhole.height,
      {pinhole.params[0], pinhole.params[1], pinhole.params[2],
       pinhole.params[3], -0.1, 0.01, 0.001, -0.001});
  calibration.lidar = LidarDescription{64, -22.5, 22.5, 0.01};
  WriteCalibration(SeedPath("calibration", "opencv_calibration.yaml"),
                   calibration);

  WriteSeed("poses", "synth_poses_prior.txt",
            HeadLines(synth_dir + "/poses_prior.txt", 6));
  WriteSeed("poses", "synth_poses_gt.txt",
            HeadLines(synth_dir + "/poses_gt.txt", 4));

  WriteSeed("kitti_calib", "kitti_2011_09_26.txt",
            ReadTextFile(kitti_dir + "/calib_cam_to_cam.txt") + "\n%%\n" +
                ReadTextFile(kitti_dir + "/calib_velo_to_cam.txt"));
}

// A small model over the synthesized recording: the prior poses of three
// frames, points seen by all three, lines seen by two.
Reconstruction SmallModel(const std::string& synth_dir) {
  const RigCalibration calibration =
      ReadCalibration(synth_dir + "/calibration.yaml");
  const std::vector<FramePose> poses =
      ReadPoses(synth_dir + "/poses_prior.txt");
  Reconstruction model;
  Camera camera = calibration.camera;
  camera.camera_id = 1;
  model.cameras[1] = camera;
  Camera opencv = Camera::FromModelName(
      "OPENCV", camera.width, camera.height,
      {camera.params[0], camera.params[1], camera.params[2], camera.params[3],
       -0.1, 0.01, 0.001, -0.001});
  opencv.camera_id = 2;
  model.cameras[2] = opencv;
  for (size_t i = 0; i < 3 && i < poses.size(); ++i) {
    Image image;
    image.image_id = static_cast<image_t>(i + 1);
    image.name = poses[i].frame + ".png";
    image.camera_id = i == 2 ? 2 : 1;
    image.cam_from_world = poses[i].world_from_cam.Inverse();
    model.images.push_back(image);
  }
  for (point3D_t point3D_id = 1; point3D_id <= 4; ++point3D_id) {
    Point3D point3D;
    point3D.xyz = Eigen::Vector3d(point3D_id, 0.5 * point3D_id, 10.0);
    point3D.color = Vector3ub(200, 100, static_cast<uint8_t>(point3D_id));
    point3D.error = 0.25 * point3D_id;
    for (Image& image : model.images) {
      Point2D point2D;
      point2D.xy = Eigen::Vector2d(10.5 * point3D_id, 20.25);
      point2D.point3D_id = point3D_id;
      point3D.track.push_back(
          {image.image_id, static_cast<point2D_t>(image.points2D.size())});
      image.points2D.push_back(point2D);
    }
    model.points3D[point3D_id] = point3D;
  }
  model.images[0].points2D.push_back(Point2D());  // No 3D point.
  for (line3D_t line3D_id = 1; line3D_id <= 2; ++line3D_id) {
    Line3D line3D;
    line3D.start_in_world = Eigen::Vector3d(0, line3D_id, 5);
    line3D.end_in_world = Eigen::Vector3d(2, line3D_id, 5);
    line3D.error = 0.5;
    line3D.track = {{1, static_cast<uint32_t>(line3D_id)},
                    {2, static_cast<uint32_t>(line3D_id + 3)}};
    model.lines3D[line3D_id] = line3D;
  }
  return model;
}

void ModelSeeds(const std::string& synth_dir) {
  const Reconstruction model = SmallModel(synth_dir);
  const std::string dir = g_root + "/.model";
  WriteReconstruction(dir + "/bin", model, ModelFormat::kBinary);
  WriteReconstruction(dir + "/txt", model, ModelFormat::kText);
  for (const char* name : {"cameras", "images", "points3D", "lines3D"}) {
    WriteSeed("model_bin", std::string(name) + ".bin",
              ReadTextFile(dir + "/bin/" + name + ".bin"));
    WriteSeed("model_txt", std::string(name) + ".txt",
              ReadTextFile(dir + "/txt/" + name + ".txt"));
  }
  fs::remove_all(dir);
}

void DenseSeeds(const std::string& synth_dir) {
  // A ground-truth depth map, every 40th pixel of every 40th row.
  const DepthMap depth = DepthMap::Read(FirstFile(synth_dir + "/ground_truth/depth_maps", ".bin"));
  const size_t width = std::max<size_t>(1, depth.GetWidth() / 40);
  const size_t height = std::max<size_t>(1, depth.GetHeight() / 40);
  DepthMap small_depth(width, height);
  NormalMap small_normals(width, height);
  for (size_t row = 0; row < height; ++row) {
    for (size_t col = 0; col < width; ++col) {
      small_depth.Set(row, col, depth.Get(40 * row, 40 * col));
      small_normals.Set(row, col, Eigen::Vector3f(0.f, 0.6f, -0.8f));
    }
  }
  small_depth.Write(SeedPath("dense_map", "depth.bin"));
  small_normals.Write(SeedPath("dense_map", "normal.bin"));
  Mat<int32_t> consistency(3, 2, 2);
  consistency.Fill(7);
  consistency.Write(SeedPath("dense_map", "int_mat.bin"));

  // A fused.ply.vis: image indices of a few points.
  const FusedVisibility visibility = {{0, 1, 2}, {1}, {}, {2, 0}};
  WriteFusedVis(SeedPath("fused_vis", "fused.ply.vis"), visibility);
}

// Rows as Database writes them (layouts in database.h and the ext tables).
void DatabaseSeeds() {
  using fuzz::DbInputWriter;
  auto doubles = [](DbInputWriter* writer, std::vector<double> values) {
    writer->Bytes(values.data(), values.size() * sizeof(double));
  };
  {
    DbInputWriter w;
    w.Table(fuzz::kDbCameras);
    w.Int(2);  // camera_id
    w.Int(4);  // OPENCV
    w.Int(848);
    w.Int(480);
    doubles(&w, {500, 500, 424, 240, -0.1, 0.01, 0.001, -0.001});
    w.Int(1);
    w.Table(fuzz::kDbImages);
    w.Int(3);
    w.Bytes("c.png", 5);
    w.Int(2);
    w.Byte(0);  // NULL mask of the prior columns: none is NULL.
    for (double v : {1.0, 0.0, 0.0, 0.0, 1.5, -2.0, 0.25}) w.Real(v);
    WriteSeed("database", "camera_image.bin", w.bytes());
  }
  {
    DbInputWriter w;
    w.Table(fuzz::kDbKeypoints);
    w.Int(1);
    w.Int(2);
    w.Int(6);
    std::vector<float> keypoints = {1.5f, 2.5f, 1, 0, 0, 1,
                                    10.5f, 3.5f, 1, 0, 0, 1};
    w.Bytes(keypoints.data(), keypoints.size() * sizeof(float));
    w.Table(fuzz::kDbDescriptors);
    w.Int(1);
    w.Int(2);
    w.Int(128);
    std::string descriptors(256, '\x20');
    w.Bytes(descriptors.data(), descriptors.size());
    w.Table(fuzz::kDbMatches);
    w.Int(2147483647LL + 2);  // pair (1, 2)
    w.Int(2);
    w.Int(2);
    std::vector<uint32_t> matches = {0, 1, 1, 0};
    w.Bytes(matches.data(), matches.size() * sizeof(uint32_t));
    WriteSeed("database", "features.bin", w.bytes());
  }
  {
    DbInputWriter w;
    w.Table(fuzz::kDbTwoViewGeometries);
    w.Int(2147483647LL + 2);
    w.Int(1);
    w.Int(2);
    std::vector<uint32_t> inliers = {0, 1};
    w.Bytes(inliers.data(), inliers.size() * sizeof(uint32_t));
    w.Int(2);  // calibrated
    doubles(&w, {0, 0, 0, 0, 0, -1, 0, 1, 0});
    doubles(&w, {0, 0, 0, 0, 0, -1, 0, 1, 0});
    doubles(&w, {1, 0, 0, 0, 1, 0, 0, 0, 1});
    doubles(&w, {1, 0, 0, 0});
    doubles(&w, {1, 0, 0});
    WriteSeed("database", "two_view_geometry.bin", w.bytes());
  }
  {
    DbInputWriter w;
    w.Table(fuzz::kDbLidarScans);
    w.Int(1);
    w.Bytes("lidar/000000.ply", 16);
    w.Int(1234);
    doubles(&w, {0, -1, 0, 0.1, 0, 0, -1, -0.2, 1, 0, 0, 0.3});
    w.Table(fuzz::kDbLineSegments);
    w.Int(1);
    w.Int(0);
    doubles(&w, {10.5, 20.5, 100.5, 20.5});
    doubles(&w, {-1, 0.5, 8, 1, 0.5, 8});
    w.Int(42);
    std::string descriptor(32, '\x7f');
    w.Bytes(descriptor.data(), descriptor.size());
    w.Table(fuzz::kDbLineMatches);
    w.Int(2147483647LL + 2);
    w.Int(1);
    w.Int(2);
    std::vector<uint32_t> line_matches = {0, 0};
    w.Bytes(line_matches.data(), line_matches.size() * sizeof(uint32_t));
    w.Table(fuzz::kDbLineTracks);
    w.Int(1);
    doubles(&w, {1, 0, 0, 0, 8, -0.5});
    doubles(&w, {-1, 0.5, 8, 1, 0.5, 8});
    w.Int(1);
    w.Int(0);
    WriteSeed("database", "ext_tables.bin", w.bytes());
  }
}

void OptionSeeds() {
  WriteSeed("options", "command_line.txt",
            "\n%%\n--workspace_path\nws\n--Section.flag\n1\n--Section.count\n"
            "-4\n--Section.scale\n2.5e-3\n--Section.ints\n1,2,3\n"
            "--Section.values\n-1.5,2\n--Section.names\nx, y\n"
            "--Other.threshold\n0\n");
  WriteSeed("options", "preset.txt",
            "workspace_path=ws\n\n[Section]\nflag=true\ncount=7\nscale=0.1\n"
            "name=some name\nints=\nvalues=1e-7\nnames=a,b,c\n\n[Other]\n"
            "threshold=3\n\n%%\n--Section.count\n8\n--check_options\n");
  WriteSeed("options", "help.txt", "\n%%\n-h\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "Usage: make_seeds <corpus_root> <kitti_date_dir> "
                 "<synthesized_dataset_dir>\n";
    return 2;
  }
  g_root = argv[1];
  try {
    ScanSeeds(argv[2], argv[3]);
    DatasetSeeds(argv[2], argv[3]);
    ModelSeeds(argv[3]);
    DenseSeeds(argv[3]);
    DatabaseSeeds();
    OptionSeeds();
  } catch (const std::exception& error) {
    std::cerr << "make_seeds: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
