#include "colmap_ext/runner/colmap_runner.h"

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "colmap_ext/util/file.h"
#include "colmap_ext/util/logging.h"
#include "colmap_ext/util/resource_usage.h"
#include "colmap_ext/util/string.h"

namespace colmap_lidar {
namespace {

bool IsExecutableFile(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode) &&
         ::access(path.c_str(), X_OK) == 0;
}

// Searches PATH like execvp would; empty when not found.
std::string SearchPath(const std::string& name) {
  const char* path_env = std::getenv("PATH");
  const std::string path_list =
      (path_env != nullptr) ? path_env : "/usr/local/bin:/usr/bin:/bin";
  for (const std::string& dir : StringSplit(path_list, ":")) {
    const std::string candidate = JoinPaths(dir.empty() ? "." : dir, name);
    if (IsExecutableFile(candidate)) {
      return std::filesystem::absolute(candidate).string();
    }
  }
  return "";
}

// Quotes an argument for display (error messages and logs only; the
// arguments are never passed through a shell).
std::string QuoteForDisplay(const std::string& arg) {
  if (!arg.empty() &&
      arg.find_first_of(" \t\n'\"\\$`*?;&|<>()") == std::string::npos) {
    return arg;
  }
  std::string quoted = "'";
  for (const char c : arg) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

std::string JoinForDisplay(const std::vector<std::string>& args) {
  std::string line;
  for (const std::string& arg : args) {
    if (!line.empty()) {
      line += ' ';
    }
    line += QuoteForDisplay(arg);
  }
  return line;
}

// Starts `args` with stdin from /dev/null and stdout/stderr into `out_fd`
// and returns the child's pid. Throws when the process cannot be started.
//
// The child is killed with SIGKILL when the calling thread ends
// (PR_SET_PDEATHSIG): a run of ours killed by a signal it cannot catch must
// not leave stock colmap writing into the workspace (database.db, dense/)
// that the resumed run is about to use. So the caller waits for the child in
// the same thread (Wait), as every caller here does. fork + execv instead of
// posix_spawn because the death signal is set in the child; between fork
// and exec the child makes async-signal-safe calls only, and reports a
// failed exec through a close-on-exec pipe.
pid_t Spawn(const std::vector<std::string>& args, int out_fd) {
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const std::string& arg : args) {
    argv.push_back(const_cast<char*>(arg.c_str()));
  }
  argv.push_back(nullptr);

  int error_pipe[2];
  THROW_CHECK(::pipe2(error_pipe, O_CLOEXEC) == 0,
              "pipe failed: " << std::strerror(errno));
  const pid_t parent_pid = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(error_pipe[0]);
    int child_error = 0;
    // getppid() != parent_pid: the parent died before prctl took effect.
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 ||
        ::getppid() != parent_pid) {
      ::_exit(127);
    }
    // Close-on-exec: only its duplicate on stdin reaches colmap.
    const int null_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
    if (null_fd < 0 || ::dup2(null_fd, STDIN_FILENO) < 0 ||
        ::dup2(out_fd, STDOUT_FILENO) < 0 || ::dup2(out_fd, STDERR_FILENO) < 0) {
      child_error = errno;
    } else {
      ::execv(argv[0], argv.data());
      child_error = errno;
    }
    const ssize_t ignored =
        ::write(error_pipe[1], &child_error, sizeof(child_error));
    (void)ignored;
    ::_exit(127);
  }
  const int fork_error = errno;
  ::close(error_pipe[1]);
  if (pid < 0) {
    ::close(error_pipe[0]);
    THROW_ERROR("Cannot start " << JoinForDisplay(args)
                                << ": fork failed: "
                                << std::strerror(fork_error));
  }
  // EOF (0 bytes) when execv succeeded and closed the pipe.
  int child_error = 0;
  ssize_t num_read = 0;
  while ((num_read = ::read(error_pipe[0], &child_error,
                            sizeof(child_error))) == -1 &&
         errno == EINTR) {
  }
  ::close(error_pipe[0]);
  if (num_read == static_cast<ssize_t>(sizeof(child_error))) {
    int status = 0;
    while (::waitpid(pid, &status, 0) == -1 && errno == EINTR) {
    }
    THROW_ERROR("Cannot start " << JoinForDisplay(args) << ": "
                                << std::strerror(child_error));
  }
  return pid;
}

