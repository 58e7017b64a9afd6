#include "src/lidar/scan_io.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/ply.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

std::string KittiScanPath(const std::string& name = "0000000000") {
  return testing::KittiSampleDir() +
         "/2011_09_26/velodyne_points/data/" + name + ".bin";
}

// Runs `body`, expects colmap_lidar::Error and returns its message.
template <typename Body>
std::string ErrorMessage(Body body) {
  try {
    body();
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "Expected colmap_lidar::Error";
  return "";
}

void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary);
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

void WriteKittiBin(const std::string& path, const std::vector<float>& values) {
  WriteBytes(path, std::string(reinterpret_cast<const char*>(values.data()),
                               values.size() * sizeof(float)));
}

// A scan with non-trivial float values, all channels, no point at origin.
LidarScan MakeScan(size_t num_points, bool intensities, bool rings) {
  LidarScan scan;
  for (size_t i = 0; i < num_points; ++i) {
    const float t = static_cast<float>(i);
    scan.points.emplace_back(1.0f / 3.0f + t, -2.718281f * t - 0.1f,
                             std::sin(t) * 1e-3f + 0.5f);
    if (intensities) {
      scan.intensities.push_back(0.01f * t + 1e-7f);
    }
    if (rings) {
      scan.rings.push_back(static_cast<uint16_t>((i * 7) % 64 + (i == 3) * 60000));
    }
  }
  return scan;
}

void ExpectSameScan(const LidarScan& expected, const LidarScan& actual) {
  ASSERT_EQ(expected.size(), actual.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(expected.points[i], actual.points[i]) << "point " << i;
  }
  EXPECT_EQ(expected.intensities, actual.intensities);
  EXPECT_EQ(expected.rings, actual.rings);
}

TEST(ScanIo, ReadsRealKittiBin) {
  const std::string path = KittiScanPath();
  const size_t file_size = std::filesystem::file_size(path);
  ASSERT_EQ(file_size % 16, 0u);
  EXPECT_EQ(CountLidarScanPoints(path), file_size / 16);

  const LidarScan scan = ReadLidarScan(path);
  // KITTI's scans have no points at the origin, so nothing is dropped.
  EXPECT_EQ(scan.size(), file_size / 16);
  EXPECT_GT(scan.size(), 100000u);
  EXPECT_LT(scan.size(), 140000u);
  ASSERT_EQ(scan.intensities.size(), scan.size());
  EXPECT_FALSE(scan.HasRings());

  // The first record, decoded independently.
  std::ifstream file(path, std::ios::binary);
  float first[4];
  file.read(reinterpret_cast<char*>(first), sizeof(first));
  EXPECT_EQ(scan.points[0], Eigen::Vector3f(first[0], first[1], first[2]));
  EXPECT_EQ(scan.intensities[0], first[3]);

  double max_range = 0;
  double min_z = 1e9;
  size_t num_near_ground_level = 0;
  for (size_t i = 0; i < scan.size(); ++i) {
    ASSERT_TRUE(scan.points[i].allFinite());
    max_range = std::max(max_range, double(scan.points[i].norm()));
    min_z = std::min(min_z, double(scan.points[i].z()));
    num_near_ground_level += std::abs(scan.points[i].z()) < 3.0f;
    ASSERT_GE(scan.intensities[i], 0.0f);
    ASSERT_LE(scan.intensities[i], 1.0f);
  }
  // HDL-64E on a car roof (1.73 m): ground ~ -1.7 m, range <= 120 m, and
  // in a street nearly everything lies within 3 m of the sensor height
  // (a few multipath returns appear far below the ground).
  EXPECT_GT(max_range, 30.0);
  EXPECT_LT(max_range, 130.0);
  EXPECT_LT(min_z, -1.3);
  EXPECT_GT(num_near_ground_level, scan.size() * 95 / 100);
}

