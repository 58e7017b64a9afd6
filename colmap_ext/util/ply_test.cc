#include "colmap_ext/util/ply.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

void WriteRaw(const std::string& path, const std::string& content) {
  std::ofstream file(path, std::ios::binary);
  file.write(content.data(), static_cast<std::streamsize>(content.size()));
  ASSERT_TRUE(file.good());
}

template <typename T>
void AppendBigEndian(T value, std::string* buffer) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  for (int i = static_cast<int>(sizeof(T)) - 1; i >= 0; --i) {
    buffer->push_back(bytes[i]);
  }
}

template <typename T>
void AppendLittleEndian(T value, std::string* buffer) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  buffer->append(bytes, sizeof(T));
}

// Expects `function` to throw colmap_lidar::Error whose message contains
// every one of `fragments`.
template <typename Function>
void ExpectErrorContaining(const Function& function,
                           const std::vector<std::string>& fragments) {
  try {
    function();
    FAIL() << "no exception; expected one containing " << fragments[0];
  } catch (const Error& error) {
    for (const std::string& fragment : fragments) {
      EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos)
          << "message '" << error.what() << "' lacks '" << fragment << "'";
    }
  }
}

// One column per scalar type, with each type's extreme values.
PlyData MakeAllTypesData() {
  PlyData data;
  data.AddColumn("x", PlyScalarType::kFloat32, {0.1f, -2.5f, 1e-7f, 3e8f});
  data.AddColumn("y", PlyScalarType::kFloat64,
                 {0.1, -1.0 / 3.0, 1e-300, std::numeric_limits<double>::max()});
  data.AddColumn("z", PlyScalarType::kFloat32, {1, 2, 3, 4});
  data.AddColumn("a_i8", PlyScalarType::kInt8, {-128, 127, 0, -1});
  data.AddColumn("a_u8", PlyScalarType::kUInt8, {0, 255, 7, 128});
  data.AddColumn("a_i16", PlyScalarType::kInt16, {-32768, 32767, 5, -300});
  data.AddColumn("a_u16", PlyScalarType::kUInt16, {0, 65535, 1000, 1});
  data.AddColumn("a_i32", PlyScalarType::kInt32,
                 {-2147483648.0, 2147483647.0, -7, 70000});
  data.AddColumn("a_u32", PlyScalarType::kUInt32,
                 {0, 4294967295.0, 123456789, 1});
  data.faces = {{0, 1, 2}, {0, 2, 3, 1}, {3, 2, 1}};
  return data;
}

void ExpectSameData(const PlyData& expected, const PlyData& actual) {
  ASSERT_EQ(expected.vertex_columns.size(), actual.vertex_columns.size());
  for (size_t c = 0; c < expected.vertex_columns.size(); ++c) {
    const PlyColumn& e = expected.vertex_columns[c];
    const PlyColumn& a = actual.vertex_columns[c];
    EXPECT_EQ(e.name, a.name);
    EXPECT_EQ(e.type, a.type) << e.name;
    ASSERT_EQ(e.values.size(), a.values.size()) << e.name;
    for (size_t i = 0; i < e.values.size(); ++i) {
      const double expected_value =
          e.type == PlyScalarType::kFloat32
              ? static_cast<double>(static_cast<float>(e.values[i]))
              : e.values[i];
      EXPECT_EQ(expected_value, a.values[i]) << e.name << "[" << i << "]";
    }
  }
  EXPECT_EQ(expected.faces, actual.faces);
}

TEST(Ply, BinaryRoundTripAllTypesAndFaces) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "all.ply");
  const PlyData data = MakeAllTypesData();
  WritePly(path, data, PlyFormat::kBinaryLittleEndian);
  const std::string content = ReadTextFile(path);
  EXPECT_NE(content.find("format binary_little_endian 1.0\n"),
            std::string::npos);
  EXPECT_NE(content.find("property list uchar int vertex_indices\n"),
            std::string::npos);
  // Record size: 4+8+4+1+1+2+2+4+4 = 30 bytes per vertex; faces 1+4n.
  const size_t header_size = content.find("end_header\n") + 11;
  EXPECT_EQ(content.size(), header_size + 4 * 30 + (1 + 12) + (1 + 16) +
                                (1 + 12));
  ExpectSameData(data, ReadPly(path));
  EXPECT_EQ(ReadPly(path).NumVertices(), 4u);
}

