#include "colmap_ext/runner/colmap_runner.h"

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/testing.h"

namespace colmap_lidar {
namespace {

ColmapRunnerOptions OptionsWithLog(const std::string& dir) {
  ColmapRunnerOptions options;
  options.log_path = JoinPaths(dir, "colmap.log");
  return options;
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

bool IsSqliteFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::string magic(16, '\0');
  file.read(magic.data(), magic.size());
  return file.good() && magic == std::string("SQLite format 3\0", 16);
}

TEST(ColmapRunner, OptionsCheck) {
  ColmapRunnerOptions options;
  EXPECT_TRUE(options.Check());
  options.num_log_tail_lines = -1;
  EXPECT_FALSE(options.Check());
  options.num_log_tail_lines = 20;
  options.log_path = "/nonexistent_folder_h3b/colmap.log";
  EXPECT_FALSE(options.Check());
}

TEST(ColmapRunner, FindsStockBinary) {
  const std::string path = ColmapRunner::FindColmapBinary("/usr/bin/colmap");
  EXPECT_EQ(path, "/usr/bin/colmap");
  // A bare name is searched on PATH.
  EXPECT_FALSE(ColmapRunner::FindColmapBinary("colmap").empty());
}

TEST(ColmapRunner, Version) {
  const ColmapRunner runner(OptionsWithLog(testing::CreateTestDir()));
  const std::string version = runner.Version();
  EXPECT_NE(version.find("3.8"), std::string::npos) << version;
}

TEST(ColmapRunner, DatabaseCreatorCreatesFile) {
  const std::string dir = testing::CreateTestDir();
  const ColmapRunner runner(OptionsWithLog(dir));
  const std::string database_path = JoinPaths(dir, "database.db");
  ASSERT_FALSE(ExistsFile(database_path));
  runner.Run("database_creator", {{"database_path", database_path}});
  EXPECT_TRUE(IsSqliteFile(database_path));
  // The log starts with the command line of the run.
  const std::string log = ReadTextFile(runner.log_path());
  EXPECT_NE(log.find("$ /usr/bin/colmap database_creator --database_path " +
                     database_path),
            std::string::npos)
      << log;
}

TEST(ColmapRunner, InvalidOptionThrowsWithLogTail) {
  const std::string dir = testing::CreateTestDir();
  const ColmapRunner runner(OptionsWithLog(dir));
  // A successful run first: its output must not appear in the failure tail.
  runner.Run("database_creator",
             {{"--database_path", JoinPaths(dir, "first.db")}});
  const std::string message = ErrorMessage([&] {
    runner.Run("database_creator", {{"no_such_option", "1"}});
  });
  EXPECT_NE(message.find("exit code 1"), std::string::npos) << message;
  EXPECT_NE(message.find("database_creator --no_such_option 1"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("unrecognised option '--no_such_option'"),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find("first.db"), std::string::npos) << message;
  // Both runs were appended to the same log.
  const std::string log = ReadTextFile(runner.log_path());
  EXPECT_NE(log.find("first.db"), std::string::npos);
  EXPECT_NE(log.find("unrecognised option"), std::string::npos);
}

TEST(ColmapRunner, UnknownCommandThrows) {
  const ColmapRunner runner(OptionsWithLog(testing::CreateTestDir()));
  const std::string message =
      ErrorMessage([&] { runner.Run("no_such_command", {}); });
  EXPECT_NE(message.find("not recognized"), std::string::npos) << message;
}

TEST(ColmapRunner, MissingBinaryThrowsClearMessage) {
  const std::string missing = "/nonexistent_h3b/bin/colmap";
  std::string message =
      ErrorMessage([&] { ColmapRunner::FindColmapBinary(missing); });
  EXPECT_NE(message.find("The stock COLMAP binary was not found"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find(missing), std::string::npos) << message;
  EXPECT_NE(message.find("scripts/install_deps.sh"), std::string::npos);
  EXPECT_NE(message.find("--colmap_binary"), std::string::npos);

  ColmapRunnerOptions options;
  options.colmap_binary = missing;
  message = ErrorMessage([&] { ColmapRunner runner(options); });
  EXPECT_NE(message.find("was not found"), std::string::npos) << message;

  // A file that exists but is not executable is not accepted either.
  const std::string dir = testing::CreateTestDir();
  const std::string not_executable = JoinPaths(dir, "colmap");
  std::ofstream(not_executable) << "#!/bin/sh\n";
  message = ErrorMessage(
      [&] { ColmapRunner::FindColmapBinary(not_executable); });
  EXPECT_NE(message.find("was not found"), std::string::npos) << message;
}

TEST(ColmapRunner, EnvironmentVariable) {
  const char* previous = std::getenv("COLMAP_BINARY");
  const std::string saved = previous != nullptr ? previous : "";

  ::setenv("COLMAP_BINARY", "/nonexistent_h3b/colmap", 1);
  const std::string message =
      ErrorMessage([] { ColmapRunner::FindColmapBinary(""); });
  EXPECT_NE(message.find("$COLMAP_BINARY"), std::string::npos) << message;

  ::setenv("COLMAP_BINARY", "/usr/bin/colmap", 1);
  EXPECT_EQ(ColmapRunner::FindColmapBinary(""), "/usr/bin/colmap");
  // An explicit hint wins over the environment.
  ::setenv("COLMAP_BINARY", "/nonexistent_h3b/colmap", 1);
  EXPECT_EQ(ColmapRunner::FindColmapBinary("/usr/bin/colmap"),
            "/usr/bin/colmap");

  if (previous != nullptr) {
    ::setenv("COLMAP_BINARY", saved.c_str(), 1);
  } else {
    ::unsetenv("COLMAP_BINARY");
  }
}

TEST(ColmapRunner, PathsWithSpacesAndQuotes) {
  const std::string dir = JoinPaths(testing::CreateTestDir(), "a folder 'x'");
  CreateDirIfNotExists(dir);
  ColmapRunnerOptions options;
  options.log_path = JoinPaths(dir, "run log.txt");
  const ColmapRunner runner(options);
  const std::string database_path = JoinPaths(dir, "my database.db");
  runner.Run("database_creator", {{"database_path", database_path}});
  EXPECT_TRUE(IsSqliteFile(database_path));
  EXPECT_TRUE(ExistsFile(options.log_path));
}

TEST(ColmapRunner, DefaultLogIsATempFile) {
  const ColmapRunner runner;
  EXPECT_TRUE(ExistsFile(runner.log_path()));
  const std::string dir = testing::CreateTestDir();
  runner.Run("database_creator",
             {{"database_path", JoinPaths(dir, "database.db")}});
  EXPECT_NE(ReadTextFile(runner.log_path()).find("database_creator"),
            std::string::npos);
  std::remove(runner.log_path().c_str());
}

// "R" (running), "S" (sleeping), "Z" (zombie) ... of /proc/<pid>/stat, or
// "" once the process is gone.
std::string ProcessState(const pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) {
    return "";
  }
  const size_t paren = line.rfind(')');
  return paren == std::string::npos || paren + 2 >= line.size()
             ? ""
             : line.substr(paren + 2, 1);
}

// A run of ours killed with SIGKILL (which it cannot catch) takes the stock
// process it started with it, so that nothing keeps writing into a workspace
// that a resumed run uses.
TEST(ColmapRunner, ChildDiesWithItsParent) {
  const std::string dir = testing::CreateTestDir();
  const std::string pid_path = JoinPaths(dir, "child.pid");
  const pid_t parent = ::fork();
  ASSERT_GE(parent, 0);
  if (parent == 0) {
    // The child writes its pid, then sleeps far longer than the test.
    try {
      RunLoggedProcess({"/bin/sh", "-c",
                        "echo $$ > '" + pid_path + "'.tmp && mv '" + pid_path +
                            "'.tmp '" + pid_path + "' && exec sleep 300"},
                       JoinPaths(dir, "log.txt"), 5, "sleeper");
    } catch (...) {
    }
    ::_exit(0);
  }
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!ExistsFile(pid_path) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(ExistsFile(pid_path));
  const pid_t child = std::stoi(ReadTextFile(pid_path));
  EXPECT_NE(ProcessState(child), "");
  ASSERT_EQ(::kill(parent, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(parent, &status, 0), parent);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  // Gone, or a zombie waiting for init to reap it.
  std::string state = ProcessState(child);
  while (state != "" && state != "Z" &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    state = ProcessState(child);
  }
  EXPECT_TRUE(state == "" || state == "Z") << "state " << state;
  if (state != "" && state != "Z") {
    ::kill(child, SIGKILL);
  }
}

TEST(ColmapRunner, ExecFailureIsReported) {
  const std::string dir = testing::CreateTestDir();
  // An executable file that the kernel cannot run.
  const std::string bad = JoinPaths(dir, "not_a_program");
  {
    std::ofstream file(bad);
    file << "\x7f" << "ELF garbage";
  }
  ASSERT_EQ(::chmod(bad.c_str(), 0755), 0);
  const std::string message = ErrorMessage([&] {
    RunLoggedProcess({bad}, JoinPaths(dir, "log.txt"), 5, "bad");
  });
  EXPECT_NE(message.find("Cannot start"), std::string::npos) << message;
  EXPECT_NE(message.find("not_a_program"), std::string::npos) << message;
}

}  // namespace
}  // namespace colmap_lidar