TEST(ScanIo, PlyRoundTripBinaryAndAscii) {
  const std::string dir = testing::CreateTestDir();
  for (const bool binary : {true, false}) {
    for (const bool channels : {true, false}) {
      const LidarScan scan = MakeScan(50, channels, channels);
      const std::string path = JoinPaths(
          dir, std::string(binary ? "b" : "a") + (channels ? "c" : "") +
                   ".ply");
      WriteLidarScanPly(path, scan, binary);
      EXPECT_EQ(CountLidarScanPoints(path), 50u);
      ExpectSameScan(scan, ReadLidarScan(path));

      // The declared types are float32 and uint16.
      const std::string header = ReadTextFile(path).substr(0, 300);
      EXPECT_NE(header.find(binary ? "binary_little_endian" : "ascii"),
                std::string::npos);
      EXPECT_NE(header.find("property float x"), std::string::npos)
          << header;
      if (channels) {
        EXPECT_NE(header.find("property float intensity"), std::string::npos)
            << header;
        EXPECT_NE(header.find("property ushort ring"), std::string::npos)
            << header;
      }
    }
  }
}

TEST(ScanIo, PlyAlternativeNamesAndTypes) {
  const std::string dir = testing::CreateTestDir();
  PlyData data;
  data.AddColumn("x", PlyScalarType::kFloat64, {1.25, 2.5, 1e-9});
  data.AddColumn("y", PlyScalarType::kFloat64, {-3.0, 4.0, 5.0});
  data.AddColumn("nx", PlyScalarType::kFloat32, {0, 0, 0});
  data.AddColumn("z", PlyScalarType::kFloat64, {0.5, 0.0, 6.0});
  data.AddColumn("reflectance", PlyScalarType::kUInt8, {10, 20, 255});
  data.AddColumn("ring", PlyScalarType::kInt32, {0, 31, 63});
  const std::string path = JoinPaths(dir, "cloud.PLY");
  WritePly(path, data, PlyFormat::kBinaryLittleEndian);
  const LidarScan scan = ReadLidarScan(path);
  ASSERT_EQ(scan.size(), 3u);
  EXPECT_EQ(scan.points[0], Eigen::Vector3f(1.25f, -3.0f, 0.5f));
  EXPECT_EQ(scan.points[2], Eigen::Vector3f(1e-9f, 5.0f, 6.0f));
  EXPECT_EQ(scan.intensities, (std::vector<float>{10, 20, 255}));
  EXPECT_EQ(scan.rings, (std::vector<uint16_t>{0, 31, 63}));

  // scalar_intensity is accepted too; no ring column gives no rings.
  PlyData other;
  other.AddColumn("x", PlyScalarType::kFloat32, {1});
  other.AddColumn("y", PlyScalarType::kFloat32, {2});
  other.AddColumn("z", PlyScalarType::kFloat32, {3});
  other.AddColumn("scalar_intensity", PlyScalarType::kFloat32, {0.25});
  WritePly(JoinPaths(dir, "other.ply"), other, PlyFormat::kAscii);
  const LidarScan other_scan = ReadLidarScan(JoinPaths(dir, "other.ply"));
  EXPECT_EQ(other_scan.intensities, std::vector<float>{0.25f});
  EXPECT_FALSE(other_scan.HasRings());

  // A negative ring is rejected with the point index.
  PlyData bad_ring = other;
  bad_ring.AddColumn("ring", PlyScalarType::kInt16, {-1});
  WritePly(JoinPaths(dir, "bad_ring.ply"), bad_ring, PlyFormat::kAscii);
  const std::string message =
      ErrorMessage([&] { ReadLidarScan(JoinPaths(dir, "bad_ring.ply")); });
  EXPECT_NE(message.find("point 0"), std::string::npos) << message;
  EXPECT_NE(message.find("bad_ring.ply"), std::string::npos) << message;

  // Missing z.
  PlyData no_z;
  no_z.AddColumn("x", PlyScalarType::kFloat32, {1});
  no_z.AddColumn("y", PlyScalarType::kFloat32, {2});
  WritePly(JoinPaths(dir, "no_z.ply"), no_z, PlyFormat::kAscii);
  EXPECT_NE(ErrorMessage([&] { ReadLidarScan(JoinPaths(dir, "no_z.ply")); })
                .find("no_z.ply"),
            std::string::npos);
}

