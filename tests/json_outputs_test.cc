// The key tables of docs/json_outputs.md against the files the writers
// produce. Every documented JSON file is written here by the project's own
// writer from small inputs (the pose, mesh, mesh alignment and depth files
// by the evaluate stage of automatic_reconstructor, EvaluatePipeline, into
// its eval folder), and its keys, in order, and their JSON types must equal
// the rows of the file's table (the table after <!-- json-keys: ID -->). A
// writer that adds, drops or reorders a key fails here until the page is
// updated.
//
// A row's key is a path: "a.b" is key b of the object under a, "a[].b" key b
// of each element of the array a, and "<name>" a key, or part of one, that
// varies. Each key of a file is mapped to the row it matches with the most
// fixed characters; the file's rows, in the order of their first
// appearance, must be the table's rows.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "colmap_ext/database/database.h"
#include "colmap_ext/database/line_segments_table.h"
#include "colmap_ext/database/line_tracks_table.h"
#include "colmap_ext/model/model_io.h"
#include "colmap_ext/mvs/dense_maps.h"
#include "colmap_ext/mvs/workspace.h"
#include "colmap_ext/util/file.h"
#include "colmap_ext/util/json.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/string.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/calibration.h"
#include "src/dataset/poses.h"
#include "src/eval/corner_test_scene.h"
#include "src/eval/line_evaluator.h"
#include "src/eval/mesh_evaluator.h"
#include "src/eval/mesh_sampling.h"
#include "src/eval/real_data_evaluator.h"
#include "src/lidar/lidar_test_scene.h"
#include "src/lines/debug_overlay.h"
#include "src/matching/track_export.h"
#include "src/pipeline/pipeline_evaluation.h"
#include "src/pipeline/stage_record.h"

namespace colmap_lidar {
namespace {
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------
// The tables of the page.

constexpr char kMarker[] = "<!-- json-keys: ";

struct KeyRow {
  // As written, e.g. "overall.<map_type>.within_<t>cm".
  std::string key;
  // string | number | integer | boolean | object | array.
  std::string type;
  // The path's parts; "[]" for the elements of an array.
  std::vector<std::string> parts;
};

// "images[].<map_type>.within_<t>cm" -> images, [], <map_type>,
// within_<t>cm (a dot inside <...> does not split).
std::vector<std::string> SplitKeyPath(const std::string& key) {
  std::vector<std::string> parts;
  std::string part;
  const auto flush = [&parts, &part]() {
    if (part.size() > 2 && part.compare(part.size() - 2, 2, "[]") == 0) {
      parts.push_back(part.substr(0, part.size() - 2));
      parts.push_back("[]");
    } else {
      parts.push_back(part);
    }
    part.clear();
  };
  int depth = 0;
  for (const char c : key) {
    depth += (c == '<') - (c == '>');
    if (c == '.' && depth == 0) {
      flush();
    } else {
      part += c;
    }
  }
  flush();
  return parts;
}

// The cells of a Markdown table row; "\|" is a pipe inside a cell.
std::vector<std::string> SplitTableRow(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '\\' && i + 1 < line.size() && line[i + 1] == '|') {
      cell += '|';
      ++i;
    } else if (line[i] == '|') {
      cells.push_back(StringTrim(cell));
      cell.clear();
    } else {
      cell += line[i];
    }
  }
  return cells;
}

// Table id -> rows, from the page.
std::map<std::string, std::vector<KeyRow>> ReadKeyTables(
    const std::string& path) {
  std::ifstream file(path);
  EXPECT_TRUE(file.is_open()) << path;
  std::map<std::string, std::vector<KeyRow>> tables;
  std::string id;  // Of the table being read; empty between tables.
  int num_table_lines = 0;
  std::string line;
  while (std::getline(file, line)) {
    if (line.rfind(kMarker, 0) == 0) {
      const size_t end = line.find(" -->");
      EXPECT_NE(end, std::string::npos) << line;
      id = line.substr(std::strlen(kMarker), end - std::strlen(kMarker));
      EXPECT_EQ(tables.count(id), 0u) << "Two tables " << id << " in " << path;
      tables[id];
      num_table_lines = 0;
      continue;
    }
    if (id.empty()) {
      continue;
    }
    if (line.empty() || line[0] != '|') {
      if (num_table_lines > 0) {
        id.clear();  // The table ended.
      }
      continue;
    }
    if (++num_table_lines <= 2) {
      continue;  // Header and separator.
    }
    const std::vector<std::string> cells = SplitTableRow(line);
    EXPECT_EQ(cells.size(), 4u) << "Not key | type | unit | meaning: " << line;
    if (cells.size() < 2) {
      continue;
    }
    const std::string& key = cells[0];
    EXPECT_TRUE(key.size() > 2 && key.front() == '`' && key.back() == '`')
        << "Key not in backticks: " << line;
    KeyRow row;
    row.key = key.substr(1, key.size() - 2);
    row.type = cells[1];
    row.parts = SplitKeyPath(row.key);
    for (const KeyRow& other : tables[id]) {
      EXPECT_NE(other.key, row.key) << "Row twice in table " << id;
    }
    tables[id].push_back(row);
  }
  return tables;
}

