#include "colmap_ext/model/model_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

const char* const kColmap = "/usr/bin/colmap";

// A consistent model with awkward values: non-contiguous ids in non-sorted
// file order, several camera models, values that need all 17 digits, points2D
// without a 3D point, images without points, 3D lines.
Reconstruction TestReconstruction(int num_points = 40) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> uniform(-10.0, 10.0);
  Reconstruction reconstruction;
  const std::vector<std::pair<std::string, std::vector<double>>> cameras = {
      {"PINHOLE", {500.125, 501.0 / 3.0, 320.5, 240.25}},
      {"OPENCV",
       {480, 481, 319.5, 239.5, -0.1, 0.0123456789012345, 1e-5, -2e-5}},
      {"SIMPLE_RADIAL", {600, 300, 200, 0.1 / 7.0}},
      {"FULL_OPENCV",
       {400, 410, 300, 200, -0.1, 0.01, 1e-4, 2e-4, 1e-3, 0.02, -1e-3, 1e-4}}};
  camera_t camera_id = 10;
  for (const auto& [model_name, params] : cameras) {
    Camera camera = Camera::FromModelName(model_name, 640 + camera_id,
                                          480 - camera_id, params);
    camera.camera_id = camera_id;
    reconstruction.cameras[camera_id] = camera;
    camera_id -= 3;  // 10, 7, 4, 1
  }
  const std::vector<image_t> image_ids = {17, 3, 1000, 42, 5};
  for (size_t i = 0; i < image_ids.size(); ++i) {
    Image image;
    image.image_id = image_ids[i];
    image.name = "seq_" + std::to_string(i % 2) + "/frame_" +
                 std::to_string(image_ids[i]) + ".png";
    image.camera_id = static_cast<camera_t>(1 + 3 * (i % 4));
    image.cam_from_world.rotation = Eigen::Quaterniond(
        Eigen::AngleAxisd(0.1 + i, Eigen::Vector3d(1.0, i, -2.0).normalized()));
    if (i == 1) {
      // colmap does not canonicalise the sign; neither do we.
      image.cam_from_world.rotation.coeffs() *= -1;
    }
    image.cam_from_world.translation =
        Eigen::Vector3d(uniform(rng), uniform(rng), 1.0 / 3.0);
    reconstruction.images.push_back(image);
  }
  // Image 42 keeps an empty points2D list.
  point3D_t point3D_id = (1ull << 40) + 7;
  for (int p = 0; p < num_points; ++p) {
    Point3D point3D;
    point3D.xyz = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
    point3D.color = Vector3ub(p % 256, (7 * p) % 256, 255 - p % 256);
    point3D.error = p == 0 ? -1.0 : std::abs(uniform(rng)) / 9.0;
    for (const size_t i : {size_t{0}, size_t{1}, size_t{2}, size_t{4}}) {
      if ((p + i) % 3 == 0 && i != 0) {
        continue;
      }
      Image& image = reconstruction.images[i];
      Point2D point2D;
      point2D.xy = Eigen::Vector2d(uniform(rng) + 320, uniform(rng) + 240);
      point2D.point3D_id = point3D_id;
      point3D.track.push_back(
          {image.image_id, static_cast<point2D_t>(image.points2D.size())});
      image.points2D.push_back(point2D);
      // A point2D without a 3D point after each observation.
      Point2D free_point2D;
      free_point2D.xy = Eigen::Vector2d(0.5, 1e-17);
      image.points2D.push_back(free_point2D);
    }
    reconstruction.points3D[point3D_id] = point3D;
    // Scattered ids.
    point3D_id = (point3D_id * 2654435761ull) % 1000003ull + 1;
  }
  for (const line3D_t line3D_id : {4ull, 2ull, 1ull << 33}) {
    Line3D line3D;
    line3D.start_in_world = Eigen::Vector3d(uniform(rng), 0.1, 1.0 / 7.0);
    line3D.end_in_world = Eigen::Vector3d(-1e-300, uniform(rng), 3.0);
    line3D.error = line3D_id == 2 ? -1.0 : 0.25;
    line3D.track = {{17, 3}, {1000, static_cast<uint32_t>(line3D_id % 5)}};
    reconstruction.lines3D[line3D_id] = line3D;
  }
  reconstruction.CheckConsistency();
  return reconstruction;
}

