// The bad-input table (docs/robustness.md): every case breaks one thing of a
// valid recording or workspace, runs the real build/colmap-lidar and checks
// that it fails with exit code 1 or 2 (never a signal or 0), that the first
// error line names the offending file or option, and that nothing in the
// case's folder changed (dataset and workspace hashed before and after; a
// workspace that did not exist must not exist afterwards).
//
// The table in docs/robustness.md is generated from these cases and their
// observed results, and checked against them: a case, exit code or message
// that changes fails this test until the table is regenerated with
//   COLMAP_LIDAR_UPDATE_DOCS=1 ctest -R tests/robustness
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/string.h"
#include "colmap_ext/util/testing.h"
#include "src/dataset/calibration.h"
#include "src/lidar/scan_io.h"

namespace colmap_lidar {
namespace {
namespace fs = std::filesystem;

constexpr char kTableBegin[] = "<!-- robustness-table-begin -->";
constexpr char kTableEnd[] = "<!-- robustness-table-end -->";

// How a case's command is run.
enum class RunMode {
  kNormal,
  // The workspace is made read-only (chmod a-w); as root, where permission
  // bits do not stop writes, the command runs as user nobody (setpriv).
  kReadOnly,
  // Files the command writes are limited to 256 KiB (RLIMIT_FSIZE with
  // SIGXFSZ ignored, so writes fail with EFBIG as on a full disk): room for
  // the database and the images, not for a scan.
  kFullDisk,
};

// The folders of one case: $CASE, and below it $DATA (rig recording), $WS
// (workspace) and $KITTI (KITTI raw recording), each present only when the
// case's setup made it.
struct CaseDirs {
  std::string root;
  std::string data;
  std::string ws;
  std::string kitti;
};

struct BadInputCase {
  std::string id;
  // What is broken, for the table.
  std::string broken;
  // colmap-lidar arguments; $DATA, $WS, $KITTI and $CASE are replaced.
  std::string command;
  // Text the first error line must contain (the file or option at fault),
  // with the same placeholders.
  std::string names;
  std::function<void(const CaseDirs&)> setup;
  RunMode mode = RunMode::kNormal;
};

struct CaseResult {
  int exit_code = -1;
  std::string message;  // First error line, paths as placeholders.
  bool unchanged = false;
  bool skipped = false;
  std::string output;  // Everything the command printed.
};

// ---------------------------------------------------------------------------
// Files.

std::string ReadBytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  EXPECT_TRUE(file.is_open()) << path;
  std::ostringstream content;
  content << file.rdbuf();
  return content.str();
}

void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  ASSERT_TRUE(file.is_open()) << path;
  file << bytes;
}

// Keeps the first `fraction` of the file.
void TruncateFile(const std::string& path, double fraction) {
  const std::string bytes = ReadBytes(path);
  WriteBytes(path, bytes.substr(
                       0, static_cast<size_t>(bytes.size() * fraction)));
}

void ReplaceInFile(const std::string& path, const std::string& from,
                   const std::string& to) {
  std::string text = ReadBytes(path);
  const size_t pos = text.find(from);
  ASSERT_NE(pos, std::string::npos) << from << " not in " << path;
  text.replace(pos, from.size(), to);
  WriteBytes(path, text);
}

void CopyTree(const std::string& from, const std::string& to) {
  fs::copy(from, to, fs::copy_options::recursive);
}

uint64_t Fnv1a(const std::string& bytes, uint64_t hash) {
  for (const unsigned char c : bytes) {
    hash = (hash ^ c) * 1099511628211ull;
  }
  return hash;
}

// A digest of every path (folders included, so an empty folder left behind
// counts) and every file's bytes under `root`. In SQLite files (.db) the
// header's file change counter (bytes 24-27) and version-valid-for number
// (92-95) are left out: a rolled-back transaction may advance them while
// every page stays as it was.
uint64_t HashTree(const std::string& root) {
  std::vector<std::string> entries;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string relative = fs::relative(entry.path(), root).string();
    entries.push_back(entry.is_directory() ? relative + "/" : relative);
  }
  std::sort(entries.begin(), entries.end());
  uint64_t hash = 14695981039346656037ull;
  for (const std::string& relative : entries) {
    hash = Fnv1a(relative + '\0', hash);
    if (relative.back() != '/') {
      std::string bytes = ReadBytes(JoinPaths(root, relative));
      if (fs::path(relative).extension() == ".db" && bytes.size() >= 100) {
        std::fill(bytes.begin() + 24, bytes.begin() + 28, '\0');
        std::fill(bytes.begin() + 92, bytes.begin() + 96, '\0');
      }
      hash = Fnv1a(bytes, hash);
    }
  }
  return hash;
}

void SetWritable(const std::string& root, bool writable) {
  const auto change = [writable](const fs::path& path) {
    fs::permissions(path,
                    fs::perms::owner_write | fs::perms::group_write |
                        fs::perms::others_write,
                    writable ? fs::perm_options::add
                             : fs::perm_options::remove);
  };
  change(root);
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    change(entry.path());
  }
}

// Writes an ASCII PLY of x y z rows.
void WriteAsciiPly(const std::string& path,
                   const std::vector<std::string>& rows) {
  std::ostringstream text;
  text << "ply\nformat ascii 1.0\nelement vertex " << rows.size()
       << "\nproperty float x\nproperty float y\nproperty float z\n"
          "end_header\n";
  for (const std::string& row : rows) {
    text << row << "\n";
  }
  WriteBytes(path, text.str());
}

float SwapBytes(float value) {
  uint32_t word = 0;
  std::memcpy(&word, &value, sizeof(word));
  word = __builtin_bswap32(word);
  std::memcpy(&value, &word, sizeof(value));
  return value;
}

// Byte-swaps every 4-byte word (float32 records of a KITTI .bin).
void SwapWords(const std::string& path) {
  std::string bytes = ReadBytes(path);
  for (size_t i = 0; i + 4 <= bytes.size(); i += 4) {
    std::swap(bytes[i], bytes[i + 3]);
    std::swap(bytes[i + 1], bytes[i + 2]);
  }
  WriteBytes(path, bytes);
}

