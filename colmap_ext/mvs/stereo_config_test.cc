#include "colmap_ext/mvs/stereo_config.h"

#include <fstream>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

void WriteRaw(const std::string& path, const std::string& content) {
  std::ofstream file(path, std::ios::binary);
  file << content;
}

TEST(StereoConfig, PatchMatchRoundTrip) {
  std::vector<PatchMatchEntry> entries(3);
  entries[0].ref_image_name = "cam0/a.png";
  entries[0].num_auto_src_images = 20;
  entries[1].ref_image_name = "b.png";
  entries[1].source_kind = PatchMatchEntry::SourceKind::kAll;
  entries[2].ref_image_name = "c d.png";
  entries[2].source_kind = PatchMatchEntry::SourceKind::kList;
  entries[2].src_image_names = {"cam0/a.png", "b.png"};
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "patch-match.cfg");
  WritePatchMatchConfig(path, entries);
  EXPECT_EQ(ReadTextFile(path),
            "cam0/a.png\n__auto__, 20\nb.png\n__all__\nc d.png\n"
            "cam0/a.png, b.png\n");
  const std::vector<PatchMatchEntry> read = ReadPatchMatchConfig(path);
  ASSERT_EQ(read.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(read[i].ref_image_name, entries[i].ref_image_name);
    EXPECT_EQ(read[i].source_kind, entries[i].source_kind);
  }
  EXPECT_EQ(read[0].num_auto_src_images, 20);
  EXPECT_EQ(read[2].src_image_names, entries[2].src_image_names);
}

TEST(StereoConfig, PatchMatchHandWritten) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "patch-match.cfg");
  WriteRaw(path,
           "# comment\n\n  a.png  \r\n__auto__,5\n# between records\n"
           "b.png\n x.png;y.png , z.png\nlonely.png\n ,\nc.png\n__all__\n");
  const std::vector<PatchMatchEntry> read = ReadPatchMatchConfig(path);
  ASSERT_EQ(read.size(), 3u);  // lonely.png has no sources: dropped.
  EXPECT_EQ(read[0].ref_image_name, "a.png");
  EXPECT_EQ(read[0].num_auto_src_images, 5);
  EXPECT_EQ(read[1].src_image_names,
            (std::vector<std::string>{"x.png", "y.png", "z.png"}));
  EXPECT_EQ(read[2].ref_image_name, "c.png");
  EXPECT_EQ(read[2].source_kind, PatchMatchEntry::SourceKind::kAll);

  const std::vector<std::pair<std::string, std::string>> bad = {
      {"no_sources.cfg", "a.png\n__all__\nb.png\n"},
      {"comment_sources.cfg", "a.png\n# sources\n"},
      {"bad_auto.cfg", "a.png\n__auto__, many\n"},
      {"zero_auto.cfg", "a.png\n__auto__, 0\n"}};
  for (const auto& [name, content] : bad) {
    const std::string bad_path = JoinPaths(dir, name);
    WriteRaw(bad_path, content);
    try {
      ReadPatchMatchConfig(bad_path);
      ADD_FAILURE() << "no exception for " << name;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(bad_path), std::string::npos)
          << error.what();
    }
  }
  EXPECT_THROW(ReadPatchMatchConfig(JoinPaths(dir, "missing.cfg")), Error);
}

TEST(StereoConfig, PatchMatchWriterRejectsUnreadableNames) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "patch-match.cfg");
  PatchMatchEntry entry;
  entry.ref_image_name = "#a.png";
  EXPECT_THROW(WritePatchMatchConfig(path, {entry}), Error);
  entry.ref_image_name = "a.png";
  entry.source_kind = PatchMatchEntry::SourceKind::kList;
  EXPECT_THROW(WritePatchMatchConfig(path, {entry}), Error);
  entry.src_image_names = {"b,c.png"};
  EXPECT_THROW(WritePatchMatchConfig(path, {entry}), Error);
  entry.src_image_names = {"b.png "};
  EXPECT_THROW(WritePatchMatchConfig(path, {entry}), Error);
  EXPECT_FALSE(ExistsFile(path));
}

TEST(StereoConfig, FusionRoundTripHasNoComments) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "fusion.cfg");
  const std::vector<std::string> names = {"cam0/a.png", "#b.png", "c d.png"};
  WriteFusionConfig(path, names);
  EXPECT_EQ(ReadTextFile(path), "cam0/a.png\n#b.png\nc d.png\n");
  EXPECT_EQ(ReadFusionConfig(path), names);
  WriteRaw(path, "\n  a.png \r\n\n b.png\n");
  EXPECT_EQ(ReadFusionConfig(path), (std::vector<std::string>{"a.png", "b.png"}));
  EXPECT_THROW(WriteFusionConfig(path, {"a.png", ""}), Error);
  EXPECT_THROW(WriteFusionConfig(path, {"a\nb.png"}), Error);
  EXPECT_THROW(ReadFusionConfig(JoinPaths(dir, "missing.cfg")), Error);
}

}  // namespace
}  // namespace colmap_lidar