// Exact comparison; rotations to `rotation_tolerance` (colmap renormalises).
void ExpectEqualReconstructions(const Reconstruction& expected,
                                const Reconstruction& actual,
                                bool compare_image_order = true,
                                bool compare_lines = true,
                                double rotation_tolerance = 0.0) {
  ASSERT_EQ(expected.cameras.size(), actual.cameras.size());
  for (const auto& [camera_id, camera] : expected.cameras) {
    ASSERT_EQ(actual.cameras.count(camera_id), 1u) << camera_id;
    const Camera& other = actual.cameras.at(camera_id);
    EXPECT_EQ(other.camera_id, camera_id);
    EXPECT_EQ(other.model_id, camera.model_id);
    EXPECT_EQ(other.width, camera.width);
    EXPECT_EQ(other.height, camera.height);
    EXPECT_EQ(other.params, camera.params) << camera_id;
  }
  ASSERT_EQ(expected.images.size(), actual.images.size());
  for (size_t i = 0; i < expected.images.size(); ++i) {
    const Image& image = expected.images[i];
    const Image* other = compare_image_order ? &actual.images[i]
                                             : actual.FindImage(image.image_id);
    ASSERT_NE(other, nullptr);
    EXPECT_EQ(other->image_id, image.image_id);
    EXPECT_EQ(other->name, image.name);
    EXPECT_EQ(other->camera_id, image.camera_id);
    const Eigen::Vector4d q = image.cam_from_world.rotation.coeffs();
    const Eigen::Vector4d other_q = other->cam_from_world.rotation.coeffs();
    EXPECT_LE((q - other_q).cwiseAbs().maxCoeff(), rotation_tolerance)
        << image.image_id;
    EXPECT_EQ(other->cam_from_world.translation,
              image.cam_from_world.translation);
    ASSERT_EQ(other->points2D.size(), image.points2D.size());
    for (size_t j = 0; j < image.points2D.size(); ++j) {
      EXPECT_EQ(other->points2D[j].xy, image.points2D[j].xy);
      EXPECT_EQ(other->points2D[j].point3D_id, image.points2D[j].point3D_id);
    }
  }
  ASSERT_EQ(expected.points3D.size(), actual.points3D.size());
  for (const auto& [point3D_id, point3D] : expected.points3D) {
    ASSERT_EQ(actual.points3D.count(point3D_id), 1u) << point3D_id;
    const Point3D& other = actual.points3D.at(point3D_id);
    EXPECT_EQ(other.xyz, point3D.xyz);
    EXPECT_EQ(other.color, point3D.color);
    EXPECT_EQ(other.error, point3D.error);
    ASSERT_EQ(other.track.size(), point3D.track.size());
    for (size_t j = 0; j < point3D.track.size(); ++j) {
      EXPECT_EQ(other.track[j].image_id, point3D.track[j].image_id);
      EXPECT_EQ(other.track[j].point2D_idx, point3D.track[j].point2D_idx);
    }
  }
  if (!compare_lines) {
    return;
  }
  ASSERT_EQ(expected.lines3D.size(), actual.lines3D.size());
  for (const auto& [line3D_id, line3D] : expected.lines3D) {
    ASSERT_EQ(actual.lines3D.count(line3D_id), 1u) << line3D_id;
    const Line3D& other = actual.lines3D.at(line3D_id);
    EXPECT_EQ(other.start_in_world, line3D.start_in_world);
    EXPECT_EQ(other.end_in_world, line3D.end_in_world);
    EXPECT_EQ(other.error, line3D.error);
    ASSERT_EQ(other.track.size(), line3D.track.size());
    for (size_t j = 0; j < line3D.track.size(); ++j) {
      EXPECT_EQ(other.track[j].image_id, line3D.track[j].image_id);
      EXPECT_EQ(other.track[j].line2D_idx, line3D.track[j].line2D_idx);
    }
  }
}