TEST(ScanIo, ReadsPcdWrittenByPclTypedWriter) {
  const std::string dir = testing::CreateTestDir();
  pcl::PointCloud<pcl::PointXYZI> cloud;
  for (int i = 0; i < 100; ++i) {
    pcl::PointXYZI point;
    point.x = 0.1f * i + 1.0f / 7.0f;
    point.y = -0.3f * i;
    point.z = 1.5f;
    point.intensity = static_cast<float>(i % 17);
    cloud.push_back(point);
  }
  const std::string ascii = JoinPaths(dir, "ascii.pcd");
  const std::string binary = JoinPaths(dir, "binary.pcd");
  const std::string compressed = JoinPaths(dir, "compressed.pcd");
  ASSERT_EQ(pcl::io::savePCDFileASCII(ascii, cloud), 0);
  ASSERT_EQ(pcl::io::savePCDFileBinary(binary, cloud), 0);
  ASSERT_EQ(pcl::io::savePCDFileBinaryCompressed(compressed, cloud), 0);
  for (const std::string& path : {ascii, binary, compressed}) {
    SCOPED_TRACE(path);
    EXPECT_EQ(CountLidarScanPoints(path), 100u);
    const LidarScan scan = ReadLidarScan(path);
    ASSERT_EQ(scan.size(), 100u);
    ASSERT_EQ(scan.intensities.size(), 100u);
    EXPECT_FALSE(scan.HasRings());
    for (int i = 0; i < 100; ++i) {
      // PCL's ASCII writer keeps 8 significant digits.
      EXPECT_NEAR(scan.points[i].x(), cloud[i].x, 1e-6f);
      EXPECT_NEAR(scan.points[i].y(), cloud[i].y, 1e-6f);
      EXPECT_EQ(scan.points[i].z(), 1.5f);
      EXPECT_EQ(scan.intensities[i], cloud[i].intensity);
    }
  }
}

TEST(ScanIo, PcdRoundTripAllFormats) {
  const std::string dir = testing::CreateTestDir();
  const LidarScan scan = MakeScan(200, true, true);
  int index = 0;
  for (const PcdFormat format :
       {PcdFormat::kAscii, PcdFormat::kBinary, PcdFormat::kBinaryCompressed}) {
    const std::string path =
        JoinPaths(dir, "scan" + std::to_string(index++) + ".pcd");
    WriteLidarScanPcd(path, scan, format);
    EXPECT_EQ(CountLidarScanPoints(path), 200u);
    ExpectSameScan(scan, ReadLidarScan(path));
  }
  // Without channels, and the default (binary) format.
  const LidarScan plain = MakeScan(10, false, false);
  WriteLidarScanPcd(JoinPaths(dir, "plain.pcd"), plain);
  EXPECT_NE(ReadTextFile(JoinPaths(dir, "plain.pcd")).find("DATA binary\n"),
            std::string::npos);
  ExpectSameScan(plain, ReadLidarScan(JoinPaths(dir, "plain.pcd")));
  // No temporary left behind.
  int num_files = 0;
  for ([[maybe_unused]] const auto& entry :
       std::filesystem::directory_iterator(dir)) {
    ++num_files;
  }
  EXPECT_EQ(num_files, 4);
}