TEST(Ply, AsciiRoundTripAllTypesAndFaces) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "all_ascii.ply");
  const PlyData data = MakeAllTypesData();
  WritePly(path, data, PlyFormat::kAscii);
  const std::string content = ReadTextFile(path);
  EXPECT_NE(content.find("format ascii 1.0\n"), std::string::npos);
  EXPECT_NE(content.find("\n4 0 2 3 1\n"), std::string::npos);
  ExpectSameData(data, ReadPly(path));
}

TEST(Ply, RandomColumnsRoundTrip) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1e3, 1e3);
  PlyData data;
  std::vector<double> a(500), b(500), c(500);
  for (size_t i = 0; i < a.size(); ++i) {
    a[i] = uniform(rng);
    b[i] = uniform(rng);
    c[i] = std::floor(uniform(rng));
  }
  data.AddColumn("intensity", PlyScalarType::kFloat32, a);
  data.AddColumn("range", PlyScalarType::kFloat64, b);
  data.AddColumn("ring", PlyScalarType::kInt16, c);
  EXPECT_THROW(data.AddColumn("short", PlyScalarType::kFloat32, {1.0}), Error);
  EXPECT_THROW(data.AddColumn("ring", PlyScalarType::kFloat32, a), Error);
  const std::string dir = testing::CreateTestDir();
  for (const PlyFormat format :
       {PlyFormat::kAscii, PlyFormat::kBinaryLittleEndian}) {
    const std::string path = JoinPaths(dir, "random.ply");
    WritePly(path, data, format);
    const PlyData read = ReadPly(path);
    ExpectSameData(data, read);
    EXPECT_TRUE(read.faces.empty());
    // No x/y/z columns: Positions() names the file.
    ExpectErrorContaining([&] { read.Positions(path); }, {path});
  }
}

TEST(Ply, WriteRejectsValuesOutsideTheType) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "bad.ply");
  PlyData data;
  data.AddColumn("red", PlyScalarType::kUInt8, {256});
  ExpectErrorContaining([&] { WritePly(path, data); }, {path, "red"});
  EXPECT_FALSE(ExistsFile(path));
  PlyData faces;
  faces.AddColumn("x", PlyScalarType::kFloat32, {0, 1});
  faces.faces = {{0, 1, 2}};
  ExpectErrorContaining([&] { WritePly(path, faces); }, {path});
}

std::string ReadAll(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(file), {});
}

// Bodies past the writer's 1 MiB buffer: the streamed writer and WritePly
// give the same bytes, and they read back.
TEST(Ply, StreamedVerticesAreWritePlysBytes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-50.0, 50.0);
  const size_t num_vertices = 70000;  // 70000 x 21 bytes: 1.47 MB.
  std::vector<double> x(num_vertices), y(num_vertices), red(num_vertices),
      distance(num_vertices);
  for (size_t i = 0; i < num_vertices; ++i) {
    x[i] = uniform(rng);
    y[i] = uniform(rng);
    red[i] = static_cast<double>(i % 256);
    distance[i] = std::abs(uniform(rng));
  }
  PlyData data;
  data.AddColumn("x", PlyScalarType::kFloat64, x);
  data.AddColumn("y", PlyScalarType::kFloat32, y);
  data.AddColumn("red", PlyScalarType::kUInt8, red);
  data.AddColumn("distance", PlyScalarType::kFloat64, distance);
  const std::string dir = testing::CreateTestDir();
  const std::string whole_path = JoinPaths(dir, "whole.ply");
  const std::string streamed_path = JoinPaths(dir, "streamed.ply");
  WritePly(whole_path, data);
  WritePlyVertices(streamed_path,
                   {{"x", PlyScalarType::kFloat64},
                    {"y", PlyScalarType::kFloat32},
                    {"red", PlyScalarType::kUInt8},
                    {"distance", PlyScalarType::kFloat64}},
                   num_vertices, [&](size_t i, double* values) {
                     values[0] = x[i];
                     values[1] = y[i];
                     values[2] = red[i];
                     values[3] = distance[i];
                   });
  const std::string whole = ReadAll(whole_path);
  EXPECT_GT(whole.size(), size_t{1} << 20);
  EXPECT_EQ(ReadAll(streamed_path), whole);
  ExpectSameData(data, ReadPly(streamed_path));

  // A value outside its type names the file and the property; no file.
  const std::string bad_path = JoinPaths(dir, "bad.ply");
  ExpectErrorContaining(
      [&] {
        WritePlyVertices(bad_path, {{"red", PlyScalarType::kUInt8}},
                         num_vertices, [&](size_t i, double* values) {
                           values[0] = i == num_vertices - 1 ? 300.0 : 1.0;
                         });
      },
      {bad_path, "red"});
  EXPECT_FALSE(ExistsFile(bad_path));
  ExpectErrorContaining(
      [&] {
        WritePlyVertices(bad_path, {}, 1, [](size_t, double*) {});
      },
      {bad_path});
}