// ---------------------------------------------------------------------------
// Running the executable.

std::string Quote(const std::string& text) { return "'" + text + "'"; }

std::string ReplaceAll(std::string text, const std::string& from,
                       const std::string& to) {
  for (size_t pos = text.find(from); pos != std::string::npos;
       pos = text.find(from, pos + to.size())) {
    text.replace(pos, from.size(), to);
  }
  return text;
}

std::string Expand(const std::string& text, const CaseDirs& dirs) {
  std::string expanded = ReplaceAll(text, "$DATA", dirs.data);
  expanded = ReplaceAll(expanded, "$WS", dirs.ws);
  expanded = ReplaceAll(expanded, "$KITTI", dirs.kitti);
  return ReplaceAll(expanded, "$CASE", dirs.root);
}

std::string Placeholders(const std::string& text, const CaseDirs& dirs) {
  std::string result = ReplaceAll(text, dirs.data, "$DATA");
  result = ReplaceAll(result, dirs.ws, "$WS");
  result = ReplaceAll(result, dirs.kitti, "$KITTI");
  return ReplaceAll(result, dirs.root, "$CASE");
}

std::string Executable() {
  return JoinPaths(testing::BinaryDir(), "colmap-lidar");
}

// The first error line of the output: "ERROR: ..." from the command
// boundary or the option parser, or a glog E/F line (prefix removed).
std::string FirstErrorLine(const std::string& output) {
  std::istringstream lines(output);
  std::string line;
  while (std::getline(lines, line)) {
    if (StringStartsWith(line, "ERROR: ")) {
      return line.substr(7);
    }
    if (line.size() > 2 && (line[0] == 'E' || line[0] == 'F') &&
        std::isdigit(static_cast<unsigned char>(line[1]))) {
      const size_t end = line.find("] ");
      if (end != std::string::npos) {
        return line.substr(end + 2);
      }
    }
  }
  return "";
}

std::string MarkdownCode(std::string text) {
  text = ReplaceAll(text, "`", "'");
  text = ReplaceAll(text, "|", "\\|");
  return "`" + text + "`";
}

// ---------------------------------------------------------------------------
// Valid inputs, made once: a tiny synthetic recording, its workspace and two
// KITTI frames. Each case copies what it needs and breaks one thing.

struct BaseInputs {
  std::string rig;
  std::string workspace;
  std::string kitti;
  bool ok = false;
};

const BaseInputs& Base() {
  static const BaseInputs base = [] {
    BaseInputs inputs;
    const std::string root = testing::CreateTestDir();
    inputs.rig = JoinPaths(root, "rig");
    inputs.workspace = JoinPaths(root, "ws");
    inputs.kitti = JoinPaths(root, "kitti");
    const std::string log = JoinPaths(root, "base.log");
    const int synth = testing::RunCommand(
        Quote(Executable()) + " synthesize --output_path " +
            Quote(inputs.rig) +
            " --Synthesis.num_frames 3 --Synthesis.path_fraction 0.1"
            " --Synthesis.image_width 96 --Synthesis.image_height 64"
            " --Synthesis.lidar_model VLP-16 --Synthesis.survey_num_stations 0"
            " --Synthesis.write_depth_maps 0 --Synthesis.supersampling 1",
        log);
    EXPECT_EQ(synth, 0) << ReadTextFile(log);
    const int import = testing::RunCommand(
        Quote(Executable()) + " lidar_importer --dataset_path " +
            Quote(inputs.rig) + " --workspace_path " +
            Quote(inputs.workspace),
        log);
    EXPECT_EQ(import, 0) << ReadTextFile(log);

    // Two frames of the KITTI sample, flattened (calibration beside the
    // image_02 and velodyne_points folders).
    const std::string sample =
        JoinPaths(testing::KittiSampleDir(), "2011_09_26");
    for (const char* dir : {"image_02/data", "velodyne_points/data"}) {
      fs::create_directories(JoinPaths(inputs.kitti, dir));
    }
    for (const char* file : {"calib_cam_to_cam.txt", "calib_velo_to_cam.txt"}) {
      fs::copy_file(JoinPaths(sample, file), JoinPaths(inputs.kitti, file));
    }
    for (const char* frame : {"0000000000", "0000000001"}) {
      const std::string image = std::string("image_02/data/") + frame + ".png";
      const std::string scan =
          std::string("velodyne_points/data/") + frame + ".bin";
      fs::copy_file(JoinPaths(sample, image), JoinPaths(inputs.kitti, image));
      fs::copy_file(JoinPaths(sample, scan), JoinPaths(inputs.kitti, scan));
    }
    const std::string kitti_ws = JoinPaths(root, "kitti_ws");
    const int kitti_import = testing::RunCommand(
        Quote(Executable()) + " lidar_importer --dataset_path " +
            Quote(inputs.kitti) + " --workspace_path " + Quote(kitti_ws),
        log);
    EXPECT_EQ(kitti_import, 0) << ReadTextFile(log);
    inputs.ok = synth == 0 && import == 0 && kitti_import == 0;
    return inputs;
  }();
  return base;
}

void UseRig(const CaseDirs& dirs) { CopyTree(Base().rig, dirs.data); }
void UseWorkspace(const CaseDirs& dirs) {
  CopyTree(Base().workspace, dirs.ws);
}
void UseKitti(const CaseDirs& dirs) { CopyTree(Base().kitti, dirs.kitti); }

std::string Frame(const CaseDirs& dirs, const std::string& kind, int index) {
  const char* extension = kind == "images" ? ".png" : ".ply";
  return JoinPaths(dirs.data, kind + "/00000" + std::to_string(index) +
                                  extension);
}

std::string KittiScan(const CaseDirs& dirs, int index) {
  return JoinPaths(dirs.kitti, "velodyne_points/data/000000000" +
                                   std::to_string(index) + ".bin");
}

