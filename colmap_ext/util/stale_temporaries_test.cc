#include "colmap_ext/util/stale_temporaries.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {
namespace fs = std::filesystem;

TEST(StaleTemporaries, ParseTemporaryName) {
  long pid = 0;
  EXPECT_TRUE(ParseTemporaryName("dense.tmp-1234-0", &pid));
  EXPECT_EQ(pid, 1234);
  EXPECT_TRUE(ParseTemporaryName("meshed-delaunay.ply.tmp-7-12", &pid));
  EXPECT_EQ(pid, 7);
  EXPECT_TRUE(ParseTemporaryName("dense.old.tmp-99-3", &pid));
  EXPECT_EQ(pid, 99);
  for (const char* name :
       {".tmp-12-0", "dense.tmp-12", "dense.tmp-12-", "dense.tmp--3",
        "dense.tmp-12-0.vis", "dense.tmp-x-0", "fused.tmp-run.ply", "dense",
        "dense.tmp-1234567890123456789012-0"}) {
    EXPECT_FALSE(ParseTemporaryName(name, &pid)) << name;
  }
}

// Temporaries that a process killed while writing leaves behind: made by a
// child that exits without running any destructor.
void LeaveTemporaries(const std::string& dir) {
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    auto* staged = new StagedDirectory(JoinPaths(dir, "dense"));
    std::ofstream(JoinPaths(staged->path(), "depth.bin")) << "partial";
    auto* writer = new AtomicFileWriter(JoinPaths(dir, "sub/mesh.ply"));
    writer->stream() << "partial";
    writer->stream().flush();
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
}

std::vector<std::string> Names(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    names.push_back(fs::relative(entry.path(), dir).string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

TEST(StaleTemporaries, RemovesThoseOfDeadProcessesOnly) {
  const std::string dir = testing::CreateTestDir();
  CreateDirIfNotExists(JoinPaths(dir, "sub"));
  LeaveTemporaries(dir);
  // A temporary of a running process (this one), and user files.
  const std::string live = JoinPaths(
      dir, "sub/other.ply.tmp-" + std::to_string(::getpid()) + "-0");
  std::ofstream(live) << "in progress";
  std::ofstream(JoinPaths(dir, "notes.tmp-draft")) << "mine";
  ASSERT_EQ(Names(dir).size(), 6u);  // dense.tmp-*/, its file, 2 + 2 files.

  EXPECT_TRUE(RemoveStaleTemporaries(dir, /*recursive=*/false, "other.")
                  .empty());
  // Not recursive: only the folder beside `sub`.
  const std::vector<std::string> top =
      RemoveStaleTemporaries(dir, /*recursive=*/false);
  ASSERT_EQ(top.size(), 1u);
  EXPECT_NE(top[0].find("dense.tmp-"), std::string::npos);
  const std::vector<std::string> all =
      RemoveStaleTemporaries(dir, /*recursive=*/true);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_NE(all[0].find("sub/mesh.ply.tmp-"), std::string::npos);
  EXPECT_EQ(Names(dir),
            std::vector<std::string>(
                {"notes.tmp-draft", "sub", "sub/" + fs::path(live).filename().string()}));
  EXPECT_TRUE(RemoveStaleTemporaries(JoinPaths(dir, "missing"), true).empty());
}

// A new StagedDirectory clears what a killed one of the same name left, and
// nothing else.
TEST(StaleTemporaries, StagedDirectoryClearsItsOwn) {
  const std::string dir = testing::CreateTestDir();
  CreateDirIfNotExists(JoinPaths(dir, "sub"));
  LeaveTemporaries(dir);
  {
    StagedDirectory unrelated(JoinPaths(dir, "eval"));
    const std::vector<std::string> names = Names(dir);
    EXPECT_EQ(std::count_if(names.begin(), names.end(),
                            [](const std::string& name) {
                              return name.find("dense.tmp-") == 0;
                            }),
              2);
  }
  StagedDirectory staged(JoinPaths(dir, "dense"));
  std::ofstream(JoinPaths(staged.path(), "depth.bin")) << "complete";
  staged.Commit();
  EXPECT_EQ(Names(dir), std::vector<std::string>(
                            {"dense", "dense/depth.bin", "sub",
                             "sub/" + Names(JoinPaths(dir, "sub"))[0]}));
  EXPECT_EQ(ReadTextFile(JoinPaths(dir, "dense/depth.bin")), "complete");
}

}  // namespace
}  // namespace colmap_lidar