TEST(Ply, HandWrittenBigEndianWithCommentsAndListCounts) {
  // Header uses the sized type names, comment and obj_info lines, an extra
  // per-vertex list (skipped), faces as "vertex_index" with uint8 count and
  // uint32 items plus a face colour, and a trailing element with a list.
  std::string content =
      "ply\n"
      "format binary_big_endian 1.0\n"
      "comment written by hand\n"
      "obj_info test object\n"
      "element vertex 3\n"
      "property float32 x\n"
      "property float32 y\n"
      "property float32 z\n"
      "property list uint8 int16 tags\n"
      "property int16 s\n"
      "property float64 d\n"
      "property uint8 red\n"
      "element face 2\n"
      "property uint8 flags\n"
      "property list uint8 uint32 vertex_index\n"
      "element material 2\n"
      "property list uint16 float32 values\n"
      "property uchar id\n"
      "end_header\n";
  const float xyz[3][3] = {{1.5f, -2.0f, 3.25f}, {0, 0, 0}, {-7, 8, 1e-3f}};
  const int16_t s[3] = {-300, 1, 32000};
  const double d[3] = {0.1, -1e20, 2.5};
  const uint8_t red[3] = {0, 128, 255};
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      AppendBigEndian(xyz[i][k], &content);
    }
    AppendBigEndian(static_cast<uint8_t>(i), &content);  // i tags
    for (int t = 0; t < i; ++t) {
      AppendBigEndian(static_cast<int16_t>(1000 + t), &content);
    }
    AppendBigEndian(s[i], &content);
    AppendBigEndian(d[i], &content);
    AppendBigEndian(red[i], &content);
  }
  AppendBigEndian(static_cast<uint8_t>(9), &content);
  AppendBigEndian(static_cast<uint8_t>(3), &content);
  for (const uint32_t index : {0u, 1u, 2u}) {
    AppendBigEndian(index, &content);
  }
  AppendBigEndian(static_cast<uint8_t>(1), &content);
  AppendBigEndian(static_cast<uint8_t>(4), &content);
  for (const uint32_t index : {2u, 1u, 0u, 1u}) {
    AppendBigEndian(index, &content);
  }
  for (int m = 0; m < 2; ++m) {
    AppendBigEndian(static_cast<uint16_t>(m + 2), &content);
    for (int v = 0; v < m + 2; ++v) {
      AppendBigEndian(static_cast<float>(v), &content);
    }
    AppendBigEndian(static_cast<uint8_t>(m), &content);
  }

  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "big.ply");
  WriteRaw(path, content);
  const PlyData data = ReadPly(path);
  ASSERT_EQ(data.NumVertices(), 3u);
  ASSERT_EQ(data.vertex_columns.size(), 6u);  // The list is not a column.
  EXPECT_EQ(data.vertex_columns[3].name, "s");
  EXPECT_EQ(data.vertex_columns[3].type, PlyScalarType::kInt16);
  EXPECT_EQ(data.vertex_columns[4].type, PlyScalarType::kFloat64);
  EXPECT_EQ(data.vertex_columns[5].type, PlyScalarType::kUInt8);
  const std::vector<Eigen::Vector3d> positions = data.Positions(path);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(positions[i], Eigen::Vector3f(xyz[i][0], xyz[i][1], xyz[i][2])
                                .cast<double>());
    EXPECT_EQ(data.FindColumn("s")->values[i], s[i]);
    EXPECT_EQ(data.FindColumn("d")->values[i], d[i]);
    EXPECT_EQ(data.FindColumn("red")->values[i], red[i]);
  }
  const std::vector<std::vector<uint32_t>> faces = {{0, 1, 2}, {2, 1, 0, 1}};
  EXPECT_EQ(data.faces, faces);

  // One byte short of the last element: truncated.
  const std::string truncated_path = JoinPaths(dir, "big_truncated.ply");
  WriteRaw(truncated_path, content.substr(0, content.size() - 1));
  ExpectErrorContaining([&] { ReadPly(truncated_path); },
                        {"Truncated", truncated_path});
}