// The synthetic scan of frame 1, in the LIDAR frame, kept to the points
// that `keep` accepts in the camera frame.
void FilterScanInCameraFrame(
    const CaseDirs& dirs,
    const std::function<bool(const Eigen::Vector3d&)>& keep) {
  const RigCalibration calibration =
      ReadCalibration(JoinPaths(dirs.data, "calibration.yaml"));
  const LidarScan scan = ReadLidarScan(Frame(dirs, "lidar", 1));
  LidarScan kept;
  for (size_t i = 0; i < scan.size(); ++i) {
    if (keep(calibration.cam_from_lidar * scan.points[i].cast<double>())) {
      kept.points.push_back(scan.points[i]);
    }
  }
  ASSERT_GT(kept.size(), 100u);
  WriteLidarScanPly(Frame(dirs, "lidar", 1), kept);
}

// Replaces the image by itself resized to width x height.
void ResizeImage(const std::string& path, int width, int height) {
  const cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(image.empty()) << path;
  cv::Mat resized;
  cv::resize(image, resized, cv::Size(width, height));
  ASSERT_TRUE(cv::imwrite(path, resized)) << path;
}

// Replaces the line of frame 000001 in poses_prior.txt.
void ReplacePoseLine(const CaseDirs& dirs, const std::string& line) {
  const std::string path = JoinPaths(dirs.data, "poses_prior.txt");
  std::string text = ReadBytes(path);
  const size_t begin = text.find("\n000001 ") + 1;
  ASSERT_NE(begin, 0u) << path;
  text.replace(begin, text.find('\n', begin) - begin, line);
  WriteBytes(path, text);
}

// ---------------------------------------------------------------------------
// The cases.

const std::string kImport = "lidar_importer --dataset_path $DATA --workspace_path $WS";
const std::string kImportKitti =
    "lidar_importer --dataset_path $KITTI --workspace_path $WS";
const std::string kExtract =
    "line_extractor --database_path $WS/database.db --image_path $WS/images "
    "--LineExtraction.num_threads 1";

