#include "colmap_ext/util/testing.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include "colmap_ext/util/file.h"

namespace colmap_lidar {
namespace {

// A child process (forked, so that it can exit normally) makes a test
// folder, writes its path into `record` and exits with exit handlers.
std::string ChildTestDir(const std::string& record, bool keep) {
  const pid_t child = ::fork();
  if (child == 0) {
    if (keep) ::setenv("COLMAP_LIDAR_KEEP_TEST_DIRS", "1", 1);
    const std::string dir = testing::CreateTestDir();
    std::ofstream(record) << dir;
    std::exit(0);  // Runs the exit handlers, unlike _exit.
  }
  int status = 0;
  EXPECT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  return ReadTextFile(record);
}

TEST(CreateTestDir, RemovedWhenTheProcessExitsUnlessKept) {
  // This process's own folder must survive its child's exit handlers.
  const std::string dir = testing::CreateTestDir();
  const std::string removed = ChildTestDir(JoinPaths(dir, "a.txt"), false);
  ASSERT_FALSE(removed.empty());
  EXPECT_FALSE(std::filesystem::exists(removed));
  const std::string kept = ChildTestDir(JoinPaths(dir, "b.txt"), true);
  ASSERT_FALSE(kept.empty());
  EXPECT_TRUE(std::filesystem::exists(kept));
  std::filesystem::remove_all(kept);
  EXPECT_TRUE(std::filesystem::exists(dir));
}

}  // namespace
}  // namespace colmap_lidar