TEST(Ply, AsciiExtraElementWithListBeforeVertices) {
  const std::string content =
      "ply\r\n"
      "format ascii 1.0\r\n"
      "comment CRLF line ends, an element before the vertices\r\n"
      "element camera 2\r\n"
      "property list int int ids\r\n"
      "property double f\r\n"
      "element vertex 2\r\n"
      "property double x\r\n"
      "property double y\r\n"
      "property double z\r\n"
      "property uchar red\r\n"
      "property uchar green\r\n"
      "property uchar blue\r\n"
      "element face 1\r\n"
      "property list uchar int vertex_indices\r\n"
      "end_header\r\n"
      "3 1 2 3 500.5\r\n"
      "0 1e3\r\n"
      "0.5 -1 2 10 20 30\r\n"
      "1 2 3 40 50 60\r\n"
      "3 0 1 0\r\n";
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "ascii.ply");
  WriteRaw(path, content);
  const std::vector<PlyPoint> points = ReadPlyPoints(path);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].xyz, Eigen::Vector3f(0.5f, -1, 2));
  EXPECT_EQ(points[1].xyz, Eigen::Vector3f(1, 2, 3));
  EXPECT_EQ(points[1].rgb, (std::array<uint8_t, 3>{40, 50, 60}));
  EXPECT_EQ(points[0].normal, Eigen::Vector3f::Zero());
  const PlyData data = ReadPly(path);
  ASSERT_EQ(data.faces.size(), 1u);
  EXPECT_EQ(data.faces[0], (std::vector<uint32_t>{0, 1, 0}));

  // The same file missing its last value.
  const std::string truncated_path = JoinPaths(dir, "ascii_truncated.ply");
  WriteRaw(truncated_path, content.substr(0, content.size() - 3));
  ExpectErrorContaining([&] { ReadPly(truncated_path); },
                        {"Truncated", truncated_path});
  // A face index beyond the vertices.
  std::string bad_face = content;
  bad_face.replace(bad_face.size() - 9, 9, "3 0 1 2\r\n");
  const std::string bad_face_path = JoinPaths(dir, "ascii_bad_face.ply");
  WriteRaw(bad_face_path, bad_face);
  ExpectErrorContaining([&] { ReadPly(bad_face_path); }, {bad_face_path});
}