std::vector<BadInputCase> Cases() {
  std::vector<BadInputCase> cases;
  const auto add = [&cases](BadInputCase c) { cases.push_back(std::move(c)); };

  // --- lidar_importer, rig format: the recording's folders and files.
  add({"missing_dataset", "dataset folder does not exist", kImport, "$DATA",
       [](const CaseDirs&) {}});
  add({"empty_dataset", "dataset folder is empty", kImport, "$DATA",
       [](const CaseDirs& d) { fs::create_directories(d.data); }});
  add({"missing_calibration", "calibration.yaml deleted",
       kImport, "$DATA",
       [](const CaseDirs& d) {
         UseRig(d);
         fs::remove(JoinPaths(d.data, "calibration.yaml"));
       }});
  add({"empty_calibration", "calibration.yaml is empty (0 bytes)", kImport,
       "$DATA/calibration.yaml", [](const CaseDirs& d) {
         UseRig(d);
         WriteBytes(JoinPaths(d.data, "calibration.yaml"), "");
       }});
  add({"truncated_calibration", "calibration.yaml cut after 40% of its bytes",
       kImport, "$DATA/calibration.yaml", [](const CaseDirs& d) {
         UseRig(d);
         TruncateFile(JoinPaths(d.data, "calibration.yaml"), 0.4);
       }});
  add({"calibration_not_yaml", "calibration.yaml is not YAML (unbalanced [)",
       kImport, "$DATA/calibration.yaml", [](const CaseDirs& d) {
         UseRig(d);
         WriteBytes(JoinPaths(d.data, "calibration.yaml"),
                    "camera: [model: PINHOLE\n");
       }});
  add({"calibration_nan_focal", "camera.params[0] is .nan", kImport,
       "camera.params[0]", [](const CaseDirs& d) {
         UseRig(d);
         ReplaceInFile(JoinPaths(d.data, "calibration.yaml"), "params: [",
                       "params: [.nan, ");
         // Keep the parameter count: drop the original first value.
         std::string text = ReadBytes(JoinPaths(d.data, "calibration.yaml"));
         const size_t start = text.find(".nan, ") + 6;
         text.erase(start, text.find(", ", start) + 2 - start);
         WriteBytes(JoinPaths(d.data, "calibration.yaml"), text);
       }});
  add({"calibration_inf_extrinsic", "cam_from_lidar[0][3] is .inf", kImport,
       "cam_from_lidar[0][3]", [](const CaseDirs& d) {
         UseRig(d);
         std::string text = ReadBytes(JoinPaths(d.data, "calibration.yaml"));
         const size_t row = text.find("  - [", text.find("cam_from_lidar"));
         const size_t last = text.rfind(", ", text.find("]", row)) + 2;
         text.replace(last, text.find("]", row) - last, ".inf");
         WriteBytes(JoinPaths(d.data, "calibration.yaml"), text);
       }});
  add({"calibration_param_count", "PINHOLE with 3 params instead of 4",
       kImport, "$DATA/calibration.yaml", [](const CaseDirs& d) {
         UseRig(d);
         std::string text = ReadBytes(JoinPaths(d.data, "calibration.yaml"));
         const size_t end = text.find("]", text.find("params: ["));
         text.erase(text.rfind(", ", end), end - text.rfind(", ", end));
         WriteBytes(JoinPaths(d.data, "calibration.yaml"), text);
       }});
  add({"calibration_unknown_model", "camera.model FISHEYE_XYZ", kImport,
       "$DATA/calibration.yaml", [](const CaseDirs& d) {
         UseRig(d);
         ReplaceInFile(JoinPaths(d.data, "calibration.yaml"),
                       "model: PINHOLE", "model: FISHEYE_XYZ");
       }});
  add({"calibration_zero_width", "camera.width 0", kImport,
       "$DATA/calibration.yaml", [](const CaseDirs& d) {
         UseRig(d);
         ReplaceInFile(JoinPaths(d.data, "calibration.yaml"), "width: 96",
                       "width: 0");
       }});
  add({"calibration_not_rigid", "cam_from_lidar rotation scaled by 2",
       kImport, "$DATA/calibration.yaml", [](const CaseDirs& d) {
         UseRig(d);
         // Rewrites the 3x3 block as 2 * identity.
         std::string text = ReadBytes(JoinPaths(d.data, "calibration.yaml"));
         const size_t begin = text.find("\n", text.find("cam_from_lidar")) + 1;
         const size_t end = text.find("  - [0, 0, 0, 1]", begin);
         text.replace(begin, end - begin,
                      "  - [2, 0, 0, 0]\n  - [0, 2, 0, 0]\n  - [0, 0, 2, 0]\n");
         WriteBytes(JoinPaths(d.data, "calibration.yaml"), text);
       }});
  add({"calibration_size_mismatch",
       "calibration says 128x64, every image is 96x64", kImport,
       "$DATA/images/000000.png", [](const CaseDirs& d) {
         UseRig(d);
         ReplaceInFile(JoinPaths(d.data, "calibration.yaml"), "width: 96",
                       "width: 128");
       }});
  add({"image_other_size", "one image is 48x32, the others 96x64", kImport,
       "$DATA/images/000001.png", [](const CaseDirs& d) {
         UseRig(d);
         ResizeImage(Frame(d, "images", 1), 48, 32);
       }});
  add({"missing_images_folder", "images/ deleted", kImport, "$DATA/images",
       [](const CaseDirs& d) {
         UseRig(d);
         fs::remove_all(JoinPaths(d.data, "images"));
       }});
  add({"no_frames", "images/ and lidar/ are empty", kImport, "$DATA/images",
       [](const CaseDirs& d) {
         UseRig(d);
         for (const char* dir : {"images", "lidar"}) {
           fs::remove_all(JoinPaths(d.data, dir));
           fs::create_directories(JoinPaths(d.data, dir));
         }
       }});
  add({"image_without_scan", "lidar/000001.ply deleted", kImport,
       "$DATA/images/000001.png", [](const CaseDirs& d) {
         UseRig(d);
         fs::remove(Frame(d, "lidar", 1));
       }});
  add({"scan_without_image", "images/000002.png deleted", kImport,
       "$DATA/lidar/000002.ply", [](const CaseDirs& d) {
         UseRig(d);
         fs::remove(Frame(d, "images", 2));
       }});
  add({"duplicate_image_names", "images/000001.png and images/000001.jpg",
       kImport, "$DATA/images/000001.jpg", [](const CaseDirs& d) {
         UseRig(d);
         const cv::Mat image = cv::imread(Frame(d, "images", 1));
         cv::imwrite(JoinPaths(d.data, "images/000001.jpg"), image);
       }});
  add({"duplicate_scan_names", "lidar/000001.ply and lidar/000001.pcd",
       kImport, "$DATA/lidar/000001.pcd", [](const CaseDirs& d) {
         UseRig(d);
         WriteLidarScanPcd(JoinPaths(d.data, "lidar/000001.pcd"),
                           ReadLidarScan(Frame(d, "lidar", 1)));
       }});
  add({"empty_image", "images/000001.png is empty (0 bytes)", kImport,
       "$DATA/images/000001.png", [](const CaseDirs& d) {
         UseRig(d);
         WriteBytes(Frame(d, "images", 1), "");
       }});
  add({"truncated_image", "images/000001.png cut in half", kImport,
       "$DATA/images/000001.png", [](const CaseDirs& d) {
         UseRig(d);
         TruncateFile(Frame(d, "images", 1), 0.5);
       }});
  add({"empty_scan", "lidar/000001.ply is empty (0 bytes)", kImport,
       "$DATA/lidar/000001.ply", [](const CaseDirs& d) {
         UseRig(d);
         WriteBytes(Frame(d, "lidar", 1), "");
       }});
  add({"truncated_scan", "binary lidar/000001.ply cut in half", kImport,
       "$DATA/lidar/000001.ply", [](const CaseDirs& d) {
         UseRig(d);
         TruncateFile(Frame(d, "lidar", 1), 0.5);
       }});
  add({"scan_overclaims", "PLY header claims twice the vertices it holds",
       kImport, "$DATA/lidar/000001.ply", [](const CaseDirs& d) {
         UseRig(d);
         const size_t count = ReadLidarScan(Frame(d, "lidar", 1)).size();
         ReplaceInFile(Frame(d, "lidar", 1),
                       "element vertex " + std::to_string(count) + "\n",
                       "element vertex " + std::to_string(2 * count) + "\n");
       }});
  add({"scan_nan_point", "ASCII PLY with a nan coordinate", kImport,
       "$DATA/lidar/000001.ply", [](const CaseDirs& d) {
         UseRig(d);
         WriteAsciiPly(Frame(d, "lidar", 1),
                       {"5 0.5 0.2", "nan 1 0.3", "6 -1 0.1"});
       }});
  add({"scan_inf_point", "ASCII PLY with an inf coordinate", kImport,
       "$DATA/lidar/000001.ply", [](const CaseDirs& d) {
         UseRig(d);
         WriteAsciiPly(Frame(d, "lidar", 1),
                       {"5 0.5 0.2", "4 inf 0.3", "6 -1 0.1"});
       }});
  add({"scan_without_xyz", "PLY vertices with properties a b c", kImport,
       "$DATA/lidar/000001.ply", [](const CaseDirs& d) {
         UseRig(d);
         WriteBytes(Frame(d, "lidar", 1),
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float "
                    "a\nproperty float b\nproperty float c\nend_header\n1 2 "
                    "3\n");
       }});
  add({"scan_wrong_endianness",
       "little-endian PLY data declared binary_big_endian", kImport,
       "$DATA/lidar/000001.ply", [](const CaseDirs& d) {
         UseRig(d);
         ReplaceInFile(Frame(d, "lidar", 1), "binary_little_endian",
                       "binary_big_endian");
       }});
  add({"scan_wrong_endianness_finite",
       "as above, every byte-swapped coordinate finite (garbage ranges)",
       kImport, "$DATA/lidar/000001.ply", [](const CaseDirs& d) {
         UseRig(d);
         const LidarScan scan = ReadLidarScan(Frame(d, "lidar", 1));
         LidarScan kept;
         for (const Eigen::Vector3f& point : scan.points) {
           const Eigen::Vector3f swapped(SwapBytes(point.x()),
                                         SwapBytes(point.y()),
                                         SwapBytes(point.z()));
           if (swapped.allFinite() && swapped != Eigen::Vector3f::Zero()) {
             kept.points.push_back(point);
           }
         }
         ASSERT_GT(kept.size(), 100u);
         WriteLidarScanPly(Frame(d, "lidar", 1), kept);
         ReplaceInFile(Frame(d, "lidar", 1), "binary_little_endian",
                       "binary_big_endian");
       }});
  add({"scan_all_no_return", "every point of the scan is (0, 0, 0)", kImport,
       "$DATA/lidar/000001.ply", [](const CaseDirs& d) {
         UseRig(d);
         WriteAsciiPly(Frame(d, "lidar", 1), {"0 0 0", "0 0 0", "0 0 0"});
       }});
  add({"scan_behind_camera",
       "scan keeps only the points behind the camera (z <= 0)", kImport,
       "$DATA/lidar/000001.ply", [](const CaseDirs& d) {
         UseRig(d);
         FilterScanInCameraFrame(
             d, [](const Eigen::Vector3d& p) { return p.z() <= 0; });
       }});
  add({"pcd_bad_header", "lidar/000001.pcd whose header has no FIELDS line",
       kImport, "$DATA/lidar/000001.pcd", [](const CaseDirs& d) {
         UseRig(d);
         fs::remove(Frame(d, "lidar", 1));
         WriteBytes(JoinPaths(d.data, "lidar/000001.pcd"),
                    "VERSION .7\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\n"
                    "POINTS 1\nDATA ascii\n1 2 3\n");
       }});

  // PCL's parser reads on past DATA as long as lines start with a keyword:
  // a POINTS line in the data would resize its buffer after our checks
  // (found by fuzz_pcd; PCL threw std::out_of_range or overflowed before).
  add({"pcd_header_in_data",
       "lidar/000001.pcd whose data starts with a header line",
       kImport, "$DATA/lidar/000001.pcd", [](const CaseDirs& d) {
         UseRig(d);
         fs::remove(Frame(d, "lidar", 1));
         WriteBytes(JoinPaths(d.data, "lidar/000001.pcd"),
                    "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\n"
                    "HEIGHT 1\nPOINTS 1\nDATA ascii\nPOINTS 1000\n1 2 3\n");
       }});

  // --- lidar_importer, rig format: the prior poses.
  add({"missing_poses", "poses_prior.txt deleted", kImport,
       "$DATA/poses_prior.txt", [](const CaseDirs& d) {
         UseRig(d);
         fs::remove(JoinPaths(d.data, "poses_prior.txt"));
       }});
  add({"empty_poses", "poses_prior.txt is empty (0 bytes)", kImport,
       "$DATA/poses_prior.txt", [](const CaseDirs& d) {
         UseRig(d);
         WriteBytes(JoinPaths(d.data, "poses_prior.txt"), "");
       }});
  add({"poses_missing_frame", "poses_prior.txt lacks frame 000002", kImport,
       "$DATA/poses_prior.txt", [](const CaseDirs& d) {
         UseRig(d);
         std::string text = ReadBytes(JoinPaths(d.data, "poses_prior.txt"));
         text.erase(text.find("\n000002 ") + 1);
         WriteBytes(JoinPaths(d.data, "poses_prior.txt"), text);
       }});
  add({"poses_seven_columns", "a pose line with 7 columns", kImport,
       "$DATA/poses_prior.txt", [](const CaseDirs& d) {
         UseRig(d);
         WriteBytes(JoinPaths(d.data, "poses_prior.txt"),
                    ReadBytes(JoinPaths(d.data, "poses_prior.txt")) +
                        "000003 1 2 3 0 0 0\n");
       }});
  add({"poses_nan", "a pose with tx = nan", kImport, "$DATA/poses_prior.txt",
       [](const CaseDirs& d) {
         UseRig(d);
         ReplacePoseLine(d, "000001 nan 0 0 0 0 0 1");
       }});
  add({"poses_zero_quaternion", "a pose with quaternion 0 0 0 0", kImport,
       "$DATA/poses_prior.txt", [](const CaseDirs& d) {
         UseRig(d);
         ReplacePoseLine(d, "000001 1 2 3 0 0 0 0");
       }});
  add({"poses_duplicate_frame", "frame 000001 has two poses", kImport,
       "$DATA/poses_prior.txt", [](const CaseDirs& d) {
         UseRig(d);
         WriteBytes(JoinPaths(d.data, "poses_prior.txt"),
                    ReadBytes(JoinPaths(d.data, "poses_prior.txt")) +
                        "000001 1 2 3 0 0 0 1\n");
       }});
  add({"poses_unknown_frame", "a pose for frame 000099, which does not exist",
       kImport, "$DATA/poses_prior.txt", [](const CaseDirs& d) {
         UseRig(d);
         WriteBytes(JoinPaths(d.data, "poses_prior.txt"),
                    ReadBytes(JoinPaths(d.data, "poses_prior.txt")) +
                        "000099 1 2 3 0 0 0 1\n");
       }});

  // --- lidar_importer, KITTI raw.
  add({"kitti_missing_velo_calib", "calib_velo_to_cam.txt deleted",
       kImportKitti, "$KITTI/calib_velo_to_cam.txt", [](const CaseDirs& d) {
         UseKitti(d);
         fs::remove(JoinPaths(d.kitti, "calib_velo_to_cam.txt"));
       }});
  add({"kitti_calib_missing_key", "P_rect_02 line deleted", kImportKitti,
       "$KITTI/calib_cam_to_cam.txt", [](const CaseDirs& d) {
         UseKitti(d);
         std::string text =
             ReadBytes(JoinPaths(d.kitti, "calib_cam_to_cam.txt"));
         const size_t begin = text.find("P_rect_02:");
         text.erase(begin, text.find('\n', begin) + 1 - begin);
         WriteBytes(JoinPaths(d.kitti, "calib_cam_to_cam.txt"), text);
       }});
  add({"kitti_calib_value_count", "T of calib_velo_to_cam.txt has 2 values",
       kImportKitti, "$KITTI/calib_velo_to_cam.txt", [](const CaseDirs& d) {
         UseKitti(d);
         std::string text =
             ReadBytes(JoinPaths(d.kitti, "calib_velo_to_cam.txt"));
         const size_t begin = text.find("T:");
         text.replace(begin, text.find('\n', begin) - begin, "T: 0.1 0.2");
         WriteBytes(JoinPaths(d.kitti, "calib_velo_to_cam.txt"), text);
       }});
  add({"kitti_image_size_mismatch", "S_rect_02 says 1240x375, images are "
       "1242x375", kImportKitti, "$KITTI/image_02/data/0000000000.png",
       [](const CaseDirs& d) {
         UseKitti(d);
         std::string text =
             ReadBytes(JoinPaths(d.kitti, "calib_cam_to_cam.txt"));
         const size_t begin = text.find("S_rect_02:");
         text.replace(begin, text.find('\n', begin) - begin,
                      "S_rect_02: 1.240000e+03 3.750000e+02");
         WriteBytes(JoinPaths(d.kitti, "calib_cam_to_cam.txt"), text);
       }});
  add({"kitti_bin_truncated", "a .bin cut to a size that is not a multiple "
       "of 16 bytes", kImportKitti,
       "$KITTI/velodyne_points/data/0000000001.bin", [](const CaseDirs& d) {
         UseKitti(d);
         const std::string bytes = ReadBytes(KittiScan(d, 1));
         WriteBytes(KittiScan(d, 1), bytes.substr(0, bytes.size() / 2 + 7));
       }});
  add({"kitti_bin_empty", "a .bin is empty (0 bytes)", kImportKitti,
       "$KITTI/velodyne_points/data/0000000001.bin", [](const CaseDirs& d) {
         UseKitti(d);
         WriteBytes(KittiScan(d, 1), "");
       }});
  add({"kitti_bin_nan", "the first x of a .bin is NaN", kImportKitti,
       "$KITTI/velodyne_points/data/0000000001.bin", [](const CaseDirs& d) {
         UseKitti(d);
         std::string bytes = ReadBytes(KittiScan(d, 1));
         const float nan = std::numeric_limits<float>::quiet_NaN();
         std::memcpy(bytes.data(), &nan, sizeof(nan));
         WriteBytes(KittiScan(d, 1), bytes);
       }});
  add({"kitti_bin_big_endian", "a .bin written big-endian (bytes swapped)",
       kImportKitti, "$KITTI/velodyne_points/data/0000000001.bin",
       [](const CaseDirs& d) {
         UseKitti(d);
         SwapWords(KittiScan(d, 1));
       }});
  add({"kitti_camera_out_of_range", "--LidarImport.kitti_camera 7",
       kImportKitti + " --LidarImport.kitti_camera 7",
       "LidarImport.kitti_camera", [](const CaseDirs& d) { UseKitti(d); }});
  add({"kitti_camera_absent", "--LidarImport.kitti_camera 3, no image_03",
       kImportKitti + " --LidarImport.kitti_camera 3", "image_03/data",
       [](const CaseDirs& d) { UseKitti(d); }});

  // --- lidar_importer: the workspace.
  add({"workspace_is_a_file", "--workspace_path names a file", kImport, "$WS",
       [](const CaseDirs& d) {
         UseRig(d);
         WriteBytes(d.ws, "a file\n");
       }});
  add({"reimport_without_overwrite",
       "the recording imported a second time without overwrite", kImport,
       "$WS/database.db", [](const CaseDirs& d) {
         UseRig(d);
         UseWorkspace(d);
       }});
  add({"database_not_sqlite", "$WS/database.db holds text", kImport,
       "$WS/database.db", [](const CaseDirs& d) {
         UseRig(d);
         fs::create_directories(d.ws);
         WriteBytes(JoinPaths(d.ws, "database.db"), "not a database\n");
       }});
  add({"database_truncated", "$WS/database.db cut in half", kImport,
       "$WS/database.db", [](const CaseDirs& d) {
         UseRig(d);
         UseWorkspace(d);
         TruncateFile(JoinPaths(d.ws, "database.db"), 0.5);
       }});
  add({"workspace_images_other_size",
       "existing workspace whose images (and camera) are 96x64, recording "
       "calibrated for 128x64", kImport + " --LidarImport.overwrite 1",
       "$WS/images/000000.png", [](const CaseDirs& d) {
         UseRig(d);
         UseWorkspace(d);
         ReplaceInFile(JoinPaths(d.data, "calibration.yaml"), "width: 96",
                       "width: 128");
         for (int i = 0; i < 3; ++i) {
           ResizeImage(Frame(d, "images", i), 128, 64);
         }
       }});
  add({"read_only_workspace",
       "re-import with overwrite into a read-only workspace",
       kImport + " --LidarImport.overwrite 1", "$WS/database.db",
       [](const CaseDirs& d) {
         UseRig(d);
         UseWorkspace(d);
         SetWritable(d.ws, false);
       },
       RunMode::kReadOnly});
  add({"disk_full_new_workspace",
       "files limited to 256 KiB (full disk): the scan copies fail", kImport,
       "$WS/lidar/000000.ply", [](const CaseDirs& d) { UseRig(d); },
       RunMode::kFullDisk});
  add({"disk_full_existing_folder",
       "as above, into an existing empty workspace folder", kImport,
       "$WS/lidar/000000.ply", [](const CaseDirs& d) {
         UseRig(d);
         fs::create_directories(d.ws);
       },
       RunMode::kFullDisk});

  // --- The command line.
  add({"unknown_option", "--LidarImport.copy_imagez 1",
       kImport + " --LidarImport.copy_imagez 1", "LidarImport.copy_imagez",
       [](const CaseDirs& d) { UseRig(d); }});
  add({"bad_bool_value", "--LidarImport.copy_images maybe",
       kImport + " --LidarImport.copy_images maybe", "LidarImport.copy_images",
       [](const CaseDirs& d) { UseRig(d); }});
  add({"unknown_input_format", "--LidarImport.input_format las",
       kImport + " --LidarImport.input_format las", "LidarImport.input_format",
       [](const CaseDirs& d) { UseRig(d); }});
  add({"missing_required_option", "--workspace_path not given",
       "lidar_importer --dataset_path $DATA", "--workspace_path",
       [](const CaseDirs& d) { UseRig(d); }});
  add({"stray_argument", "a positional argument", kImport + " extra",
       "'extra'", [](const CaseDirs& d) { UseRig(d); }});
  add({"preset_missing", "--project_path names no file",
       kImport + " --project_path $CASE/missing.ini", "$CASE/missing.ini",
       [](const CaseDirs& d) { UseRig(d); }});
  add({"preset_unknown_key", "preset with [LidarImport] copy_imagez=1",
       kImport + " --project_path $CASE/preset.ini", "copy_imagez",
       [](const CaseDirs& d) {
         UseRig(d);
         WriteBytes(JoinPaths(d.root, "preset.ini"),
                    "[LidarImport]\ncopy_imagez=1\n");
       }});

  // --- synthesize: out-of-range and malformed options.
  const std::string synth = "synthesize --output_path $CASE/out";
  add({"synth_zero_frames", "--Synthesis.num_frames 0",
       synth + " --Synthesis.num_frames 0", "num_frames",
       [](const CaseDirs&) {}});
  add({"synth_not_a_number", "--Synthesis.num_frames three",
       synth + " --Synthesis.num_frames three", "Synthesis.num_frames",
       [](const CaseDirs&) {}});
  add({"synth_tiny_image", "--Synthesis.image_width 4",
       synth + " --Synthesis.image_width 4", "image_width",
       [](const CaseDirs&) {}});
  add({"synth_fov_out_of_range", "--Synthesis.horizontal_fov_deg 180",
       synth + " --Synthesis.horizontal_fov_deg 180", "horizontal_fov_deg",
       [](const CaseDirs&) {}});
  add({"synth_unknown_preset", "--Synthesis.preset moon",
       synth + " --Synthesis.preset moon", "Synthesis.preset",
       [](const CaseDirs&) {}});
  add({"synth_dropout_one", "--Synthesis.lidar_dropout_probability 1",
       synth + " --Synthesis.lidar_dropout_probability 1",
       "lidar_dropout_probability", [](const CaseDirs&) {}});
  add({"synth_output_is_file", "--output_path names a file",
       "synthesize --output_path $CASE/file --Synthesis.num_frames 1",
       "$CASE/file", [](const CaseDirs& d) {
         WriteBytes(JoinPaths(d.root, "file"), "a file\n");
       }});
  add({"synth_output_not_empty", "--output_path is a recording already",
       "synthesize --output_path $DATA --Synthesis.num_frames 1", "$DATA",
       [](const CaseDirs& d) { UseRig(d); }});

  // --- Later stages on broken workspaces.
  add({"extract_missing_database", "$WS/database.db deleted", kExtract,
       "$WS/database.db", [](const CaseDirs& d) {
         UseWorkspace(d);
         fs::remove(JoinPaths(d.ws, "database.db"));
       }});
  add({"extract_missing_scan", "$WS/lidar/000001.ply deleted", kExtract,
       "$WS/lidar/000001.ply", [](const CaseDirs& d) {
         UseWorkspace(d);
         fs::remove(JoinPaths(d.ws, "lidar/000001.ply"));
       }});
  add({"extract_missing_image", "$WS/images/000001.png deleted", kExtract,
       "$WS/images/000001.png", [](const CaseDirs& d) {
         UseWorkspace(d);
         fs::remove(JoinPaths(d.ws, "images/000001.png"));
       }});
  add({"extract_bad_option", "--LineExtraction.num_threads 0",
       "line_extractor --database_path $WS/database.db --image_path "
       "$WS/images --LineExtraction.num_threads 0",
       "LineExtraction.num_threads", [](const CaseDirs& d) {
         UseWorkspace(d);
       }});
  add({"matcher_no_model", "--input_path is an empty folder",
       "line_matcher --database_path $WS/database.db --input_path "
       "$WS/sparse/empty",
       "$WS/sparse/empty", [](const CaseDirs& d) {
         UseWorkspace(d);
         fs::create_directories(JoinPaths(d.ws, "sparse/empty"));
       }});
  add({"matcher_truncated_model", "$WS/sparse/prior/images.bin cut in half",
       "line_matcher --database_path $WS/database.db --input_path "
       "$WS/sparse/prior",
       "$WS/sparse/prior/images.bin", [](const CaseDirs& d) {
         UseWorkspace(d);
         TruncateFile(JoinPaths(d.ws, "sparse/prior/images.bin"), 0.5);
       }});
  add({"fuser_truncated_scan", "$WS/lidar/000001.ply cut in half",
       "lidar_fuser --database_path $WS/database.db --input_path "
       "$WS/sparse/prior --output_path $WS/dense",
       "$WS/lidar/000001.ply", [](const CaseDirs& d) {
         UseWorkspace(d);
         TruncateFile(JoinPaths(d.ws, "lidar/000001.ply"), 0.5);
       }});
  add({"mesh_eval_missing_mesh", "--input_path names no file",
       "mesh_evaluator --input_path $CASE/mesh.ply --reference_path "
       "$DATA/lidar/000000.ply",
       "$CASE/mesh.ply", [](const CaseDirs& d) { UseRig(d); }});
  add({"mesh_eval_truncated_mesh", "mesh PLY cut in half",
       "mesh_evaluator --input_path $CASE/mesh.ply --reference_path "
       "$DATA/lidar/000000.ply",
       "$CASE/mesh.ply", [](const CaseDirs& d) {
         UseRig(d);
         fs::copy_file(Frame(d, "lidar", 1), JoinPaths(d.root, "mesh.ply"));
         TruncateFile(JoinPaths(d.root, "mesh.ply"), 0.5);
       }});
  add({"mesh_eval_empty_reference", "reference PLY with 0 vertices",
       "mesh_evaluator --input_path $DATA/lidar/000001.ply --reference_path "
       "$CASE/reference.ply",
       "$CASE/reference.ply", [](const CaseDirs& d) {
         UseRig(d);
         WriteAsciiPly(JoinPaths(d.root, "reference.ply"), {});
       }});
  add({"pose_eval_nan", "poses_gt.txt with tx = nan",
       "pose_evaluator --input_path $WS/sparse/prior --ground_truth_path "
       "$DATA/poses_gt.txt",
       "$DATA/poses_gt.txt", [](const CaseDirs& d) {
         UseRig(d);
         UseWorkspace(d);
         std::string text = ReadBytes(JoinPaths(d.data, "poses_gt.txt"));
         const size_t begin = text.find("\n000001 ") + 1;
         text.replace(begin, text.find('\n', begin) - begin,
                      "000001 nan 0 0 0 0 0 1");
         WriteBytes(JoinPaths(d.data, "poses_gt.txt"), text);
       }});
  return cases;
}