const std::map<std::string, std::vector<KeyRow>>& KeyTables() {
  static const std::map<std::string, std::vector<KeyRow>> tables =
      ReadKeyTables(JoinPaths(testing::SourceDir(), "docs/json_outputs.md"));
  return tables;
}

std::vector<KeyRow> KeyTable(const std::string& id) {
  const auto it = KeyTables().find(id);
  EXPECT_TRUE(it != KeyTables().end())
      << "No table <!-- json-keys: " << id << " --> in docs/json_outputs.md";
  return it == KeyTables().end() ? std::vector<KeyRow>() : it->second;
}

// ---------------------------------------------------------------------------
// A file's keys mapped to the rows.

// The fixed characters of `pattern` (a key part with <...> placeholders,
// each matching one or more characters) when it matches `part`, else -1.
int MatchScore(const std::string& pattern, const std::string& part) {
  if (pattern.find('<') == std::string::npos) {
    return pattern == part ? static_cast<int>(pattern.size()) : -1;
  }
  std::string regex;
  int num_fixed = 0;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] == '<') {
      const size_t close = pattern.find('>', i);
      if (close == std::string::npos) {
        return -1;
      }
      regex += "(.+)";
      i = close;
      continue;
    }
    if (std::strchr(".^$|()[]{}*+?\\", pattern[i]) != nullptr) {
      regex += '\\';
    }
    regex += pattern[i];
    ++num_fixed;
  }
  return std::regex_match(part, std::regex(regex)) ? num_fixed : -1;
}

struct KeyEntry {
  std::vector<std::string> parts;
  const Json* value;
};

void FlattenKeys(const Json& object, const std::vector<std::string>& prefix,
                 std::vector<KeyEntry>* entries) {
  for (const auto& item : object.items()) {
    std::vector<std::string> parts = prefix;
    parts.push_back(item.key());
    entries->push_back({parts, &item.value()});
    if (item.value().is_object()) {
      FlattenKeys(item.value(), parts, entries);
    } else if (item.value().is_array()) {
      parts.push_back("[]");
      for (const Json& element : item.value()) {
        if (element.is_object()) {
          FlattenKeys(element, parts, entries);
        }
      }
    }
  }
}

bool HasDocumentedType(const Json& value, const std::string& type) {
  if (type == "string") return value.is_string();
  if (type == "number") return value.is_number_float();
  if (type == "integer") return value.is_number_integer();
  if (type == "boolean") return value.is_boolean();
  if (type == "object") return value.is_object();
  if (type == "array") return value.is_array();
  return false;
}