std::string ReadBytes(const std::string& path) { return ReadTextFile(path); }

void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file << bytes;
}

// Runs colmap; on failure the log is printed.
void RunColmap(const std::string& args, const std::string& log_path) {
  const int code =
      testing::RunCommand(std::string(kColmap) + " " + args, log_path);
  ASSERT_EQ(code, 0) << args << "\n" << ReadTextFile(log_path);
}

// The message of the colmap_lidar::Error thrown by fn, or "" if none.
template <typename Fn>
std::string ErrorMessage(Fn&& fn) {
  try {
    fn();
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(ModelIO, BinaryAndTextRoundTripsAreLossless) {
  const Reconstruction reconstruction = TestReconstruction();
  const std::string dir = testing::CreateTestDir();
  for (const ModelFormat format : {ModelFormat::kBinary, ModelFormat::kText}) {
    const std::string model_dir =
        JoinPaths(dir, format == ModelFormat::kBinary ? "bin" : "txt");
    WriteReconstruction(model_dir, reconstruction, format);
    EXPECT_EQ(DetectModelFormat(model_dir), format);
    const Reconstruction read = ReadReconstruction(model_dir);
    ExpectEqualReconstructions(reconstruction, read);
    // Rewriting what was read gives the same bytes (orders preserved).
    const std::string again = model_dir + "_again";
    WriteReconstruction(again, read, format);
    const std::string ext = format == ModelFormat::kBinary ? ".bin" : ".txt";
    for (const std::string name :
         {"cameras", "images", "points3D", "lines3D"}) {
      EXPECT_EQ(ReadBytes(JoinPaths(model_dir, name + ext)),
                ReadBytes(JoinPaths(again, name + ext)))
          << name;
    }
  }
}

TEST(ModelIO, BinaryLayoutSizes) {
  // One PINHOLE camera is 64 bytes (colmap-formats.md 2.1); the other files'
  // sizes follow from the documented layouts.
  Reconstruction reconstruction = TestReconstruction();
  const std::string dir = testing::CreateTestDir();
  WriteReconstruction(dir, reconstruction, ModelFormat::kBinary);
  size_t cameras_bytes = 8;
  for (const auto& entry : reconstruction.cameras) {
    cameras_bytes += 4 + 4 + 8 + 8 + 8 * entry.second.params.size();
  }
  size_t images_bytes = 8;
  for (const Image& image : reconstruction.images) {
    images_bytes +=
        4 + 56 + 4 + image.name.size() + 1 + 8 + 24 * image.points2D.size();
  }
  size_t points_bytes = 8;
  for (const auto& entry : reconstruction.points3D) {
    points_bytes += 8 + 24 + 3 + 8 + 8 + 8 * entry.second.track.size();
  }
  size_t lines_bytes = 8;
  for (const auto& entry : reconstruction.lines3D) {
    lines_bytes += 8 + 48 + 8 + 8 + 8 * entry.second.track.size();
  }
  EXPECT_EQ(ReadBytes(JoinPaths(dir, "cameras.bin")).size(), cameras_bytes);
  EXPECT_EQ(ReadBytes(JoinPaths(dir, "images.bin")).size(), images_bytes);
  EXPECT_EQ(ReadBytes(JoinPaths(dir, "points3D.bin")).size(), points_bytes);
  EXPECT_EQ(ReadBytes(JoinPaths(dir, "lines3D.bin")).size(), lines_bytes);

  Reconstruction single;
  single.cameras[1] = Camera::FromModelName("PINHOLE", 640, 480, {1, 2, 3, 4});
  single.cameras[1].camera_id = 1;
  WriteCamerasBinary(JoinPaths(dir, "single.bin"), single);
  const std::string bytes = ReadBytes(JoinPaths(dir, "single.bin"));
  ASSERT_EQ(bytes.size(), 64u);
  uint64_t num_cameras;
  uint32_t camera_id;
  int32_t model_id;
  uint64_t width, height;
  double fy;
  std::memcpy(&num_cameras, bytes.data(), 8);
  std::memcpy(&camera_id, bytes.data() + 8, 4);
  std::memcpy(&model_id, bytes.data() + 12, 4);
  std::memcpy(&width, bytes.data() + 16, 8);
  std::memcpy(&height, bytes.data() + 24, 8);
  std::memcpy(&fy, bytes.data() + 40, 8);
  EXPECT_EQ(num_cameras, 1u);
  EXPECT_EQ(camera_id, 1u);
  EXPECT_EQ(model_id, 1);
  EXPECT_EQ(width, 640u);
  EXPECT_EQ(height, 480u);
  EXPECT_EQ(fy, 2.0);
}

TEST(ModelIO, TextFormatDetails) {
  Reconstruction reconstruction;
  Camera camera =
      Camera::FromModelName("PINHOLE", 640, 480, {500, 500, 320, 240});
  camera.camera_id = 1;
  reconstruction.cameras[1] = camera;
  Image image;
  image.image_id = 5;
  image.name = "a.png";
  image.camera_id = 1;
  image.cam_from_world.translation = Eigen::Vector3d(0.1, 0, -2);
  image.points2D.resize(2);
  image.points2D[0].xy = Eigen::Vector2d(1.5, 2.5);
  image.points2D[0].point3D_id = 7;
  image.points2D[1].xy = Eigen::Vector2d(3, 4);
  Image empty_image = image;
  empty_image.image_id = 6;
  empty_image.name = "b.png";
  empty_image.points2D.clear();
  reconstruction.images = {image, empty_image};
  Point3D point3D;
  point3D.xyz = Eigen::Vector3d(1, 2, 3);
  point3D.color = Vector3ub(255, 0, 10);
  point3D.error = 0.5;
  point3D.track = {{5, 0}};
  reconstruction.points3D[7] = point3D;
  const std::string dir = testing::CreateTestDir();
  WriteReconstruction(dir, reconstruction, ModelFormat::kText);
  EXPECT_EQ(ReadTextFile(JoinPaths(dir, "cameras.txt")),
            "# Camera list with one line of data per camera:\n"
            "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
            "# Number of cameras: 1\n"
            "1 PINHOLE 640 480 500 500 320 240\n");
  EXPECT_EQ(ReadTextFile(JoinPaths(dir, "images.txt")),
            "# Image list with two lines of data per image:\n"
            "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
            "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
            "# Number of images: 2, mean observations per image: 0.5\n"
            "5 1 0 0 0 0.10000000000000001 0 -2 1 a.png\n"
            "1.5 2.5 7 3 4 -1\n"
            "6 1 0 0 0 0.10000000000000001 0 -2 1 b.png\n"
            "\n");
  EXPECT_EQ(ReadTextFile(JoinPaths(dir, "points3D.txt")),
            "# 3D point list with one line of data per point:\n"
            "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, "
            "POINT2D_IDX)\n"
            "# Number of points: 1, mean track length: 1\n"
            "7 1 2 3 255 0 10 0.5 5 0\n");
  EXPECT_FALSE(ExistsFile(JoinPaths(dir, "lines3D.txt")));

  // colmap writes the same bytes for this model (one image in its output
  // order is not guaranteed, so keep to cameras and points here).
  const std::string colmap_dir = JoinPaths(dir, "colmap");
  CreateDirIfNotExists(colmap_dir);
  RunColmap("model_converter --input_path " + dir + " --output_path " +
                colmap_dir + " --output_type TXT",
            JoinPaths(dir, "convert.log"));
  EXPECT_EQ(ReadTextFile(JoinPaths(colmap_dir, "cameras.txt")),
            ReadTextFile(JoinPaths(dir, "cameras.txt")));
  EXPECT_EQ(ReadTextFile(JoinPaths(colmap_dir, "points3D.txt")),
            ReadTextFile(JoinPaths(dir, "points3D.txt")));

  // Names colmap's text format cannot hold are refused.
  reconstruction.images[0].name = "my img.png";
  EXPECT_NE(ErrorMessage([&] {
              WriteReconstruction(JoinPaths(dir, "spaces"), reconstruction,
                                  ModelFormat::kText);
            }).find("my img.png"),
            std::string::npos);
  // Binary keeps them.
  WriteReconstruction(JoinPaths(dir, "spaces"), reconstruction,
                      ModelFormat::kBinary);
  EXPECT_EQ(ReadReconstruction(JoinPaths(dir, "spaces")).images[0].name,
            "my img.png");
}

TEST(ModelIO, ColmapModelConverterRoundTrip) {
  const Reconstruction reconstruction = TestReconstruction();
  const std::string dir = testing::CreateTestDir();
  const std::string ours_txt = JoinPaths(dir, "ours_txt");
  const std::string ours_bin = JoinPaths(dir, "ours_bin");
  WriteReconstruction(ours_txt, reconstruction, ModelFormat::kText);
  WriteReconstruction(ours_bin, reconstruction, ModelFormat::kBinary);
  struct Case {
    std::string input;
    std::string output_type;
  };
  for (const Case& test_case : {Case{ours_txt, "BIN"}, Case{ours_txt, "TXT"},
                                Case{ours_bin, "BIN"}, Case{ours_bin, "TXT"}}) {
    const std::string output = test_case.input + "_to_" + test_case.output_type;
    CreateDirIfNotExists(output);
    RunColmap("model_converter --input_path " + test_case.input +
                  " --output_path " + output + " --output_type " +
                  test_case.output_type,
              output + ".log");
    const Reconstruction read = ReadReconstruction(output);
    EXPECT_EQ(DetectModelFormat(output), test_case.output_type == "BIN"
                                             ? ModelFormat::kBinary
                                             : ModelFormat::kText);
    // colmap reorders images (hash map) and drops our lines; it renormalises
    // quaternions (last-bit changes at most).
    ExpectEqualReconstructions(reconstruction, read,
                               /*compare_image_order=*/false,
                               /*compare_lines=*/false,
                               /*rotation_tolerance=*/1e-15);
    EXPECT_TRUE(read.lines3D.empty());
  }
}

TEST(ModelIO, ReencodingColmapBinaryIsByteIdentical) {
  // Enough points for colmap's hash-map order to differ from id order.
  const Reconstruction reconstruction = TestReconstruction(200);
  const std::string dir = testing::CreateTestDir();
  const std::string ours_txt = JoinPaths(dir, "ours_txt");
  const std::string colmap_bin = JoinPaths(dir, "colmap_bin");
  const std::string rewritten = JoinPaths(dir, "rewritten");
  WriteReconstruction(ours_txt, reconstruction, ModelFormat::kText);
  CreateDirIfNotExists(colmap_bin);
  RunColmap("model_converter --input_path " + ours_txt + " --output_path " +
                colmap_bin + " --output_type BIN",
            JoinPaths(dir, "convert.log"));
  const Reconstruction read = ReadReconstruction(colmap_bin);
  // The test is only meaningful if colmap did reorder something.
  std::vector<point3D_t> sorted_ids = read.point3D_file_order;
  std::sort(sorted_ids.begin(), sorted_ids.end());
  EXPECT_NE(sorted_ids, read.point3D_file_order);
  WriteReconstruction(rewritten, read, ModelFormat::kBinary);
  for (const std::string name : {"cameras.bin", "images.bin", "points3D.bin"}) {
    const std::string expected = ReadBytes(JoinPaths(colmap_bin, name));
    const std::string actual = ReadBytes(JoinPaths(rewritten, name));
    EXPECT_EQ(expected.size(), actual.size()) << name;
    EXPECT_TRUE(expected == actual) << name << " differs";
  }
}

TEST(ModelIO, ColmapModelAnalyzerReadsOurModel) {
  const Reconstruction reconstruction = TestReconstruction();
  size_t num_observations = 0;
  for (const auto& entry : reconstruction.points3D) {
    num_observations += entry.second.track.size();
  }
  const std::string dir = testing::CreateTestDir();
  for (const ModelFormat format : {ModelFormat::kBinary, ModelFormat::kText}) {
    const std::string model_dir =
        JoinPaths(dir, format == ModelFormat::kBinary ? "bin" : "txt");
    WriteReconstruction(model_dir, reconstruction, format);
    const std::string log_path = model_dir + ".log";
    RunColmap("model_analyzer --path " + model_dir, log_path);
    const std::string log = ReadTextFile(log_path);
    const auto value_of = [&](const std::string& key) -> long long {
      std::smatch match;
      const std::regex pattern("(^|\\n)" + key + ": ([0-9]+)");
      if (!std::regex_search(log, match, pattern)) {
        ADD_FAILURE() << "no '" << key << "' in\n" << log;
        return -1;
      }
      return std::stoll(match[2]);
    };
    EXPECT_EQ(value_of("Cameras"), 4);
    EXPECT_EQ(value_of("Images"), 5);
    EXPECT_EQ(value_of("Registered images"), 5);
    EXPECT_EQ(value_of("Points"),
              static_cast<long long>(reconstruction.points3D.size()));
    EXPECT_EQ(value_of("Observations"),
              static_cast<long long>(num_observations));
  }
}

TEST(ModelIO, TruncatedBinaryFilesThrowNamingTheFile) {
  const Reconstruction reconstruction = TestReconstruction(5);
  const std::string dir = testing::CreateTestDir();
  const std::string model_dir = JoinPaths(dir, "model");
  for (const std::string name :
       {"cameras.bin", "images.bin", "points3D.bin", "lines3D.bin"}) {
    WriteReconstruction(model_dir, reconstruction, ModelFormat::kBinary);
    const std::string path = JoinPaths(model_dir, name);
    const std::string bytes = ReadBytes(path);
    // Every proper prefix must be rejected.
    for (size_t size = 0; size < bytes.size(); ++size) {
      WriteBytes(path, bytes.substr(0, size));
      const std::string message =
          ErrorMessage([&] { ReadReconstruction(model_dir); });
      ASSERT_NE(message.find(name), std::string::npos)
          << name << " truncated to " << size << ": '" << message << "'";
    }
    // Trailing garbage too.
    WriteBytes(path, bytes + "x");
    EXPECT_NE(
        ErrorMessage([&] { ReadReconstruction(model_dir); }).find("trailing"),
        std::string::npos);
    WriteBytes(path, bytes);
    EXPECT_NO_THROW(ReadReconstruction(model_dir));
  }
}

TEST(ModelIO, CorruptBinaryValuesThrow) {
  Reconstruction reconstruction = TestReconstruction(3);
  const std::string dir = testing::CreateTestDir();
  WriteReconstruction(dir, reconstruction, ModelFormat::kBinary);
  const std::string cameras_path = JoinPaths(dir, "cameras.bin");
  const std::string cameras = ReadBytes(cameras_path);
  // Unknown model id in the first camera (bytes 12..15).
  std::string corrupt = cameras;
  const int32_t bad_model = 11;
  std::memcpy(&corrupt[12], &bad_model, 4);
  WriteBytes(cameras_path, corrupt);
  std::string message = ErrorMessage([&] { ReadReconstruction(dir); });
  EXPECT_NE(message.find("unknown camera model id 11"), std::string::npos)
      << message;
  EXPECT_NE(message.find("cameras.bin"), std::string::npos) << message;
  // A NaN focal length (first parameter at byte 32).
  corrupt = cameras;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(&corrupt[32], &nan, 8);
  WriteBytes(cameras_path, corrupt);
  message = ErrorMessage([&] { ReadReconstruction(dir); });
  EXPECT_NE(message.find("non-finite"), std::string::npos) << message;
  // An absurd count.
  corrupt = cameras;
  const uint64_t huge = 1ull << 62;
  std::memcpy(&corrupt[0], &huge, 8);
  WriteBytes(cameras_path, corrupt);
  message = ErrorMessage([&] { ReadReconstruction(dir); });
  EXPECT_NE(message.find("num_cameras"), std::string::npos) << message;
}

TEST(ModelIO, CorruptTextThrowsNamingFileAndLine) {
  const std::string dir = testing::CreateTestDir();
  WriteReconstruction(dir, TestReconstruction(3), ModelFormat::kText);
  const std::string cameras_path = JoinPaths(dir, "cameras.txt");
  const std::string cameras = ReadTextFile(cameras_path);
  const struct {
    std::string content;
    std::string expected;
  } cases[] = {
      {"1 PINHOL 640 480 1 2 3 4\n", "unknown camera model 'PINHOL'"},
      {"1 PINHOLE 640 480 1 2 3\n", "expects 4"},
      {"1 PINHOLE 640 480 1 2 3 nan\n", "bad camera parameter 'nan'"},
      {"1 PINHOLE 640 480 1 2 3 4x\n", "bad camera parameter '4x'"},
      {"# comment\n1 PINHOLE -640 480 1 2 3 4\n", "cameras.txt:2: bad width"},
      {"1 PINHOLE 640\n", "expected CAMERA_ID"},
  };
  for (const auto& test_case : cases) {
    WriteBytes(cameras_path, test_case.content);
    const std::string message = ErrorMessage([&] { ReadReconstruction(dir); });
    EXPECT_NE(message.find(test_case.expected), std::string::npos)
        << test_case.content << " -> '" << message << "'";
    EXPECT_NE(message.find(cameras_path), std::string::npos) << message;
  }
  WriteBytes(cameras_path, cameras);
  EXPECT_NO_THROW(ReadReconstruction(dir));

  // images.txt cut after an image line: its POINTS2D line is missing.
  const std::string images_path = JoinPaths(dir, "images.txt");
  const std::string images = ReadTextFile(images_path);
  const size_t last_line = images.rfind('\n', images.size() - 2);
  WriteBytes(images_path, images.substr(0, last_line + 1));
  std::string message = ErrorMessage([&] { ReadReconstruction(dir); });
  EXPECT_NE(message.find("missing the POINTS2D"), std::string::npos) << message;
  // A points line cut in the middle of a triplet.
  WriteBytes(images_path, images.substr(0, images.size() - 4) + "\n");
  message = ErrorMessage([&] { ReadReconstruction(dir); });
  EXPECT_NE(message.find("images.txt"), std::string::npos) << message;
}

TEST(ModelIO, MissingFolderOrModelThrowsNamingTheFolder) {
  const std::string dir = testing::CreateTestDir();
  const std::string missing = JoinPaths(dir, "does_not_exist");
  EXPECT_NE(ErrorMessage([&] { ReadReconstruction(missing); }).find(missing),
            std::string::npos);
  EXPECT_FALSE(ExistsModel(missing));
  // An incomplete set of either format is no model.
  const std::string partial = JoinPaths(dir, "partial");
  WriteReconstruction(partial, TestReconstruction(3), ModelFormat::kBinary);
  std::filesystem::remove(JoinPaths(partial, "points3D.bin"));
  EXPECT_FALSE(ExistsModel(partial));
  const std::string message =
      ErrorMessage([&] { ReadReconstruction(partial); });
  EXPECT_NE(message.find(partial), std::string::npos) << message;
  EXPECT_NE(message.find("No COLMAP model"), std::string::npos) << message;
}

TEST(ModelIO, BinaryWinsOverText) {
  const std::string dir = testing::CreateTestDir();
  Reconstruction text_model = TestReconstruction(3);
  Reconstruction binary_model = TestReconstruction(4);
  binary_model.images[0].name = "from_binary.png";
  WriteReconstruction(dir, text_model, ModelFormat::kText);
  // The per-file writers leave the text files in place.
  WriteCamerasBinary(JoinPaths(dir, "cameras.bin"), binary_model);
  WriteImagesBinary(JoinPaths(dir, "images.bin"), binary_model);
  WritePoints3DBinary(JoinPaths(dir, "points3D.bin"), binary_model);
  ASSERT_TRUE(ExistsFile(JoinPaths(dir, "images.txt")));
  EXPECT_EQ(DetectModelFormat(dir), ModelFormat::kBinary);
  const Reconstruction read = ReadReconstruction(dir);
  EXPECT_EQ(read.images[0].name, "from_binary.png");
  EXPECT_EQ(read.points3D.size(), 4u);
  // lines3D.txt belongs to the text model and is ignored.
  EXPECT_TRUE(read.lines3D.empty());
}

TEST(ModelIO, WriteRemovesStaleFilesOfTheOtherFormat) {
  const std::string dir = testing::CreateTestDir();
  const Reconstruction with_lines = TestReconstruction(3);
  Reconstruction without_lines = with_lines;
  without_lines.lines3D.clear();
  WriteFileAtomically(JoinPaths(dir, "project.ini"),
                      [](std::ostream& stream) { stream << "x\n"; });

  WriteReconstruction(dir, with_lines, ModelFormat::kBinary);
  EXPECT_TRUE(ExistsFile(JoinPaths(dir, "lines3D.bin")));
  WriteReconstruction(dir, without_lines, ModelFormat::kText);
  for (const std::string name : {"cameras.bin", "images.bin", "points3D.bin",
                                 "lines3D.bin", "lines3D.txt"}) {
    EXPECT_FALSE(ExistsFile(JoinPaths(dir, name))) << name;
  }
  EXPECT_EQ(DetectModelFormat(dir), ModelFormat::kText);
  WriteReconstruction(dir, with_lines, ModelFormat::kText);
  EXPECT_TRUE(ExistsFile(JoinPaths(dir, "lines3D.txt")));
  WriteReconstruction(dir, with_lines, ModelFormat::kBinary);
  for (const std::string name :
       {"cameras.txt", "images.txt", "points3D.txt", "lines3D.txt"}) {
    EXPECT_FALSE(ExistsFile(JoinPaths(dir, name))) << name;
  }
  ExpectEqualReconstructions(with_lines, ReadReconstruction(dir));
  EXPECT_TRUE(ExistsFile(JoinPaths(dir, "project.ini")));
  // Only the model files: no temporaries left behind.
  size_t num_files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    (void)entry;
    ++num_files;
  }
  EXPECT_EQ(num_files, 5u);
}

TEST(ModelIO, WriteRefusesInconsistentModels) {
  const std::string dir = testing::CreateTestDir();
  Reconstruction reconstruction = TestReconstruction(3);
  reconstruction.images[0].camera_id = 77;
  EXPECT_NE(ErrorMessage([&] {
              WriteReconstruction(dir, reconstruction, ModelFormat::kBinary);
            }).find("missing camera 77"),
            std::string::npos);
  EXPECT_FALSE(ExistsModel(dir));
}

}  // namespace
}  // namespace colmap_lidar