TEST(Ply, BinaryExtraElementWithListIsSkipped) {
  std::string content =
      "ply\nformat binary_little_endian 1.0\n"
      "element vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "element tristrips 1\nproperty list int int vertex_indices\n"
      "element face 1\nproperty list ushort ushort vertex_indices\n"
      "end_header\n";
  for (int i = 0; i < 6; ++i) {
    AppendLittleEndian(static_cast<float>(i), &content);
  }
  AppendLittleEndian(static_cast<int32_t>(5), &content);
  for (int i = 0; i < 5; ++i) {
    AppendLittleEndian(static_cast<int32_t>(i % 2), &content);
  }
  AppendLittleEndian(static_cast<uint16_t>(3), &content);
  for (const uint16_t index : {1, 0, 1}) {
    AppendLittleEndian(index, &content);
  }
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "strips.ply");
  WriteRaw(path, content);
  const PlyData data = ReadPly(path);
  EXPECT_EQ(data.NumVertices(), 2u);
  EXPECT_EQ(data.Positions()[1], Eigen::Vector3d(3, 4, 5));
  ASSERT_EQ(data.faces.size(), 1u);
  EXPECT_EQ(data.faces[0], (std::vector<uint32_t>{1, 0, 1}));
}

TEST(Ply, ErrorsNameTheFile) {
  const std::string dir = testing::CreateTestDir();
  const std::string missing = JoinPaths(dir, "missing.ply");
  ExpectErrorContaining([&] { ReadPly(missing); }, {missing});

  const std::string bad_magic = JoinPaths(dir, "magic.ply");
  WriteRaw(bad_magic, "plx\nformat ascii 1.0\nend_header\n");
  ExpectErrorContaining([&] { ReadPly(bad_magic); }, {"magic", bad_magic});

  const std::string no_end = JoinPaths(dir, "no_end.ply");
  WriteRaw(no_end, "ply\nformat ascii 1.0\nelement vertex 1\n");
  ExpectErrorContaining([&] { ReadPly(no_end); }, {"header", no_end});

  const std::string bad_keyword = JoinPaths(dir, "keyword.ply");
  WriteRaw(bad_keyword,
           "ply\nformat ascii 1.0\nelemnt vertex 1\nend_header\n1\n");
  ExpectErrorContaining([&] { ReadPly(bad_keyword); }, {"header", bad_keyword});

  const std::string bad_count = JoinPaths(dir, "count.ply");
  WriteRaw(bad_count,
           "ply\nformat ascii 1.0\nelement vertex -1\nend_header\n1\n");
  ExpectErrorContaining([&] { ReadPly(bad_count); }, {"header", bad_count});

  const std::string bad_format = JoinPaths(dir, "format.ply");
  WriteRaw(bad_format, "ply\nformat binary_middle_endian 1.0\nend_header\n");
  ExpectErrorContaining([&] { ReadPly(bad_format); }, {"format", bad_format});

  const std::string unsupported = JoinPaths(dir, "int64.ply");
  WriteRaw(unsupported,
           "ply\nformat ascii 1.0\nelement vertex 1\nproperty int64 x\n"
           "end_header\n1\n");
  ExpectErrorContaining([&] { ReadPly(unsupported); },
                        {"Unsupported", "int64", unsupported});

  const std::string bad_value = JoinPaths(dir, "value.ply");
  WriteRaw(bad_value,
           "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
           "end_header\n1.5abc\n");
  ExpectErrorContaining([&] { ReadPly(bad_value); }, {bad_value});

  // A huge declared count must fail cleanly, not allocate.
  const std::string huge = JoinPaths(dir, "huge.ply");
  WriteRaw(huge,
           "ply\nformat binary_little_endian 1.0\nelement vertex "
           "9000000000000000000\nproperty float x\nend_header\nabcd");
  ExpectErrorContaining([&] { ReadPly(huge); }, {"Truncated", huge});
}

std::vector<PlyPoint> MakeSpherePoints(int count) {
  std::mt19937 rng(3);
  std::normal_distribution<float> normal(0, 1);
  std::vector<PlyPoint> points(count);
  for (PlyPoint& point : points) {
    const Eigen::Vector3f direction =
        Eigen::Vector3f(normal(rng), normal(rng), normal(rng)).normalized();
    point.xyz = direction;
    point.normal = direction;
    point.rgb = {static_cast<uint8_t>(rng() % 256),
                 static_cast<uint8_t>(rng() % 256),
                 static_cast<uint8_t>(rng() % 256)};
  }
  return points;
}

