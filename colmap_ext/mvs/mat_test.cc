#include "colmap_ext/mvs/mat.h"

#include <cstring>
#include <filesystem>
#include <fstream>

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

void ExpectErrorNaming(const std::function<void()>& function,
                       const std::string& path) {
  try {
    function();
    FAIL() << "no exception for " << path;
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos)
        << error.what();
  }
}

float Value(size_t row, size_t col, size_t ch) {
  return static_cast<float>(100 * ch + 10 * row + col) + 0.5f;
}

TEST(Mat, PlanarLayoutAtByteLevel) {
  MatF mat(2, 2, 3);
  for (size_t row = 0; row < 2; ++row) {
    for (size_t col = 0; col < 2; ++col) {
      for (size_t ch = 0; ch < 3; ++ch) {
        mat.Set(row, col, ch, Value(row, col, ch));
      }
    }
  }
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "map.bin");
  mat.Write(path);
  const std::string content = ReadTextFile(path);
  ASSERT_EQ(content.size(), 6u + 12u * 4u);
  EXPECT_EQ(content.substr(0, 6), "2&2&3&");
  // Element (row, col, ch) is at ch*W*H + row*W + col.
  auto at = [&](size_t index) {
    float value;
    std::memcpy(&value, content.data() + 6 + 4 * index, 4);
    return value;
  };
  EXPECT_EQ(at(0), Value(0, 0, 0));
  EXPECT_EQ(at(1), Value(0, 1, 0));
  EXPECT_EQ(at(2), Value(1, 0, 0));
  EXPECT_EQ(at(3), Value(1, 1, 0));
  EXPECT_EQ(at(4), Value(0, 0, 1));
  EXPECT_EQ(at(7), Value(1, 1, 1));
  EXPECT_EQ(at(8), Value(0, 0, 2));
  EXPECT_EQ(at(10), Value(1, 0, 2));
  EXPECT_EQ(at(11), Value(1, 1, 2));
  // Nothing left behind by the atomic writer.
  size_t num_files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    (void)entry;
    ++num_files;
  }
  EXPECT_EQ(num_files, 1u);
}

TEST(Mat, RoundTripNonSquare) {
  MatF mat(5, 3, 2);
  for (size_t i = 0; i < mat.GetNumValues(); ++i) {
    mat.GetData()[i] = static_cast<float>(i) * 0.25f - 3.0f;
  }
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "map.bin");
  WriteMat(path, mat);
  EXPECT_EQ(ReadTextFile(path).substr(0, 6), "5&3&2&");
  const MatF read = ReadMat<float>(path);
  EXPECT_EQ(read.GetWidth(), 5u);
  EXPECT_EQ(read.GetHeight(), 3u);
  EXPECT_EQ(read.GetDepth(), 2u);
  EXPECT_EQ(read.GetData(), mat.GetData());
  EXPECT_EQ(read.Get(2, 4, 1), mat.GetData()[1 * 15 + 2 * 5 + 4]);

  const MatHeader header = ReadMatHeader(path);
  EXPECT_EQ(header.width, 5u);
  EXPECT_EQ(header.height, 3u);
  EXPECT_EQ(header.depth, 2u);
  EXPECT_EQ(header.data_offset, 6u);

  Mat<int32_t> ints(3, 1, 1);
  ints.Set(0, 2, -7);
  WriteMat(path, ints);
  EXPECT_EQ(ReadMat<int32_t>(path).Get(0, 2), -7);
}

TEST(Mat, LongHeaderNumbers) {
  MatF mat(1000, 2, 1);
  mat.Fill(2.0f);
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "wide.bin");
  mat.Write(path);
  EXPECT_EQ(ReadMatHeader(path).data_offset, 9u);
  EXPECT_EQ(ReadMat<float>(path).Get(1, 999), 2.0f);
}

TEST(Mat, BadFilesThrowNamingTheFile) {
  const std::string dir = testing::CreateTestDir();
  std::string data(4 * 4, '\0');
  const std::vector<std::string> bad_headers = {
      "2&2&",          "2&2&1",  "0&2&1&",  "2&0&1&", "2&2&0&",
      "-2&2&1&",       "a&2&1&", " 2&2&1&", "2x2x1",  "",
      "99999999999&1&1&"};
  for (size_t i = 0; i < bad_headers.size(); ++i) {
    const std::string path = JoinPaths(dir, "bad" + std::to_string(i) + ".bin");
    WriteRaw(path, bad_headers[i] + data);
    ExpectErrorNaming([&] { ReadMat<float>(path); }, path);
  }
  // Short and long bodies: stricter than COLMAP.
  const std::string short_path = JoinPaths(dir, "short.bin");
  WriteRaw(short_path, "2&2&1&" + data.substr(1));
  ExpectErrorNaming([&] { ReadMat<float>(short_path); }, short_path);
  const std::string long_path = JoinPaths(dir, "long.bin");
  WriteRaw(long_path, "2&2&1&" + data + "x");
  ExpectErrorNaming([&] { ReadMat<float>(long_path); }, long_path);
  const std::string good_path = JoinPaths(dir, "good.bin");
  WriteRaw(good_path, "2&2&1&" + data);
  EXPECT_EQ(ReadMat<float>(good_path).Get(1, 1), 0.0f);

  const std::string missing = JoinPaths(dir, "missing.bin");
  ExpectErrorNaming([&] { ReadMat<float>(missing); }, missing);
  const std::string empty_path = JoinPaths(dir, "empty.bin");
  ExpectErrorNaming([&] { MatF().Write(empty_path); }, empty_path);
  EXPECT_FALSE(ExistsFile(empty_path));
  EXPECT_THROW(MatF(0, 1, 1), Error);
}

}  // namespace
}  // namespace colmap_lidar