// Checks the keys of the JSON file at `path` against `rows`: the rows the
// file's keys map to, in order of first appearance, must be `rows`, and
// each value must have its row's type.
void ExpectKeysAsDocumented(const std::string& path,
                            const std::vector<KeyRow>& rows) {
  SCOPED_TRACE(path);
  ASSERT_FALSE(rows.empty());
  const Json json = ReadJsonFile(path);
  ASSERT_TRUE(json.is_object());
  std::vector<KeyEntry> entries;
  FlattenKeys(json, {}, &entries);
  std::vector<std::string> file_keys;
  std::set<std::string> seen;
  for (const KeyEntry& entry : entries) {
    const KeyRow* best = nullptr;
    int best_score = -1;
    for (const KeyRow& row : rows) {
      if (row.parts.size() != entry.parts.size()) {
        continue;
      }
      int score = 0;
      for (size_t i = 0; i < row.parts.size() && score >= 0; ++i) {
        const int part_score = MatchScore(row.parts[i], entry.parts[i]);
        score = part_score < 0 ? -1 : score + part_score;
      }
      if (score > best_score) {
        best = &row;
        best_score = score;
      }
    }
    std::string key;
    if (best == nullptr) {
      key = "(not in the table) ";
      for (size_t i = 0; i < entry.parts.size(); ++i) {
        key += (i > 0 && entry.parts[i] != "[]" ? "." : "") + entry.parts[i];
      }
    } else {
      key = best->key;
      EXPECT_TRUE(HasDocumentedType(*entry.value, best->type))
          << best->key << " is documented as " << best->type << ", written "
          << entry.value->type_name() << " (" << entry.value->dump() << ")";
    }
    if (seen.insert(key).second) {
      file_keys.push_back(key);
    }
  }
  std::vector<std::string> table_keys;
  for (const KeyRow& row : rows) {
    table_keys.push_back(row.key);
  }
  size_t first = 0;
  while (first < file_keys.size() && first < table_keys.size() &&
         file_keys[first] == table_keys[first]) {
    ++first;
  }
  EXPECT_EQ(file_keys, table_keys)
      << "The keys of " << path
      << " (left) differ from its table in docs/json_outputs.md (right) "
         "first at position "
      << first << ": file "
      << (first < file_keys.size() ? file_keys[first] : "(end)") << ", table "
      << (first < table_keys.size() ? table_keys[first] : "(end)");
}

// The rows not under `prefix` (an optional object).
std::vector<KeyRow> RowsWithout(const std::vector<KeyRow>& rows,
                                const std::string& prefix) {
  std::vector<KeyRow> kept;
  for (const KeyRow& row : rows) {
    if (row.parts.front() != prefix) {
      kept.push_back(row);
    }
  }
  return kept;
}

TEST(JsonOutputs, EveryTableIsCheckedHere) {
  std::set<std::string> ids;
  for (const auto& [id, rows] : KeyTables()) {
    ids.insert(id);
    EXPECT_FALSE(rows.empty()) << id;
  }
  EXPECT_EQ(ids, std::set<std::string>({"pose", "mesh", "mesh_alignment",
                                        "line", "depth", "real_data",
                                        "stages", "line_tracks",
                                        "line_outcomes"}));
}

// ---------------------------------------------------------------------------
// The evaluate stage: poses, meshes, mesh alignment and depth maps.

// The corner scene: src/eval/corner_test_scene.h.
using testing::CornerMesh;
using testing::Displacement;
using testing::EstimateFromReference;
using testing::WritePointsPly;