TEST(Ply, ColmapPlyPointsLayoutAndRoundTrip) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "fused.ply");
  const std::vector<PlyPoint> points = MakeSpherePoints(10);
  WriteColmapPlyPoints(path, points);
  const std::string content = ReadTextFile(path);
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 10\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "end_header\n";
  ASSERT_EQ(content.size(), header.size() + 10 * 27);
  EXPECT_EQ(content.substr(0, header.size()), header);
  // The second record at a known offset: 6 floats then 3 bytes.
  const char* record = content.data() + header.size() + 27;
  float values[6];
  std::memcpy(values, record, sizeof(values));
  EXPECT_EQ(values[0], points[1].xyz.x());
  EXPECT_EQ(values[5], points[1].normal.z());
  EXPECT_EQ(static_cast<uint8_t>(record[24]), points[1].rgb[0]);
  EXPECT_EQ(static_cast<uint8_t>(record[26]), points[1].rgb[2]);

  const std::vector<PlyPoint> read = ReadPlyPoints(path);
  ASSERT_EQ(read.size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(read[i].xyz, points[i].xyz);
    EXPECT_EQ(read[i].normal, points[i].normal);
    EXPECT_EQ(read[i].rgb, points[i].rgb);
  }
  // Rewriting what was read gives the same bytes.
  const std::string rewritten = JoinPaths(dir, "rewritten.ply");
  WriteColmapPlyPoints(rewritten, read);
  EXPECT_EQ(ReadTextFile(rewritten), content);

  // Past the writer's 1 MiB buffer (50000 x 27 bytes): every record lands.
  const std::vector<PlyPoint> many = MakeSpherePoints(50000);
  const std::string many_path = JoinPaths(dir, "many.ply");
  WriteColmapPlyPoints(many_path, many);
  const std::vector<PlyPoint> many_read = ReadPlyPoints(many_path);
  ASSERT_EQ(many_read.size(), many.size());
  EXPECT_EQ(many_read.back().xyz, many.back().xyz);
  EXPECT_EQ(many_read[30000].normal, many[30000].normal);

  // An empty cloud is a valid file (COLMAP writes those too).
  const std::string empty = JoinPaths(dir, "empty.ply");
  WriteColmapPlyPoints(empty, {});
  EXPECT_TRUE(ReadPlyPoints(empty).empty());
}

// Stock colmap reads our fused.ply and we read its binary mesh (faces as
// "list uchar int vertex_indices").
TEST(Ply, PoissonMesherReadsColmapPlyPoints) {
  const std::string dir = testing::CreateTestDir();
  const std::string points_path = JoinPaths(dir, "fused.ply");
  const std::string mesh_path = JoinPaths(dir, "meshed-poisson.ply");
  WriteColmapPlyPoints(points_path, MakeSpherePoints(5000));
  const int code = testing::RunCommand(
      "colmap poisson_mesher --input_path " + points_path +
          " --output_path " + mesh_path +
          " --PoissonMeshing.depth 6 --PoissonMeshing.trim 0"
          " --PoissonMeshing.num_threads 1",
      JoinPaths(dir, "poisson.log"));
  ASSERT_EQ(code, 0) << ReadTextFile(JoinPaths(dir, "poisson.log"));
  const PlyData mesh = ReadPly(mesh_path);
  ASSERT_GT(mesh.NumVertices(), 500u);
  ASSERT_GT(mesh.faces.size(), 1000u);
  for (const std::vector<uint32_t>& face : mesh.faces) {
    ASSERT_EQ(face.size(), 3u);
  }
  double max_error = 0;
  for (const Eigen::Vector3d& vertex : mesh.Positions(mesh_path)) {
    max_error = std::max(max_error, std::abs(vertex.norm() - 1.0));
  }
  EXPECT_LT(max_error, 0.05);
  // Our binary writer reproduces the mesh exactly.
  const std::string copy_path = JoinPaths(dir, "copy.ply");
  WritePly(copy_path, mesh);
  ExpectSameData(mesh, ReadPly(copy_path));
}

}  // namespace
}  // namespace colmap_lidar