// ---------------------------------------------------------------------------

bool IsRoot() { return ::geteuid() == 0; }

// Sets the case up, runs it and compares the case folder before and after.
// Thread-safe: two cases run at a time.
CaseResult RunCase(const BadInputCase& c, const CaseDirs& dirs) {
  CaseResult result;
  c.setup(dirs);
  const uint64_t before = HashTree(dirs.root);

  std::string prefix;
  if (c.mode == RunMode::kReadOnly && IsRoot()) {
    // Root ignores permission bits; run as nobody instead.
    if (testing::RunCommand("setpriv --reuid=65534 --regid=65534 "
                            "--clear-groups true") != 0) {
      result.skipped = true;
      return result;
    }
    prefix = "setpriv --reuid=65534 --regid=65534 --clear-groups ";
  } else if (c.mode == RunMode::kFullDisk) {
    prefix = "trap '' XFSZ; prlimit --fsize=262144 ";
  }
  // The log lives outside the case folder, which must stay unchanged.
  const std::string log = dirs.root + ".log";
  result.exit_code = testing::RunCommand(
      prefix + Quote(Executable()) + " " + Expand(c.command, dirs), log);
  result.output = ReadTextFile(log);
  fs::remove(log);
  result.message = Placeholders(FirstErrorLine(result.output), dirs);
  if (c.mode == RunMode::kReadOnly) {
    SetWritable(dirs.ws, true);
  }
  result.unchanged = HashTree(dirs.root) == before;
  return result;
}