// A recording and a workspace for EvaluatePipeline under `root`:
//   dataset/reference.ply       the corner sampled, 500 points per m2;
//   dataset/poses_gt.txt        six cameras around it;
//   dataset/ground_truth/crease_edges.txt   the corner's three creases;
//   dataset/calibration.yaml, dataset/ground_truth/depth_maps/000000.bin
//                               a 40 x 30 camera seeing a wall 4 m away;
//   ws/sparse/refined           the six cameras in the estimate's frame;
//   ws/dense/meshed.ply         the corner there, slightly displaced;
//   ws/dense/{images,sparse,stereo}  depth maps of images 000000 (with
//                               truth) and 000001 (without).
PipelineEvaluationInput WriteEvaluationInputs(const std::string& root) {
  PipelineEvaluationInput input;
  input.dataset_path = JoinPaths(root, "dataset");
  fs::create_directories(JoinPaths(input.dataset_path, "ground_truth"));
  const testing::Corner corner = CornerMesh();
  WritePointsPly(JoinPaths(input.dataset_path, "reference.ply"),
              SampleTriangleMesh(corner.vertices, corner.triangles, 500.0,
                                 /*seed=*/5));
  {
    std::ofstream edges(
        JoinPaths(input.dataset_path, "ground_truth/crease_edges.txt"));
    edges << "0 0 0 6 0 0\n0 0 0 0 6 0\n0 0 0 0 0 3\n";
  }

  input.refined_model_path = JoinPaths(root, "ws/sparse/refined");
  fs::create_directories(input.refined_model_path);
  testing::WriteCornerCameras(JoinPaths(input.dataset_path, "poses_gt.txt"),
                              input.refined_model_path);
  const Eigen::Affine3d estimate_from_reference = EstimateFromReference();
  // The priors and the stock mapper's model: the same model.
  input.prior_model_path = input.refined_model_path;
  input.mapper_model_path = input.refined_model_path;

  const std::string dense = JoinPaths(root, "ws/dense");
  fs::create_directories(dense);
  testing::Corner mesh = CornerMesh();
  for (Eigen::Vector3d& vertex : mesh.vertices) {
    vertex = estimate_from_reference * Displacement() * vertex;
  }
  input.mesh_path = JoinPaths(dense, "meshed.ply");
  WritePointsPly(input.mesh_path, mesh.vertices, mesh.triangles);
  // Not written: no observed cloud, no LIDAR baseline; its folder is the
  // dense workspace of the depth maps.
  input.lidar_cloud_path = JoinPaths(dense, "lidar_fused.ply");
  input.database_path = JoinPaths(root, "ws/database.db");
  input.output_path = JoinPaths(root, "ws/eval");

  // Depth maps: a wall 4 m in front of the camera; ours 1 cm (geometric)
  // and 3 cm (photometric) behind it.
  const Camera depth_camera =
      Camera::FromModelName("PINHOLE", 40, 30, {40, 40, 20, 15});
  RigCalibration calibration;
  calibration.camera = depth_camera;
  WriteCalibration(JoinPaths(input.dataset_path, "calibration.yaml"),
                   calibration);
  fs::create_directories(
      JoinPaths(input.dataset_path, "ground_truth/depth_maps"));
  const auto constant_map = [](float depth) {
    DepthMap map(40, 30);
    for (size_t row = 0; row < 30; ++row) {
      for (size_t col = 0; col < 40; ++col) {
        map.Set(row, col, depth);
      }
    }
    return map;
  };
  constant_map(4.0f).Write(
      JoinPaths(input.dataset_path, "ground_truth/depth_maps/000000.bin"));
  const std::vector<std::string> names = {"000000.png", "000001.png"};
  CreateDenseWorkspaceLayout(dense, names);
  const DenseWorkspace workspace(dense);
  Reconstruction dense_model;
  Camera dense_camera = depth_camera;
  dense_camera.camera_id = 1;
  dense_model.cameras[1] = dense_camera;
  for (size_t i = 0; i < names.size(); ++i) {
    Image image;
    image.image_id = i + 1;
    image.camera_id = 1;
    image.name = names[i];
    dense_model.images.push_back(image);
    constant_map(4.01f).Write(
        workspace.DepthMapPath(names[i], DenseMapType::kGeometric));
    constant_map(4.03f).Write(
        workspace.DepthMapPath(names[i], DenseMapType::kPhotometric));
  }
  WriteReconstruction(workspace.SparseDir(), dense_model, ModelFormat::kBinary);
  return input;
}

TEST(JsonOutputs, EvaluateStage) {
  const std::string root = testing::CreateTestDir();
  const PipelineEvaluationInput input = WriteEvaluationInputs(root);
  PipelineEvaluationOptions options;
  options.mesh.thresholds_m = {0.05, 0.2};
  options.mesh.sample_density_per_m2 = 300.0;
  options.icp.max_num_samples = 5000;
  options.lidar_baseline = false;
  options.num_threads = 2;
  EvaluatePipeline(input, options);

  std::set<std::string> json_files;
  for (const auto& entry : fs::directory_iterator(input.output_path)) {
    if (entry.path().extension() == ".json") {
      json_files.insert(entry.path().filename().string());
    }
  }
  EXPECT_EQ(json_files,
            std::set<std::string>(
                {"poses_prior_none.json", "poses_refined_none.json",
                 "poses_refined_se3.json", "poses_refined_sim3.json",
                 "poses_refined_sim3_axes.json",
                 "poses_refined_se3_axes.json",
                 "poses_colmap_mapper_sim3.json", "mesh_ours.json",
                 "mesh_ours_icp.json", "mesh_alignment.json",
                 "depth_maps.json"}));
  // The page names each file.
  const std::string page =
      ReadTextFile(JoinPaths(testing::SourceDir(), "docs/json_outputs.md"));
  for (const std::string& name : json_files) {
    EXPECT_NE(page.find("`" + name + "`"), std::string::npos)
        << name << " is not named in docs/json_outputs.md";
    const std::string path = JoinPaths(input.output_path, name);
    if (name.rfind("poses_", 0) == 0) {
      ExpectKeysAsDocumented(path, KeyTable("pose"));
    } else if (name == "mesh_alignment.json") {
      ExpectKeysAsDocumented(path, KeyTable("mesh_alignment"));
    } else if (name == "depth_maps.json") {
      ExpectKeysAsDocumented(path, KeyTable("depth"));
    } else {
      // With the recording's crease edges: edge_region included.
      ExpectKeysAsDocumented(path, KeyTable("mesh"));
    }
  }

  // Without crease edges the mesh report has no edge_region; the other keys
  // stay in their order.
  MeshEvaluationOptions mesh_options = options.mesh;
  const MeshEvaluation evaluation = EvaluateMeshFiles(
      input.mesh_path, JoinPaths(input.dataset_path, "reference.ply"),
      mesh_options, EstimateFromReference().inverse());
  ASSERT_FALSE(evaluation.has_edge_region);
  const std::string path = JoinPaths(root, "mesh_without_edges.json");
  WriteMeshEvaluationJson(path, evaluation);
  ExpectKeysAsDocumented(path, RowsWithout(KeyTable("mesh"), "edge_region"));
}