// Waits for `pid` and returns the raw wait status.
int Wait(const pid_t pid, const std::vector<std::string>& args) {
  int status = 0;
  rusage usage{};
  while (::wait4(pid, &status, 0, &usage) == -1) {
    THROW_CHECK(errno == EINTR, "wait4 failed for " << JoinForDisplay(args)
                                                      << ": "
                                                      << std::strerror(errno));
  }
  // ru_maxrss is in KiB on Linux.
  RecordChildPeakMemory(static_cast<size_t>(usage.ru_maxrss) * 1024);
  return status;
}

std::string DescribeStatus(const int status) {
  std::ostringstream text;
  if (WIFEXITED(status)) {
    text << "exit code " << WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    text << "signal " << WTERMSIG(status) << " ("
         << strsignal(WTERMSIG(status)) << ")";
  } else {
    text << "wait status " << status;
  }
  return text.str();
}

// The last `num_lines` lines of `path` from byte `offset` on.
std::string ReadLogTail(const std::string& path, std::streamoff offset,
                        int num_lines) {
  std::ifstream file(path, std::ios::binary);
  if (!file.is_open()) {
    return "";
  }
  file.seekg(offset);
  std::deque<std::string> lines;
  std::string line;
  while (std::getline(file, line)) {
    lines.push_back(line);
    if (static_cast<int>(lines.size()) > num_lines) {
      lines.pop_front();
    }
  }
  std::string tail;
  for (const std::string& kept : lines) {
    tail += "  " + kept + "\n";
  }
  return tail;
}

}  // namespace

bool ColmapRunnerOptions::Check() const {
  if (num_log_tail_lines < 0) {
    LOG(ERROR) << "ColmapRunnerOptions.num_log_tail_lines must be >= 0, got "
               << num_log_tail_lines;
    return false;
  }
  if (!log_path.empty()) {
    const std::filesystem::path parent =
        std::filesystem::absolute(log_path).parent_path();
    if (!ExistsDir(parent.string())) {
      LOG(ERROR) << "ColmapRunnerOptions.log_path: folder " << parent
                 << " does not exist";
      return false;
    }
  }
  return true;
}

ColmapRunner::ColmapRunner(const ColmapRunnerOptions& options)
    : options_(options) {
  THROW_CHECK(options_.Check(), "Invalid ColmapRunnerOptions");
  binary_path_ = FindColmapBinary(options_.colmap_binary);
  if (options_.log_path.empty()) {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "colmap_runner_XXXXXX.log")
            .string();
    const int fd = ::mkstemps(pattern.data(), 4);
    THROW_CHECK(fd >= 0, "Cannot create a temporary log file " << pattern
                                                               << ": "
                                                               << std::strerror(
                                                                      errno));
    ::close(fd);
    log_path_ = pattern;
  } else {
    log_path_ = options_.log_path;
  }
}

std::string ColmapRunner::FindColmapBinary(const std::string& hint) {
  std::string requested = hint;
  std::string source = "--colmap_binary";
  if (requested.empty()) {
    const char* env = std::getenv("COLMAP_BINARY");
    if (env != nullptr && env[0] != '\0') {
      requested = env;
      source = "$COLMAP_BINARY";
    } else {
      requested = "colmap";
      source = "PATH";
    }
  }

  const std::string found = FindExecutable(requested);
  THROW_CHECK(!found.empty(),
              "The stock COLMAP binary was not found (looked for '"
                  << requested << "' from " << source
                  << "). Install Debian's colmap package "
                     "(scripts/install_deps.sh) or pass --colmap_binary "
                     "with the path of a COLMAP 3.8 executable.");
  return found;
}