TEST(ScanIo, DropsNoReturnPointsAtOrigin) {
  const std::string dir = testing::CreateTestDir();
  LidarScan scan = MakeScan(5, true, true);
  scan.points[1].setZero();
  scan.points[4].setZero();
  const std::string path = JoinPaths(dir, "scan.ply");
  WriteLidarScanPly(path, scan);
  EXPECT_EQ(CountLidarScanPoints(path), 5u);
  const LidarScan read = ReadLidarScan(path);
  ASSERT_EQ(read.size(), 3u);
  for (const auto& [read_index, index] :
       std::vector<std::pair<int, int>>{{0, 0}, {1, 2}, {2, 3}}) {
    EXPECT_EQ(read.points[read_index], scan.points[index]);
    EXPECT_EQ(read.intensities[read_index], scan.intensities[index]);
    EXPECT_EQ(read.rings[read_index], scan.rings[index]);
  }

  // Only no-return points: an error.
  WriteKittiBin(JoinPaths(dir, "zeros.bin"), {0, 0, 0, 1, 0, 0, 0, 2});
  const std::string message =
      ErrorMessage([&] { ReadLidarScan(JoinPaths(dir, "zeros.bin")); });
  EXPECT_NE(message.find("zeros.bin"), std::string::npos) << message;
}

TEST(ScanIo, KittiBinErrors) {
  const std::string dir = testing::CreateTestDir();
  // Truncated: the real scan minus 5 bytes.
  const std::string real = ReadTextFile(KittiScanPath());
  const std::string truncated = JoinPaths(dir, "truncated.bin");
  WriteBytes(truncated, real.substr(0, real.size() - 5));
  std::string message = ErrorMessage([&] { ReadLidarScan(truncated); });
  EXPECT_NE(message.find(truncated), std::string::npos) << message;
  EXPECT_NE(message.find("multiple of 16"), std::string::npos) << message;
  message = ErrorMessage([&] { CountLidarScanPoints(truncated); });
  EXPECT_NE(message.find(truncated), std::string::npos) << message;

  const std::string empty = JoinPaths(dir, "empty.bin");
  WriteBytes(empty, "");
  message = ErrorMessage([&] { ReadLidarScan(empty); });
  EXPECT_NE(message.find(empty), std::string::npos) << message;
  EXPECT_NE(message.find("no points"), std::string::npos) << message;

  const std::string nan = JoinPaths(dir, "nan.bin");
  const float kNaN = std::numeric_limits<float>::quiet_NaN();
  WriteKittiBin(nan, {1, 2, 3, 0, 4, 5, 6, 0, 7, kNaN, 8, 0});
  message = ErrorMessage([&] { ReadLidarScan(nan); });
  EXPECT_NE(message.find(nan), std::string::npos) << message;
  EXPECT_NE(message.find("point 2"), std::string::npos) << message;

  const std::string inf = JoinPaths(dir, "inf.bin");
  WriteKittiBin(inf, {std::numeric_limits<float>::infinity(), 2, 3, 0});
  message = ErrorMessage([&] { ReadLidarScan(inf); });
  EXPECT_NE(message.find("point 0"), std::string::npos) << message;
}