// ---------------------------------------------------------------------------
// The other writers.

// A scan of the street scene seen from `world_from_lidar`, up to 30 m, with
// 1 cm range noise.
LidarScan MakeScan(const Rigid3d& world_from_lidar, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.01);
  const Rigid3d lidar_from_world = world_from_lidar.Inverse();
  LidarScan scan;
  for (const Eigen::Vector3d& point : SampleStreetScene(seed, 10.0)) {
    const Eigen::Vector3d p = lidar_from_world * point;
    if (p.norm() < 30.0) {
      scan.points.push_back((p + noise(rng) * p.normalized()).cast<float>());
    }
  }
  return scan;
}

// Every section: priors (so prior crispness and length), the trajectory, and
// the mesh against the LIDAR points with the in-view figures.
TEST(JsonOutputs, RealDataEvaluation) {
  std::vector<LidarScan> scans;
  std::vector<Rigid3d> poses;
  for (int k = 0; k < 3; ++k) {
    poses.push_back(PoseFromYawRoll(3.0 * k, 0.0, {1.2 * k, 0.1 * k, 0.0}));
    scans.push_back(MakeScan(poses.back(), 100 + k));
  }
  std::vector<RealDataFrame> frames;
  for (int k = 0; k < 3; ++k) {
    RealDataFrame frame;
    frame.name = "frame" + std::to_string(k);
    frame.scan = &scans[k];
    frame.refined_world_from_lidar = poses[k];
    frame.has_prior = true;
    frame.prior_world_from_lidar =
        poses[k] * PoseFromYawRoll(1.0, 0.0, {0.05, 0.05, 0.0});
    frames.push_back(frame);
  }
  RealDataEvaluationOptions options;
  options.num_threads = 2;
  options.crispness_max_queries_per_scan = 1000;
  RealDataEvaluation evaluation = EvaluateRealDataFrames(frames, options);
  ASSERT_TRUE(evaluation.has_prior);
  ASSERT_TRUE(evaluation.has_trajectory);

  // A 10 x 10 m square at z = 0 and LIDAR points on and above it, seen by a
  // camera 5 m above looking down.
  const std::vector<Eigen::Vector3d> vertices = {
      {0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  const std::vector<Eigen::Vector3i> triangles = {{0, 1, 2}, {0, 2, 3}};
  std::vector<Eigen::Vector3d> lidar;
  for (double x = 0.05; x < 10.0; x += 0.1) {
    for (double y = 0.05; y < 10.0; y += 0.1) {
      lidar.emplace_back(x, y, x < 5.0 ? 0.0 : 0.3);
    }
  }
  Reconstruction model;
  model.cameras[1] =
      Camera::FromModelName("PINHOLE", 100, 100, {100, 100, 50, 50});
  Image image;
  image.image_id = 1;
  image.camera_id = 1;
  image.name = "down.png";
  image.cam_from_world.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  image.cam_from_world.translation =
      -(image.cam_from_world.rotation * Eigen::Vector3d(2.5, 5.0, 5.0));
  model.images.push_back(image);
  evaluation.mesh_vs_lidar = EvaluateMeshVsLidar(
      vertices, triangles, lidar, options, InCameraView(model, lidar, 20.0));
  evaluation.has_mesh = true;

  const std::string path =
      JoinPaths(testing::CreateTestDir(), "real_data.json");
  WriteRealDataJson(path, evaluation);
  ExpectKeysAsDocumented(path, KeyTable("real_data"));
}

TEST(JsonOutputs, LineEvaluation) {
  const std::vector<Segment3D> ground_truth = {
      {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 0, 0)},
      {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1)}};
  const std::vector<Segment3D> estimate = {
      {Eigen::Vector3d(0, 0.03, 0), Eigen::Vector3d(1, 0.03, 0)}};
  const LineEvaluation evaluation =
      EvaluateLines(estimate, ground_truth, LineEvaluationOptions());
  const std::string path =
      JoinPaths(testing::CreateTestDir(), "lines_eval.json");
  WriteLineEvaluationJson(path, evaluation);
  ExpectKeysAsDocumented(path, KeyTable("line"));
}