std::string ColmapRunner::Version() const {
  const std::vector<std::string> args = {binary_path_, "help"};
  int pipe_fds[2];
  THROW_CHECK(::pipe2(pipe_fds, O_CLOEXEC) == 0,
              "pipe failed: " << std::strerror(errno));
  // The child gets the write end through dup2 (which clears O_CLOEXEC on
  // the duplicate); we close our write end right after the spawn so that
  // read() sees EOF when the child exits, and read before waiting so that a
  // full pipe cannot block the child.
  pid_t pid = 0;
  try {
    pid = Spawn(args, pipe_fds[1]);
  } catch (...) {
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
    throw;
  }
  ::close(pipe_fds[1]);
  std::string output;
  char buffer[4096];
  ssize_t num_read = 0;
  while ((num_read = ::read(pipe_fds[0], buffer, sizeof(buffer))) > 0) {
    output.append(buffer, static_cast<size_t>(num_read));
  }
  ::close(pipe_fds[0]);
  const int status = Wait(pid, args);

  THROW_CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0,
              "'" << JoinForDisplay(args) << "' failed with "
                  << DescribeStatus(status) << ":\n"
                  << output);
  const std::string first_line =
      StringTrim(output.substr(0, output.find('\n')));
  const std::vector<std::string> words = StringSplit(first_line, " ");
  THROW_CHECK(words.size() >= 2 && words[0] == "COLMAP",
              "Unexpected output of '" << JoinForDisplay(args)
                                       << "', first line: " << first_line);
  return words[1];
}

void ColmapRunner::Run(
    const std::string& command,
    const std::vector<std::pair<std::string, std::string>>& options) const {
  std::vector<std::string> args = {binary_path_, command};
  for (const auto& [key, value] : options) {
    args.push_back(StringStartsWith(key, "--") ? key : "--" + key);
    args.push_back(value);
  }
  RunLoggedProcess(args, log_path_, options_.num_log_tail_lines,
                   "colmap " + command);
}

std::string FindExecutable(const std::string& name) {
  if (name.find('/') != std::string::npos) {
    return IsExecutableFile(name) ? std::filesystem::absolute(name).string()
                                  : "";
  }
  return SearchPath(name);
}

void RunLoggedProcess(const std::vector<std::string>& args,
                      const std::string& log_path,
                      const int num_log_tail_lines,
                      const std::string& display_name) {
  THROW_CHECK(!args.empty(), "RunLoggedProcess: no command");
  const std::string command_line = JoinForDisplay(args);
  THROW_CHECK(args[0].find('/') != std::string::npos &&
                  IsExecutableFile(args[0]),
              "Cannot run " << command_line << ": " << args[0]
                            << " is not an executable path");

  const int log_fd =
      ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC,
             0644);
  THROW_CHECK(log_fd >= 0, "Cannot open the log file "
                               << log_path << ": " << std::strerror(errno));
  struct stat log_info;
  const std::streamoff run_offset =
      (::fstat(log_fd, &log_info) == 0) ? log_info.st_size : 0;
  const std::string header = "$ " + command_line + "\n";
  const bool header_ok =
      ::write(log_fd, header.data(), header.size()) ==
      static_cast<ssize_t>(header.size());

  if (!header_ok) {
    ::close(log_fd);
    THROW_ERROR("Cannot write the log file " << log_path);
  }

  const auto start = std::chrono::steady_clock::now();
  pid_t pid = 0;
  try {
    pid = Spawn(args, log_fd);
  } catch (...) {
    ::close(log_fd);
    throw;
  }
  ::close(log_fd);
  const int status = Wait(pid, args);
  const double elapsed_s = std::chrono::duration<double>(
                               std::chrono::steady_clock::now() - start)
                               .count();

  const bool success = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  LOG(INFO) << display_name << (success ? "" : " FAILED") << " in "
            << elapsed_s << " s: " << command_line;
  THROW_CHECK(success, display_name << " failed with "
                                    << DescribeStatus(status)
                                    << ".\nCommand: " << command_line
                                    << "\nLog: " << log_path
                                    << "\nLast lines of the log:\n"
                                    << ReadLogTail(log_path, run_offset,
                                                   num_log_tail_lines));
}

}  // namespace colmap_lidar