void CheckResult(const BadInputCase& c, const CaseResult& result) {
  if (result.skipped) {
    return;
  }
  EXPECT_TRUE(result.exit_code == 1 || result.exit_code == 2)
      << c.id << ": exit code " << result.exit_code << "\n" << result.output;
  EXPECT_NE(result.message.find(c.names), std::string::npos)
      << c.id << ": the first error line does not name '" << c.names
      << "'\n" << result.output;
  EXPECT_TRUE(result.unchanged)
      << c.id << ": the case folder changed\n" << result.output;
}

std::string TableRow(int number, const BadInputCase& c,
                     const CaseResult& result) {
  std::ostringstream row;
  row << "| " << number << " | `" << c.id << "` " << c.broken << " | "
      << MarkdownCode("colmap-lidar " + c.command) << " | ";
  if (result.skipped) {
    row << "skipped | (setpriv unavailable) | - |";
  } else {
    row << result.exit_code << " | " << MarkdownCode(result.message) << " | "
        << (result.unchanged ? "yes" : "no") << " |";
  }
  return row.str();
}

std::string DocPath() {
  return JoinPaths(testing::SourceDir(), "docs/robustness.md");
}

TEST(Robustness, BadInputsFailCleanlyAndMatchTheTable) {
  ASSERT_TRUE(Base().ok);
  const std::vector<BadInputCase> cases = Cases();
  std::map<std::string, int> ids;
  for (const BadInputCase& c : cases) {
    EXPECT_EQ(ids[c.id]++, 0) << "duplicate case id " << c.id;
  }

  std::ostringstream table;
  table << "| # | case | command | exit | message (first line) | workspace "
           "unchanged |\n|---|---|---|---|---|---|\n";
  // Two cases at a time: most of a case is the executable starting up.
  std::vector<CaseDirs> dirs(cases.size());
  std::vector<CaseResult> results(cases.size());
  std::atomic<size_t> next_case(0);
  const auto worker = [&]() {
    for (size_t i = next_case++; i < cases.size(); i = next_case++) {
      dirs[i].root = testing::CreateTestDir();
      dirs[i].data = JoinPaths(dirs[i].root, "data");
      dirs[i].ws = JoinPaths(dirs[i].root, "ws");
      dirs[i].kitti = JoinPaths(dirs[i].root, "kitti");
      results[i] = RunCase(cases[i], dirs[i]);
    }
  };
  std::thread helper(worker);
  worker();
  helper.join();

  for (size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].id);
    const bool had_failure = ::testing::Test::HasFailure();
    CheckResult(cases[i], results[i]);
    table << TableRow(static_cast<int>(i + 1), cases[i], results[i]) << "\n";
    // Failed cases keep their folder for a look.
    if (::testing::Test::HasFailure() == had_failure) {
      fs::remove_all(dirs[i].root);
    }
  }
  EXPECT_GE(cases.size(), 40u);

  const std::string doc = ReadTextFile(DocPath());
  const size_t begin = doc.find(kTableBegin);
  const size_t end = doc.find(kTableEnd);
  ASSERT_NE(begin, std::string::npos) << DocPath() << " lacks " << kTableBegin;
  ASSERT_NE(end, std::string::npos) << DocPath() << " lacks " << kTableEnd;
  const size_t table_begin = begin + std::strlen(kTableBegin) + 1;
  const std::string documented = doc.substr(table_begin, end - table_begin);
  const char* update = std::getenv("COLMAP_LIDAR_UPDATE_DOCS");
  if (update != nullptr && std::string(update) == "1") {
    WriteBytes(DocPath(), doc.substr(0, table_begin) + table.str() +
                              doc.substr(end));
    return;
  }
  EXPECT_EQ(documented, table.str())
      << DocPath() << " differs from the cases; regenerate its table with "
      << "COLMAP_LIDAR_UPDATE_DOCS=1 ctest -R tests/robustness";
}

}  // namespace
}  // namespace colmap_lidar