TEST(JsonOutputs, StageRecords) {
  StageRecord import;
  import.stage = "import";
  import.wall_seconds = 0.25;
  import.cpu_seconds = 0.5;
  import.peak_memory_bytes = 103018496;
  import.finished_at = "2026-11-22T05:12:03Z";
  import.note = "20 frames";
  StageRecord sfm = import;
  sfm.stage = "sfm";
  const std::string path = JoinPaths(testing::CreateTestDir(), "stages.json");
  WriteStageRecordsJson(path, {import, sfm});
  ExpectKeysAsDocumented(path, KeyTable("stages"));
}

TEST(JsonOutputs, LineTracks) {
  const std::string dir = testing::CreateTestDir();
  Database database(JoinPaths(dir, "database.db"));
  const camera_t camera_id = database.WriteCamera(
      Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240}));
  std::vector<image_t> image_ids;
  for (const char* name : {"000000.png", "000001.png"}) {
    DatabaseImage image;
    image.name = name;
    image.camera_id = camera_id;
    image_ids.push_back(database.WriteImage(image));
  }
  LineSegmentRecord segment;
  segment.start2D = {10.5, 20.25};
  segment.end2D = {100.0, 0.1};
  segment.start3D_in_cam = {-1.0, 0.5, 5.0};
  segment.end3D_in_cam = {1.0, -0.25, 7.0};
  WriteLineSegments(&database, image_ids[0], {segment});
  WriteLineSegments(&database, image_ids[1], {segment, segment});
  LineTrackRecord track;
  track.line3D_id = 1;
  track.plucker << 1, 0, 0, 0, 2, -3;
  track.start_in_world = {0.0, -3.0, -2.0};
  track.end_in_world = {1.0, -3.0, -2.0};
  track.elements = {{image_ids[0], 0}, {image_ids[1], 1}};
  const std::string path = JoinPaths(dir, "tracks.json");
  WriteLineTracksJson(path, database, {track});
  ExpectKeysAsDocumented(path, KeyTable("line_tracks"));
}

TEST(JsonOutputs, LineOutcomes) {
  ViewLines lines;
  lines.num_lsd_segments = 2;
  lines.range_noise_m = 0.02;
  SegmentOutcome lifted;
  lifted.segment.start = {10.5, 20.25};
  lifted.segment.end = {100.0, 0.1};
  lifted.edge_result = LiftResult::kLifted;
  lifted.lifted2D = lifted.segment;
  lifted.start3D_in_cam = {-1.0, 0.5, 5.0};
  lifted.end3D_in_cam = {1.0, -0.25, 7.0};
  lifted.edge_surface = LineSurfaceType::kCrease;
  SegmentOutcome rejected = lifted;
  rejected.edge_result = LiftResult::kTooFewPoints;
  rejected.edge_surface.reset();
  rejected.plane_result = PlaneLiftResult::kBoundary;
  lines.outcomes = {lifted, rejected};
  const std::string path =
      JoinPaths(testing::CreateTestDir(), "000000.json");
  WriteJsonFile(path, LineOutcomesToJson("000000.png", lines));
  ExpectKeysAsDocumented(path, KeyTable("line_outcomes"));
  const Json json = ReadJsonFile(path);
  EXPECT_EQ(json["segments"][0]["edge_surface"], "crease");
  EXPECT_EQ(json["segments"][1]["plane_result"], "boundary");
  EXPECT_FALSE(json["segments"][1].contains("edge_surface"));
  EXPECT_FALSE(json["segments"][1].contains("start3D_in_cam"));
}

}  // namespace
}  // namespace colmap_lidar