TEST(ScanIo, OtherErrorsNameTheFile) {
  const std::string dir = testing::CreateTestDir();
  const std::string missing = JoinPaths(dir, "missing.pcd");
  EXPECT_NE(ErrorMessage([&] { ReadLidarScan(missing); }).find(missing),
            std::string::npos);
  EXPECT_NE(ErrorMessage([&] { CountLidarScanPoints(missing); }).find(missing),
            std::string::npos);

  const std::string unknown = JoinPaths(dir, "scan.xyz");
  WriteBytes(unknown, "1 2 3\n");
  std::string message = ErrorMessage([&] { ReadLidarScan(unknown); });
  EXPECT_NE(message.find(unknown), std::string::npos) << message;
  EXPECT_NE(message.find(".ply, .pcd, .bin"), std::string::npos) << message;
  const std::string no_extension = JoinPaths(dir, "scan");
  EXPECT_NE(ErrorMessage([&] { ReadLidarScan(no_extension); })
                .find(no_extension),
            std::string::npos);

  const std::string garbage_pcd = JoinPaths(dir, "garbage.pcd");
  WriteBytes(garbage_pcd, "this is not a point cloud\n");
  message = ErrorMessage([&] { ReadLidarScan(garbage_pcd); });
  EXPECT_NE(message.find(garbage_pcd), std::string::npos) << message;

  // PCL 1.13 crashes on some of these, so the header is checked first.
  const std::string truncated_pcd = JoinPaths(dir, "truncated.pcd");
  WriteLidarScanPcd(truncated_pcd, MakeScan(20, true, false));
  const std::string pcd_bytes = ReadTextFile(truncated_pcd);
  // PCL pads binary files to whole pages; cut inside the point data.
  const size_t data_start = pcd_bytes.find("DATA binary\n") + 12;
  WriteBytes(truncated_pcd, pcd_bytes.substr(0, data_start + 100));
  message = ErrorMessage([&] { ReadLidarScan(truncated_pcd); });
  EXPECT_NE(message.find(truncated_pcd), std::string::npos) << message;
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;

  // A header that passes our check but makes PCL's parser throw
  // std::out_of_range (found by fuzz_pcd, minimised): an error naming the
  // file, not a crash.
  const std::string bad_header_pcd = JoinPaths(dir, "bad_header.pcd");
  const std::string bad_header =
      "FIELDS x y z y\nSIZE 4 4 4 4\nTYPE F F 1 2\nWIDTH 48\nHEIGHT 1\n"
      "POINTS 48\nDATA ascii\nDATA089\nWIDTH 48\nHEIGHT 1\nVIEP0001\n"
      "0000001\n0000001\n0000001\n0.100000001\n0000001\n00001\n\n"
      "1.720001\n -1.727.100000001\n00000010000001\n0000001\n0.100000001\n"
      "0000001\n0000001\n0000001\n0.100000001\n0000001\n";
  WriteBytes(bad_header_pcd, bad_header);
  message = ErrorMessage([&] { ReadLidarScan(bad_header_pcd); });
  EXPECT_NE(message.find(bad_header_pcd), std::string::npos) << message;

  // Headers that PCL reads differently from our check (it takes keyword
  // lines as they come, even after DATA): each is refused with the reason.
  const std::string valid_fields = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n";
  const std::pair<std::string, std::string> kRefused[] = {
      // Found by fuzz_pcd: PCL resized its buffer after our checks.
      {valid_fields + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n"
                      "\n# comment\nPOINTS 1000\n1 2 3\n",
       "after the DATA line starts with a header keyword (POINTS)"},
      {valid_fields + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary\n"
                      "SIZE 8 8 8\n0123456789ab",
       "after the DATA line starts with a header keyword (SIZE)"},
      {valid_fields + "SIZE 8 8 8\nWIDTH 1\nHEIGHT 1\nPOINTS 1\n"
                      "DATA ascii\n1 2 3\n",
       "SIZE on line 4 repeated or out of order"},
      {"FIELDS x y z\nTYPE F F F\nSIZE 4 4 4\nWIDTH 1\nHEIGHT 1\n"
       "POINTS 1\nDATA ascii\n1 2 3\n",
       "SIZE on line 3 repeated or out of order"},
      {"COLUMNS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\n"
       "POINTS 1\nDATA ascii\n1 2 3\n",
       "COLUMNS line"},
      {"FIELDS x y z\nSIZE 4 4 2\nTYPE F F F\nWIDTH 1\nHEIGHT 1\n"
       "POINTS 1\nDATA ascii\n1 2 3\n",
       "field 'z' has TYPE 'F' with SIZE 2"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F X\nWIDTH 1\nHEIGHT 1\n"
       "POINTS 1\nDATA ascii\n1 2 3\n",
       "field 'z' has TYPE 'X'"},
      {"FIELDS x y\rz\nSIZE 4 4\nTYPE F F\nWIDTH 1\nHEIGHT 1\n"
       "POINTS 1\nDATA ascii\n1 2\n",
       "carriage return inside line 1"},
  };
  for (const auto& [header, reason] : kRefused) {
    const std::string refused_pcd = JoinPaths(dir, "refused.pcd");
    WriteBytes(refused_pcd, header);
    for (const std::string& message :
         {ErrorMessage([&] { ReadLidarScan(refused_pcd); }),
          ErrorMessage([&] { CountLidarScanPoints(refused_pcd); })}) {
      EXPECT_NE(message.find(refused_pcd), std::string::npos) << message;
      EXPECT_NE(message.find(reason), std::string::npos) << message;
    }
  }
  // Every optional line, CRLF line ends and lower-case types stay readable.
  const std::string crlf_pcd = JoinPaths(dir, "crlf.pcd");
  WriteBytes(crlf_pcd,
             "# .PCD v0.7\r\nVERSION 0.7\r\nFIELDS x y z\r\nSIZE 4 4 8\r\n"
             "TYPE F f F\r\nCOUNT 1 1 1\r\nWIDTH 2\r\nHEIGHT 1\r\n"
             "VIEWPOINT 0 0 0 1 0 0 0\r\nPOINTS 2\r\nDATA ascii\r\n"
             "1 2 3\r\n4 5 6\r\n");
  EXPECT_EQ(CountLidarScanPoints(crlf_pcd), 2u);
  const LidarScan crlf = ReadLidarScan(crlf_pcd);
  ASSERT_EQ(crlf.size(), 2u);
  EXPECT_EQ(crlf.points[1], Eigen::Vector3f(4, 5, 6));

  const std::string empty_pcd = JoinPaths(dir, "empty.pcd");
  WriteLidarScanPcd(empty_pcd, LidarScan());
  EXPECT_EQ(CountLidarScanPoints(empty_pcd), 0u);
  message = ErrorMessage([&] { ReadLidarScan(empty_pcd); });
  EXPECT_NE(message.find("no points"), std::string::npos) << message;

  const std::string garbage_ply = JoinPaths(dir, "garbage.ply");
  WriteBytes(garbage_ply, "ply\nformat ascii 1.0\nelement vertex 3\n");
  message = ErrorMessage([&] { ReadLidarScan(garbage_ply); });
  EXPECT_NE(message.find(garbage_ply), std::string::npos) << message;

  // A PLY with zero vertices is an empty scan.
  const std::string empty_ply = JoinPaths(dir, "empty.ply");
  WriteLidarScanPly(empty_ply, LidarScan());
  EXPECT_EQ(CountLidarScanPoints(empty_ply), 0u);
  message = ErrorMessage([&] { ReadLidarScan(empty_ply); });
  EXPECT_NE(message.find(empty_ply), std::string::npos) << message;
  EXPECT_NE(message.find("no points"), std::string::npos) << message;

  // A NaN in a PCD is reported with its index, too.
  LidarScan with_nan = MakeScan(4, false, false);
  with_nan.points[3].y() = std::numeric_limits<float>::quiet_NaN();
  const std::string nan_pcd = JoinPaths(dir, "nan.pcd");
  WriteLidarScanPcd(nan_pcd, with_nan);
  message = ErrorMessage([&] { ReadLidarScan(nan_pcd); });
  EXPECT_NE(message.find("point 3"), std::string::npos) << message;
  EXPECT_NE(message.find(nan_pcd), std::string::npos) << message;
}

TEST(ScanIo, KittiConvertsToPlyLosslessly) {
  const LidarScan scan = ReadLidarScan(KittiScanPath("0000000005"));
  const std::string path = JoinPaths(testing::CreateTestDir(), "kitti.ply");
  WriteLidarScanPly(path, scan);
  ExpectSameScan(scan, ReadLidarScan(path));
  // 3 x float32 + float32 intensity per point after the header.
  EXPECT_GT(std::filesystem::file_size(path), 16 * scan.size());
  EXPECT_LT(std::filesystem::file_size(path), 16 * scan.size() + 300);
}

}  // namespace
}  // namespace colmap_lidar
