#include "colmap_ext/mvs/fused_vis.h"

#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

void WriteRaw(const std::string& path, const std::string& content) {
  std::ofstream file(path, std::ios::binary);
  file.write(content.data(), static_cast<std::streamsize>(content.size()));
}

TEST(FusedVis, RoundTripAndBytes) {
  const FusedVisibility visibility = {{2, 0, 1}, {}, {7}};
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "fused.ply.vis");
  WriteFusedVis(path, visibility);
  const std::string content = ReadTextFile(path);
  ASSERT_EQ(content.size(), 8u + (4 + 12) + 4 + (4 + 4));
  uint64_t count;
  std::memcpy(&count, content.data(), 8);
  EXPECT_EQ(count, 3u);
  uint32_t words[7];
  std::memcpy(words, content.data() + 8, sizeof(words));
  EXPECT_EQ(words[0], 3u);
  EXPECT_EQ(words[1], 2u);
  EXPECT_EQ(words[3], 1u);
  EXPECT_EQ(words[4], 0u);  // The empty list.
  EXPECT_EQ(words[5], 1u);
  EXPECT_EQ(words[6], 7u);
  EXPECT_EQ(ReadFusedVis(path), visibility);
  EXPECT_EQ(ReadFusedVis(path, 3), visibility);
  EXPECT_THROW(ReadFusedVis(path, 4), Error);
  CheckFusedVisIndices(visibility, 8, path);
  try {
    CheckFusedVisIndices(visibility, 7, path);
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos);
  }
}

TEST(FusedVis, EmptyAndBrokenFiles) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "empty.vis");
  WriteFusedVis(path, {});
  EXPECT_EQ(ReadTextFile(path), std::string(8, '\0'));
  EXPECT_TRUE(ReadFusedVis(path, 0).empty());

  WriteFusedVis(path, {{1, 2}, {3}});
  const std::string content = ReadTextFile(path);
  for (size_t size : {size_t{0}, size_t{4}, size_t{8}, size_t{15},
                      content.size() - 1}) {
    const std::string cut = JoinPaths(dir, "cut.vis");
    WriteRaw(cut, content.substr(0, size));
    EXPECT_THROW(ReadFusedVis(cut), Error) << size;
  }
  const std::string long_path = JoinPaths(dir, "long.vis");
  WriteRaw(long_path, content + "x");
  EXPECT_THROW(ReadFusedVis(long_path), Error);
  EXPECT_THROW(ReadFusedVis(JoinPaths(dir, "missing.vis")), Error);
}

}  // namespace
}  // namespace colmap_lidar
