#include "colmap_ext/util/file.h"

#include <filesystem>
#include <sstream>

#include <gtest/gtest.h>

#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {
namespace fs = std::filesystem;

size_t CountEntries(const std::string& dir) {
  size_t count = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    (void)entry;
    ++count;
  }
  return count;
}

TEST(File, BinaryRoundTripIsLittleEndian) {
  std::stringstream stream;
  WriteBinary<uint32_t>(stream, 0x01020304u);
  const double values[2] = {1.5, -2.25};
  WriteBinaryArray(stream, values, 2);
  const std::string bytes = stream.str();
  ASSERT_EQ(bytes.size(), 4u + 16u);
  EXPECT_EQ(static_cast<uint8_t>(bytes[0]), 0x04);
  EXPECT_EQ(static_cast<uint8_t>(bytes[3]), 0x01);
  EXPECT_EQ(ReadBinary<uint32_t>(stream), 0x01020304u);
  double read[2];
  ReadBinaryArray(stream, read, 2);
  EXPECT_EQ(read[1], -2.25);
  EXPECT_THROW(ReadBinary<uint8_t>(stream), Error);
}

TEST(File, AtomicWriterCommitsOrLeavesNothing) {
  const std::string dir = testing::CreateTestDir();
  const std::string path = JoinPaths(dir, "a.txt");
  WriteFileAtomically(path, [](std::ostream& out) { out << "first"; });
  EXPECT_EQ(ReadTextFile(path), "first");
  try {
    WriteFileAtomically(path, [](std::ostream& out) {
      out << "second";
      throw Error("interrupted");
    });
    FAIL();
  } catch (const Error&) {
  }
  EXPECT_EQ(ReadTextFile(path), "first");
  EXPECT_EQ(CountEntries(dir), 1u);
  EXPECT_THROW(AtomicFileWriter(JoinPaths(dir, "missing/x.txt")), Error);
}

TEST(File, StagedDirectoryReplacesOnCommitOnly) {
  const std::string dir = testing::CreateTestDir();
  const std::string target = JoinPaths(dir, "model");
  {
    StagedDirectory staged(target);
    WriteFileAtomically(JoinPaths(staged.path(), "x"), [](std::ostream& o) { o << 1; });
    EXPECT_FALSE(fs::exists(target));
  }
  EXPECT_FALSE(fs::exists(target));
  EXPECT_EQ(CountEntries(dir), 0u);
  {
    StagedDirectory staged(target);
    WriteFileAtomically(JoinPaths(staged.path(), "x"), [](std::ostream& o) { o << 1; });
    staged.Commit();
  }
  EXPECT_EQ(ReadTextFile(JoinPaths(target, "x")), "1");
  {
    StagedDirectory staged(target + "/");
    WriteFileAtomically(JoinPaths(staged.path(), "y"), [](std::ostream& o) { o << 2; });
    staged.Commit();
  }
  EXPECT_FALSE(fs::exists(JoinPaths(target, "x")));
  EXPECT_EQ(ReadTextFile(JoinPaths(target, "y")), "2");
  EXPECT_EQ(CountEntries(dir), 1u);
}

TEST(File, StagedFilesLandTogether) {
  const std::string dir = testing::CreateTestDir();
  const std::string source = JoinPaths(dir, "src.bin");
  WriteFileAtomically(source, [](std::ostream& o) { o << "payload"; });
  {
    StagedFiles staged;
    staged.Copy(source, JoinPaths(dir, "out/a.bin"));
    staged.Copy(source, JoinPaths(dir, "out/b.bin"));
    EXPECT_EQ(staged.NumStaged(), 2u);
    EXPECT_FALSE(ExistsFile(JoinPaths(dir, "out/a.bin")));
  }
  EXPECT_EQ(CountEntries(JoinPaths(dir, "out")), 0u);
  StagedFiles staged;
  staged.Copy(source, JoinPaths(dir, "out/a.bin"));
  staged.Commit();
  EXPECT_TRUE(FilesHaveSameContent(source, JoinPaths(dir, "out/a.bin")));
  EXPECT_FALSE(FilesHaveSameContent(source, JoinPaths(dir, "out/none")));
  EXPECT_TRUE(IsSameFile(source, JoinPaths(dir, "./src.bin")));
  StagedFiles failing;
  EXPECT_THROW(failing.Copy(JoinPaths(dir, "missing"), JoinPaths(dir, "out/c")), Error);
}

TEST(File, ExistenceChecksNameThePath) {
  const std::string dir = testing::CreateTestDir();
  try {
    CheckFileExists(JoinPaths(dir, "nope.yaml"), "Calibration");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nope.yaml"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("Calibration"), std::string::npos);
  }
  EXPECT_NO_THROW(CheckDirExists(dir, "x"));
  EXPECT_THROW(ReadTextFile(JoinPaths(dir, "nope")), Error);
}

}  // namespace
}  // namespace colmap_lidar
